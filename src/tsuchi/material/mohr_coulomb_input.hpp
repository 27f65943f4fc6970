#pragma once
// Mohr-Coulomb's parameters from an input table, past the elastic moduli (METHOD.md section 5;
// docs/input.md). `Table` is the input reader's table (io/toml_section.hpp: number, choice, fail);
// `warn(key, text)` records a valid value that looks like a slip of units. Angles are in degrees,
// as in every soil report.
#include "tsuchi/material/mohr_coulomb.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string_view>
#include <type_traits>

namespace tsuchi {

// c, phi and psi of a Mohr-Coulomb-type strength (angles read in degrees, returned in radians),
// and the tension strength capped at the apex c / tan(phi) (eq 29): the keys Mohr-Coulomb and
// Drucker-Prager share.
struct CohesionFriction {
  double cohesion, phi, psi, tension;
};

template <class Table, class Warn>
CohesionFriction read_cohesion_friction(Table& s, Warn&& warn) {
  constexpr double rad = std::numbers::pi / 180.0;
  // An angle below 1 degree was most likely given in radians.
  const auto check_angle = [&](std::string_view key, double degrees) {
    if (degrees > 0.0 && degrees < 1.0)
      warn(key, fmt::format("{:g} degrees is below 1 degree; angles are in degrees ({:g} radians would be {:.4g} degrees)",
                            degrees, degrees, degrees * 180.0 / std::numbers::pi));
  };
  const auto non_negative = [](double v) { return v >= 0.0; };
  CohesionFriction r;
  r.cohesion = s.number("cohesion", "a cohesion >= 0 in Pa", non_negative);
  // phi = 0 is Tresca (undrained clay, c = s_u): no tension cap then, as c / tan(0) is infinite.
  const double phi = s.number("friction_angle", "a friction angle in degrees, in [0, 90) (0: Tresca)",
                              [](double v) { return v >= 0.0 && v < 90.0; });
  const double psi = s.number("dilatancy_angle", "a dilatancy angle in degrees, in [0, friction_angle]",
                              [](double v) { return v >= 0.0 && v < 90.0; }, 0.0);
  check_angle("friction_angle", phi);
  check_angle("dilatancy_angle", psi);
  if (psi > phi)
    s.fail("dilatancy_angle",
           fmt::format("expected a dilatancy angle no larger than the friction angle ({} degrees), got {}", phi, psi));
  r.phi = phi * rad;
  r.psi = psi * rad;
  // Above the apex c / tan(phi) a tension strength has no meaning; (29) caps it there.
  r.tension = s.number("tension_strength", "a tension strength >= 0 in Pa", non_negative, 0.0);
  r.tension = std::min(r.tension, r.cohesion / std::tan(r.phi));
  return r;
}

template <class Table, class Warn>
MohrCoulomb read_model_parameters(Table& s, const LinearElastic& elastic, Warn&& warn, std::type_identity<MohrCoulomb>) {
  const CohesionFriction cf = read_cohesion_friction(s, warn);
  MohrCoulomb m;
  m.elastic = elastic;
  m.cohesion = cf.cohesion;
  m.phi = cf.phi;
  m.psi = cf.psi;
  m.tension = cf.tension;
  m.tension_rule = static_cast<TensionRule>(s.choice("tension_rule", {"flac", "paper"}, 0));
  // Each rule goes with its own selection unless told otherwise.
  const int rule = static_cast<int>(m.tension_rule);
  m.tension_selection = static_cast<TensionSelection>(s.choice("tension_selection", {"flac", "paper"}, rule));
  if (m.tension_rule == TensionRule::Paper && m.tension_selection == TensionSelection::Flac)
    s.fail("tension_selection",
           "tension_rule = \"paper\" needs tension_selection = \"paper\": with FLAC's h-function the release "
           "and the shear return meet at different stresses where h = 0, so the result would jump");
  return m;
}

}  // namespace tsuchi
