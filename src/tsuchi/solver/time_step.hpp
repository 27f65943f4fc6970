#pragma once
// The explicit stable time step: a wave must not cross a cell in one step. With the P-wave speed
// c_p = sqrt(M / rho) of the point's current constrained modulus M = K + 4G/3 (the material's
// stiffness(state), material/material.hpp) and the particle speed |v_p| (material moving through
// the grid),
//   dt_crit = min_p  h / (c_p + |v_p|),   dt = Courant * dt_crit.
// A non-finite particle state gives NaN, which the caller reports.
#include "tsuchi/core/reduction.hpp"
#include "tsuchi/model/material_state.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace tsuchi {

// c_p + |v_p| of a particle of constrained modulus `modulus`: the speed of the fastest signal it carries.
template <int D>
inline double signal_speed(const Particles<D>& p, double modulus, std::size_t i) {
  const double rho = p.m_p[i] / p.V_p[i];
  const double c = std::sqrt(modulus / rho);
  return c + p.v_p[i].norm();
}

template <int D>
inline double signal_speed(const Particles<D>& p, const std::vector<Material>& materials, std::size_t i) {
  return signal_speed(p, stiffness_of(materials[static_cast<std::size_t>(p.material_p[i])], p, i).constrained_modulus(), i);
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

// The largest signal speed, material group by material group (the model chosen once per group);
// a maximum is exact in any order, so the step is the same on any number of threads or processes.
template <int D>
double critical_time_step(const Particles<D>& p, const std::vector<Material>& materials, double h) {
  double max_speed = 0.0;
  bool finite = true;
  const auto n = static_cast<std::int64_t>(p.size());
  // One parallel region for all the material groups (a fork and a join each cost microseconds, and
  // this runs every step); each thread's maximum is combined at its end.
#pragma omp parallel reduction(max : max_speed) reduction(&& : finite)
  for (std::size_t mat = 0; mat < materials.size(); ++mat) {
    std::visit(
        [&](const auto& model) {
          using M = std::decay_t<decltype(model)>;
          const auto state = state_columns<M>(p);
          const auto group = static_cast<std::int32_t>(mat);
#pragma omp for schedule(static) nowait
          for (std::int64_t ii = 0; ii < n; ++ii) {
            const auto i = static_cast<std::size_t>(ii);
            if (p.material_p[i] != group) continue;
            const double speed = signal_speed(p, model.stiffness(StateRef{state.data(), i}).constrained_modulus(), i);
            finite = finite && std::isfinite(speed);
            max_speed = std::max(max_speed, speed);
          }
        },
        materials[mat].model);
  }
  if (!reduce::all(finite)) return std::numeric_limits<double>::quiet_NaN();
  max_speed = reduce::max(max_speed);
  return max_speed > 0.0 ? h / max_speed : std::numeric_limits<double>::infinity();
}

}  // namespace tsuchi
