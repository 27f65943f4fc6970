#pragma once
// Whole-model sums for the global CSV and for conservation checks.
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

template <int D>
GlobalQuantities<D> global_quantities(const Model<D>& m) {
  GlobalQuantities<D> q;
  const auto& p = m.particles;
  Vec<D> b;
  for (int d = 0; d < D; ++d) b[d] = m.config.gravity[d];
  for (std::size_t i = 0; i < p.size(); ++i) {
    q.mass += p.m_p[i];
    q.momentum += p.m_p[i] * p.v_p[i];
    q.kinetic_energy += 0.5 * p.m_p[i] * p.v_p[i].squaredNorm();
    q.gravity_potential -= p.m_p[i] * b.dot(p.x_p[i] - m.grid.origin);
    const Voigt<D> s = p.sigma_p[i] - p.sigma0_p[i];
    q.strain_energy += p.V_p[i] * m.config.materials[p.material_p[i]].elastic().template energy_density<D>(s);
  }
  return q;
}

}  // namespace tsuchi
