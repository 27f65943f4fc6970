#pragma once
// A model ready to step: the grid with its boundary conditions, the particles of every body, the
// materials and the step's settings, built from a validated Config. Physics only: the run's time,
// output, checkpoint and recorder settings stay in the Config, for the run loop (run/).
#include "tsuchi/grid/grid.hpp"
#include "tsuchi/material/material.hpp"
#include "tsuchi/model/config.hpp"
#include "tsuchi/model/contact.hpp"
#include "tsuchi/model/loads.hpp"
#include "tsuchi/model/node_sets.hpp"
#include "tsuchi/model/step_settings.hpp"
#include "tsuchi/particles/particles.hpp"
#include "tsuchi/shape/gimp.hpp"
#include "tsuchi/shape/stencil.hpp"

#include <algorithm>
#include <string>
#include <vector>

namespace tsuchi {

// Per body: which velocity components are prescribed, v = f(t) (v0 + grad . x) (a loading platen;
// f = 1 unless bodies.N.prescribed_velocity_function names one; the solver applies f).
template <int D>
struct BodyMotion {
  std::array<bool, D> prescribed{};
  Vec<D> v0 = Vec<D>::Zero();
  Mat<D> grad = Mat<D>::Zero();
  bool any = false;
  TimeFunction function;
  // A free rigid body (bodies.N.rigid_mass): every component is held, and the solver sets v0 of the
  // `free` ones after each step from the body's momentum balance with this mass.
  double rigid_mass = 0.0;
  std::array<bool, D> free{};

  double velocity(int d, const Vec<D>& x) const { return v0[d] + grad.row(d).dot(x); }
  // Every component prescribed: with rigid_mass = 0, a body rigid in contact (a platen or wall).
  bool fully_prescribed() const { return std::all_of(prescribed.begin(), prescribed.end(), [](bool p) { return p; }); }
};

template <int D>
struct Model {
  std::string source;             // the input file, for messages
  std::uint64_t fingerprint = 0;  // Config::fingerprint: a checkpoint restarts only the same physics
  std::vector<Material> materials;
  std::vector<std::string> body_names;
  StepSettings<D> step;
  Grid<D> grid;
  Particles<D> particles;
  std::vector<BodyMotion<D>> motion;        // one per body
  std::vector<std::size_t> body_particles;  // particle count per body
  std::vector<double> body_volume;          // initial volume per body (m^3; m^2 in 2D)
  std::vector<NodeSet<D>> node_sets;        // [[boundary.nodes]], in input order
  std::vector<std::int64_t> held_nodes;     // grid slots with a held component (fixed_g != 0), increasing
  bool rotate_initial_stress = false;       // some body holds an anisotropic sigma0 by eq (2)
  Loads<D> loads;                           // the input's [[loads]] (model/loads.hpp)
  Contact<D> contact;                       // [[contact]] and frictional faces (model/contact.hpp)
  // Staged runs (model/stage_change.hpp): the particles of the bodies a later stage adds, made with
  // the others (so overlaps and ids are settled once) and kept out of the step until then.
  Particles<D> dormant;
  std::int64_t id_count = 0;                // ids 0..id_count-1 are given out, in particles or dormant
  bool staged = false;                      // the particle count may change between stages
  std::size_t stage_count = 0;              // Config::stages.size()

  std::size_t bytes() const {
    return grid.bytes() + (particles.size() + dormant.size()) * particles.bytes_per_particle();
  }
};

// Peak memory of a run in bytes, from its grid slots (Grid::size) and particle count: the model
// (Model::bytes) and the step's stencil factors per particle (Stencil::Axes), plus the block
// schedule and the reordering's marks (a quarter on top covers them: peak RSS measured at 1.02-1.05
// times model and factors for the 1e6-particle blocks, BENCHMARKS.md), plus 32 MB for the program.
// `layout` is the model's particles before any is added: which optional arrays they hold;
// `keep_acceleration` whether the grid holds the nodal acceleration (Grid::keep_acceleration).
template <int D>
double memory_estimate(double grid_slots, double particles, const Particles<D>& layout, bool keep_acceleration) {
  const double per_particle =
      static_cast<double>(layout.bytes_per_particle() + sizeof(typename Stencil<D, shape::GimpKernel>::Axes));
  const double model = grid_slots * static_cast<double>(Grid<D>::bytes_per_slot(keep_acceleration)) + particles * per_particle;
  return 1.25 * model + 32e6;
}

// A body's prescribed motion from its input (its function on the run's clock).
template <int D>
BodyMotion<D> body_motion(const Config& config, int body);

// Builds the particles and grid; throws InputError (before allocating) when memory_estimate
// exceeds the memory available.
template <int D>
Model<D> build_model(const Config& config);

extern template BodyMotion<2> body_motion<2>(const Config&, int);
extern template BodyMotion<3> body_motion<3>(const Config&, int);
extern template Model<2> build_model<2>(const Config&);
extern template Model<3> build_model<3>(const Config&);

}  // namespace tsuchi
