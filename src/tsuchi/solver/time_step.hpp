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

// c_p + |v_p| of particle i: the speed of the fastest signal it carries.
template <int D>
inline double signal_speed(const Particles<D>& p, const std::vector<Material>& materials, std::size_t i) {
  const double rho = p.m_p[i] / p.V_p[i];
  const double c = std::sqrt(materials[p.material_p[i]].elastic().constrained_modulus() / rho);
  return c + p.v_p[i].norm();
}

// The particle that sets dt_crit (the largest signal speed), or the first with a non-finite one:
// the particle a fault of the time step is about.
template <int D>
std::size_t limiting_particle(const Particles<D>& p, const std::vector<Material>& materials) {
  std::size_t best = 0;
  double fastest = -1.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double speed = signal_speed(p, materials, i);
    if (!std::isfinite(speed)) return i;
    if (speed > fastest) fastest = speed, best = i;
  }
  return best;
}

template <int D>
double critical_time_step(const Particles<D>& p, const std::vector<Material>& materials, double h) {
  double max_speed = 0.0;
  bool finite = true;
  const auto n = static_cast<std::int64_t>(p.size());
  // max is exact in any order: the step is the same on any number of threads.
#pragma omp parallel for schedule(static) reduction(max : max_speed) reduction(&& : finite)
  for (std::int64_t i = 0; i < n; ++i) {
    const double speed = signal_speed(p, materials, static_cast<std::size_t>(i));
    finite = finite && std::isfinite(speed);
    max_speed = std::max(max_speed, speed);
  }
  if (!finite) return std::numeric_limits<double>::quiet_NaN();
  return max_speed > 0.0 ? h / max_speed : std::numeric_limits<double>::infinity();
}

}  // namespace tsuchi
