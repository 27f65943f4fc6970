#pragma once
// Particle fields projected to the background grid's nodes, for output (issue 41: ParaView's Plot
// Over Line, Probe, Slice and Contour need cells, and the particle frames hold only vertices).
// With the run's own shape functions S_ip (linear, uGIMP or GIMP with each particle's domain) at
// the particles' current positions:
//   m_i = sum_p S_ip m_p,            V_i = sum_p S_ip V_p,
//   m_i q_i = sum_p S_ip m_p q_p,    so q_i = sum_p S_ip m_p q_p / m_i        (P1)
// the mass-weighted projection by which p2g forms the nodal velocity from the momentum (eqs 1-2,
// explicit_step.cpp), applied to each component of each field as the particles hold it (a derived
// scalar such as max_shear_strain is averaged, not formed again from the averaged strain). A node
// beyond the grid's edge takes no weight in the step (shape/stencil.hpp); here its weight goes to
// the edge node instead, so that sum_i S_ip = 1 for every particle and sum_i m_i = sum_p m_p to
// rounding. It is not nothing: a GIMP domain pressed against a held face pokes past it (of order
// 1e-5 m under the 3D column of examples/column_self_weight at rest), and dropping that weight lost
// 5.8e-12 of the mass. (A domain that crosses a free face stops the run, model/free_faces.hpp.)
// Nodes no particle reaches have m_i = 0 and no value.
//
// Computed for an output frame only, never by the step, in one serial pass over the particles in
// storage order: the sums are the same bits on any thread count, and a run without grid output
// pays nothing. The nodes are those of the box of every particle's stencil (clipped to the grid),
// stored lexicographically in it (x fastest): a body far smaller than its grid takes memory for
// its own box only.
#include "tsuchi/model/model.hpp"
#include "tsuchi/model/particle_fields.hpp"

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace tsuchi {

template <int D>
struct GridProjection {
  std::array<int, D> first{};  // grid index of the box's first node, per axis
  std::array<int, D> count{};  // nodes of the box per axis (all 0: no particle)
  std::vector<double> m, V;    // per box node: m_i, V_i of (P1)
  // The fields projected, their components (1, D, or the Voigt entries: particle_fields.hpp) and
  // where each starts among a node's values.
  std::vector<const ParticleField*> fields;
  std::vector<int> components, offset;
  int stride = 0;              // values per node: the sum of the components
  std::vector<double> values;  // per box node, `stride` values: q_i of (P1); 0 where m_i = 0

  std::size_t nodes() const {
    std::size_t n = 1;
    for (int d = 0; d < D; ++d) n *= static_cast<std::size_t>(count[d]);
    return n;
  }
  // Box node b of grid index ijk (inside the box).
  std::size_t at(const std::array<int, D>& ijk) const {
    std::size_t b = 0;
    for (int d = D - 1; d >= 0; --d) b = b * static_cast<std::size_t>(count[d]) + static_cast<std::size_t>(ijk[d] - first[d]);
    return b;
  }
  // Grid index of box node b.
  std::array<int, D> ijk(std::size_t b) const {
    std::array<int, D> r{};
    for (int d = 0; d < D; ++d) {
      r[d] = first[d] + static_cast<int>(b % static_cast<std::size_t>(count[d]));
      b /= static_cast<std::size_t>(count[d]);
    }
    return r;
  }
};

// (P1) for the particle fields named in `fields` (each a projectable field: see
// is_projectable_field), with the kernel of model.step.
template <int D>
GridProjection<D> project_to_grid(const Model<D>& model, const std::vector<std::string>& fields);

// A field (P1) means something for: a Float64 field of the particles that is not where or how big a
// particle is (position, radius, volume, mass, density: the nodal mass and density are written
// anyway) and not an index.
bool is_projectable_field(const ParticleField& f);
// Their names, in the registry's order.
std::vector<std::string> projectable_field_names();

extern template GridProjection<2> project_to_grid<2>(const Model<2>&, const std::vector<std::string>&);
extern template GridProjection<3> project_to_grid<3>(const Model<3>&, const std::vector<std::string>&);

}  // namespace tsuchi
