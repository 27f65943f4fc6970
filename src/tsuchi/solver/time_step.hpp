#pragma once
// The explicit stable time step: a wave must not cross a cell in one step. With the P-wave speed
// c_p = sqrt((K + 4G/3) / rho) and the particle speed |v_p| (material moving through the grid),
//   dt_crit = min_p  h / (c_p + |v_p|),   dt = Courant * dt_crit.
// A non-finite particle state gives NaN, which the caller reports.
#include "tsuchi/material/material.hpp"
#include "tsuchi/particles/particles.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace tsuchi {

template <int D>
double critical_time_step(const Particles<D>& p, const std::vector<Material>& materials, double h) {
  double max_speed = 0.0;
  bool finite = true;
  const auto n = static_cast<std::int64_t>(p.size());
  // max is exact in any order: the step is the same on any number of threads.
#pragma omp parallel for schedule(static) reduction(max : max_speed) reduction(&& : finite)
  for (std::int64_t i = 0; i < n; ++i) {
    const double rho = p.m_p[i] / p.V_p[i];
    const double c = std::sqrt(materials[p.material_p[i]].elastic().constrained_modulus() / rho);
    const double speed = c + p.v_p[i].norm();
    finite = finite && std::isfinite(speed);
    max_speed = std::max(max_speed, speed);
  }
  if (!finite) return std::numeric_limits<double>::quiet_NaN();
  return max_speed > 0.0 ? h / max_speed : std::numeric_limits<double>::infinity();
}

}  // namespace tsuchi
