#include "tsuchi/io/material_reader.hpp"

#include <numbers>

namespace tsuchi::io {

namespace {

LinearElastic read_elastic(Section& s) {
  const double nu = s.number("poisson_ratio", "a Poisson's ratio in (-1, 0.5)",
                             [](double v) { return v > -1.0 && v < 0.5; });
  const bool has_E = s.has("youngs_modulus"), has_G = s.has("shear_modulus");
  if (has_E == has_G) s.fail_here("give exactly one of 'youngs_modulus' and 'shear_modulus' (Pa)");
  if (has_E) return LinearElastic::from_young(s.number("youngs_modulus", "a positive modulus in Pa", positive), nu);
  return LinearElastic::from_shear(s.number("shear_modulus", "a positive modulus in Pa", positive), nu);
}

// Angles are given in degrees, as in every soil report.
MohrCoulomb read_mohr_coulomb(Section& s, const LinearElastic& elastic) {
  constexpr double rad = std::numbers::pi / 180.0;
  MohrCoulomb m;
  m.elastic = elastic;
  m.cohesion = s.number("cohesion", "a cohesion >= 0 in Pa", non_negative);
  const double phi = s.number("friction_angle", "a friction angle in degrees, in (0, 90)",
                              [](double v) { return v > 0.0 && v < 90.0; });
  const double psi = s.number("dilatancy_angle", "a dilatancy angle in degrees, in [0, friction_angle]",
                              [](double v) { return v >= 0.0 && v < 90.0; }, 0.0);
  if (psi > phi)
    s.fail("dilatancy_angle",
           fmt::format("expected a dilatancy angle no larger than the friction angle ({} degrees), got {}", phi, psi));
  m.phi = phi * rad;
  m.psi = psi * rad;
  // Above the apex c / tan(phi) a tension strength has no meaning; (29) caps it there.
  m.tension = s.number("tension_strength", "a tension strength >= 0 in Pa", non_negative, 0.0);
  m.tension = std::min(m.tension, m.cohesion / std::tan(m.phi));
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

}  // namespace

Material read_material(Section& s, const std::vector<Material>& defined) {
  Material m;
  m.name = s.string("name", "a material name");
  for (const auto& other : defined)
    if (other.name == m.name) s.fail("name", fmt::format("material \"{}\" is defined twice", m.name));
  const int model = s.choice("model", {"linear_elastic", "mohr_coulomb"}, -1);
  if (model < 0) s.need("model", "a constitutive model name (\"linear_elastic\" or \"mohr_coulomb\")");
  m.density = s.number("density", "a positive density in kg/m^3", positive);
  const LinearElastic elastic = read_elastic(s);
  if (model == 0) m.model = elastic;
  else m.model = read_mohr_coulomb(s, elastic);
  s.finish();
  return m;
}

}  // namespace tsuchi::io
