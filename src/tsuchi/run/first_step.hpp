#pragma once
// A first step too long for the load it carries. time.courant bounds the step by the wave speed of
// the starting stiffness (solver/time_step.hpp); a soil whose stiffness grows with its pressure and
// starts at none (modified Cam-Clay at zero stress: K = v p_min / kappa, so minimum_pressure = 1 Pa
// gives a step of 0.12 s in 0.05 m cells) may take a step in which gravity alone moves it a large
// part of a cell. Stable for the stiffness it had, the step then crushes the soil, and the fault
// that follows ("compressed to zero volume in one step") blames the step. Said before the run with
// the particle, material and modulus that set the step.
#include "tsuchi/model/config.hpp"
#include "tsuchi/model/material_state.hpp"
#include "tsuchi/model/model.hpp"
#include "tsuchi/run/simulation.hpp"
#include "tsuchi/solver/time_step.hpp"

#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <string>

namespace tsuchi {

// Gravity's fall in the first step, g dt^2 / 2, above this part of a cell is said.
inline constexpr double first_step_fall_limit = 0.1;

template <int D>
std::optional<std::string> long_first_step_warning(const Config& c, const Model<D>& m) {
  const auto& p = m.particles;
  if (!c.time.courant || p.size() == 0) return std::nullopt;
  double g = 0.0;
  for (int d = 0; d < D; ++d) g += c.gravity[static_cast<std::size_t>(d)] * c.gravity[static_cast<std::size_t>(d)];
  g = std::sqrt(g);
  const double dt_crit = critical_time_step<D>(p, c.materials, m.grid.h);
  // A step that is no bound at all (or not finite) is refused by next_time_step.
  if (!(g > 0.0) || !(dt_crit <= max_stable_step)) return std::nullopt;
  const double dt = *c.time.courant * dt_crit;
  const double fall = 0.5 * g * dt * dt;
  if (!(fall > first_step_fall_limit * m.grid.h)) return std::nullopt;
  const std::size_t i = limiting_particle<D>(p, c.materials);
  const Material& mat = c.materials[static_cast<std::size_t>(p.material_p[i])];
  const double modulus = stiffness_of(mat, p, i).constrained_modulus();
  return fmt::format(
      "the first step is {:.3g} s (time.courant = {:g} of cell size / P-wave speed), set by particle {} of body "
      "\"{}\", material \"{}\", whose constrained modulus at its starting stress is {:.3g} Pa; gravity alone moves "
      "the soil {:.3g} m in that step, {:.2g} of a cell, and a soil whose stiffness grows with its pressure is "
      "crushed before the step can follow it; give the body an initial stress ([bodies.initial_stress]), a larger "
      "minimum_pressure of a pressure-dependent model, or check the moduli (Pa) and densities (kg/m^3)",
      dt, *c.time.courant, i, c.bodies[static_cast<std::size_t>(p.body_p[i])].name, mat.name, modulus, fall,
      fall / m.grid.h);
}

}  // namespace tsuchi
