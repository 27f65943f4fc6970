#pragma once
// The explicit stable time step: a wave must not cross a cell in one step. With the P-wave speed
// c_p = sqrt((K + 4G/3) / rho) and the particle speed |v_p| (material moving through the grid),
//   dt_crit = min_p  h / (c_p + |v_p|),   dt = Courant * dt_crit.
// A non-finite particle state gives NaN, which the caller reports.
#include "tsuchi/material/material.hpp"
#include "tsuchi/particles/particles.hpp"

#include <cmath>
#include <limits>
#include <vector>

namespace tsuchi {

template <int D>
double critical_time_step(const Particles<D>& p, const std::vector<Material>& materials, double h) {
  double max_speed = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double rho = p.m_p[i] / p.V_p[i];
    const double c = std::sqrt(materials[p.material_p[i]].elastic().constrained_modulus() / rho);
    const double speed = c + p.v_p[i].norm();
    if (!std::isfinite(speed)) return std::numeric_limits<double>::quiet_NaN();
    max_speed = std::max(max_speed, speed);
  }
  return max_speed > 0.0 ? h / max_speed : std::numeric_limits<double>::infinity();
}

}  // namespace tsuchi
