#pragma once
// Drucker-Prager's parameters from an input table, past the elastic moduli (docs/input.md,
// model = "drucker_prager"). `Table` is the input reader's table (io/toml_section.hpp); `warn(key,
// text)` records a valid value that looks like a slip of units. Angles in degrees.
#include "tsuchi/material/drucker_prager.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string_view>
#include <string>
#include <type_traits>
#include <vector>

namespace tsuchi {

template <class Table, class Warn>
DruckerPrager read_model_parameters(Table& s, const LinearElastic& elastic, Warn&& warn,
                                    std::type_identity<DruckerPrager>) {
  constexpr double rad = std::numbers::pi / 180.0;
  const auto check_angle = [&](std::string_view key, double degrees) {
    if (degrees > 0.0 && degrees < 1.0)
      warn(key, fmt::format("{:g} degrees is below 1 degree; angles are in degrees ({:g} radians would be {:.4g} degrees)",
                            degrees, degrees, degrees * 180.0 / std::numbers::pi));
  };
  const auto non_negative = [](double v) { return v >= 0.0; };
  DruckerPrager m;
  m.elastic = elastic;
  m.cohesion = s.number("cohesion", "a cohesion >= 0 in Pa", non_negative);
  const double phi = s.number("friction_angle", "a friction angle in degrees, in (0, 90)",
                              [](double v) { return v > 0.0 && v < 90.0; });
  const double psi = s.number("dilatancy_angle", "a dilatancy angle in degrees, in [0, friction_angle]",
                              [](double v) { return v >= 0.0 && v < 90.0; }, 0.0);
  check_angle("friction_angle", phi);
  check_angle("dilatancy_angle", psi);
  if (psi > phi)
    s.fail("dilatancy_angle",
           fmt::format("expected a dilatancy angle no larger than the friction angle ({} degrees), got {}", phi, psi));
  m.phi = phi * rad;
  m.psi = psi * rad;
  // The three cones differ by up to a factor (3 + sin phi) / (3 - sin phi) in strength: no default.
  const std::string matches = "one of \"compression\", \"extension\", \"plane_strain\" (the Mohr-Coulomb strength the cone reproduces)";
  if (!s.has("match")) s.need("match", matches);
  m.match = static_cast<ConeMatch>(s.choice("match", std::vector<std::string>(cone_match_names.begin(), cone_match_names.end()), 0));
  // Above the apex c / tan(phi) (the same for every matching) a tension strength has no meaning.
  m.tension = s.number("tension_strength", "a tension strength >= 0 in Pa", non_negative, 0.0);
  m.tension = std::min(m.tension, m.cohesion / std::tan(m.phi));
  return m;
}

}  // namespace tsuchi
