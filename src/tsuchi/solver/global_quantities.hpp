#pragma once
// Whole-model sums for the global CSV and for conservation checks.
#include "tsuchi/core/reduction.hpp"
#include "tsuchi/model/material_state.hpp"
#include "tsuchi/model/model.hpp"

namespace tsuchi {

template <int D>
struct GlobalQuantities {
  double mass = 0.0;
  double kinetic_energy = 0.0;     // sum m v^2 / 2
  double strain_energy = 0.0;      // recoverable elastic energy of sigma - sigma0
  double gravity_potential = 0.0;  // -sum m b . x, zero at the grid origin
  Vec<D> momentum = Vec<D>::Zero();
};

// sum m v^2 / 2 in storage order (the same bits on any thread count): global.csv's column and a
// stage's kinetic-energy ratio.
template <int D>
double kinetic_energy(const Particles<D>& p) {
  double e = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) e += 0.5 * p.m_p[i] * p.v_p[i].squaredNorm();
  return e;
}

template <int D>
GlobalQuantities<D> global_quantities(const Model<D>& m) {
  GlobalQuantities<D> q;
  const auto& p = m.particles;
  const Vec<D> b = m.step.gravity;
  for (std::size_t i = 0; i < p.size(); ++i) {
    q.mass += p.m_p[i];
    q.momentum += p.m_p[i] * p.v_p[i];
    q.gravity_potential -= p.m_p[i] * b.dot(p.x_p[i] - m.grid.origin);
    const Voigt<D> s = p.stress_above_initial(i);
    q.strain_energy += p.V_p[i] * stiffness_of(m.materials[static_cast<std::size_t>(p.material_p[i])], p, i).template energy_density<D>(s);
  }
  q.kinetic_energy = kinetic_energy(p);  // its own sum, in the same order as in the loop before
  q.mass = reduce::sum(q.mass);
  q.kinetic_energy = reduce::sum(q.kinetic_energy);
  q.strain_energy = reduce::sum(q.strain_energy);
  q.gravity_potential = reduce::sum(q.gravity_potential);
  for (int d = 0; d < D; ++d) q.momentum[d] = reduce::sum(q.momentum[d]);
  return q;
}

}  // namespace tsuchi
