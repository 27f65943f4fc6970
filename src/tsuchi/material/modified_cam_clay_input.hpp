#pragma once
// Modified Cam-Clay's parameters from an input table (docs/input.md, model = "modified_cam_clay").
// The model reads its own elasticity (kappa with poisson_ratio or shear_modulus): the material
// reader skips youngs_modulus for it (ModifiedCamClay::reads_own_elasticity). Each pair of
// alternatives (M or the critical-state friction angle, e0 or v0, p_c or OCR, nu or G) takes
// exactly one.
#include "tsuchi/material/modified_cam_clay.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <string_view>
#include <type_traits>

namespace tsuchi {

template <class Table, class Warn>
ModifiedCamClay read_model_parameters(Table& s, const LinearElastic&, Warn&& warn,
                                      std::type_identity<ModifiedCamClay>) {
  const auto positive = [](double v) { return v > 0.0; };
  // Exactly one of two keys; returns whether the first is the one given.
  const auto one_of = [&](std::string_view a, std::string_view b, std::string_view what) {
    const bool has_a = s.has(a), has_b = s.has(b);
    if (has_a == has_b)
      s.fail(has_a ? b : a, fmt::format("give exactly one of '{}' and '{}' ({}), got {}", a, b, what,
                                        has_a ? "both" : "neither"));
    return has_a;
  };
  ModifiedCamClay m;
  m.kappa = s.number("kappa", "a swelling index kappa > 0 (slope of the unloading line in v - ln p)", positive);
  m.lambda = s.number("lambda", "a compression index lambda > 0 (slope of the NCL in v - ln p)", positive);
  if (!(m.lambda > m.kappa))
    s.fail("lambda", fmt::format("expected lambda larger than kappa ({:g}), got {:g}: plastic compression "
                                 "needs lambda - kappa > 0",
                                 m.kappa, m.lambda));
  if (one_of("critical_state_slope", "critical_state_friction_angle", "M, or phi_cs in degrees")) {
    m.M = s.number("critical_state_slope", "a critical state slope M > 0 (q / p at critical state)", positive);
  } else {
    const double phi = s.number("critical_state_friction_angle", "a critical state friction angle in degrees, in (0, 90)",
                                [](double v) { return v > 0.0 && v < 90.0; });
    if (phi < 1.0)
      warn("critical_state_friction_angle",
           fmt::format("{:g} degrees is below 1 degree; angles are in degrees", phi));
    const double sp = std::sin(phi * std::numbers::pi / 180.0);
    m.M = 6.0 * sp / (3.0 - sp);  // triaxial compression
  }
  if (one_of("initial_void_ratio", "initial_specific_volume", "e0 or v0 = 1 + e0"))
    m.v0 = 1.0 + s.number("initial_void_ratio", "an initial void ratio e0 > 0", positive);
  else
    m.v0 = s.number("initial_specific_volume", "an initial specific volume v0 > 1",
                    [](double v) { return v > 1.0; });
  if (one_of("preconsolidation_pressure", "ocr", "p_c in Pa, or OCR relative to the starting stress"))
    m.pc0 = s.number("preconsolidation_pressure", "a preconsolidation pressure > 0 in Pa", positive);
  else
    m.ocr = s.number("ocr", "an over-consolidation ratio >= 1", [](double v) { return v >= 1.0; });
  if (one_of("poisson_ratio", "shear_modulus", "nu for G from K, or a constant G in Pa")) {
    m.poisson = s.number("poisson_ratio", "a Poisson's ratio in (-1, 0.5)", [](double v) { return v > -1.0 && v < 0.5; });
  } else {
    m.shear_modulus = s.number("shear_modulus", "a positive shear modulus in Pa", positive);
    if (m.shear_modulus < 1e3)
      warn("shear_modulus", fmt::format("{:g} Pa is below 1 kPa; moduli are in Pa", m.shear_modulus));
  }
  m.p_min = s.number("minimum_pressure", "a minimum pressure > 0 in Pa (the floor of the bulk modulus)", positive, 1e3);
  return m;
}

}  // namespace tsuchi
