#include "tsuchi/io/material_reader.hpp"

#include <numbers>

namespace tsuchi::io {

namespace {

void warn(const Section& s, std::vector<std::string>* warnings, std::string_view key, const std::string& msg) {
  if (warnings) warnings->push_back(s.located(key, msg));
}

// Soil moduli are MPa to GPa: below 1 kPa, a value was most likely given in kPa or MPa.
void check_modulus(const Section& s, std::vector<std::string>* warnings, std::string_view key, double v) {
  if (v < 1e3)
    warn(s, warnings, key,
         fmt::format("{:g} Pa is below 1 kPa; moduli are in Pa (for {:g} MPa write {:g})", v, v, v * 1e6));
}

LinearElastic read_elastic(Section& s, std::vector<std::string>* warnings) {
  const double nu = s.number("poisson_ratio", "a Poisson's ratio in (-1, 0.5)",
                             [](double v) { return v > -1.0 && v < 0.5; });
  const bool has_E = s.has("youngs_modulus"), has_G = s.has("shear_modulus");
  if (has_E == has_G) s.fail_here("give exactly one of 'youngs_modulus' and 'shear_modulus' (Pa)");
  const char* key = has_E ? "youngs_modulus" : "shear_modulus";
  const double modulus = s.number(key, "a positive modulus in Pa", positive);
  check_modulus(s, warnings, key, modulus);
  return has_E ? LinearElastic::from_young(modulus, nu) : LinearElastic::from_shear(modulus, nu);
}

// Angles are in degrees; one below 1 degree was most likely given in radians.
void check_angle(const Section& s, std::vector<std::string>* warnings, std::string_view key, double degrees) {
  if (degrees > 0.0 && degrees < 1.0)
    warn(s, warnings, key,
         fmt::format("{:g} degrees is below 1 degree; angles are in degrees ({:g} radians would be {:.4g} degrees)",
                     degrees, degrees, degrees * 180.0 / std::numbers::pi));
}

// Angles are given in degrees, as in every soil report.
MohrCoulomb read_mohr_coulomb(Section& s, const LinearElastic& elastic, std::vector<std::string>* warnings) {
  constexpr double rad = std::numbers::pi / 180.0;
  MohrCoulomb m;
  m.elastic = elastic;
  m.cohesion = s.number("cohesion", "a cohesion >= 0 in Pa", non_negative);
  const double phi = s.number("friction_angle", "a friction angle in degrees, in (0, 90)",
                              [](double v) { return v > 0.0 && v < 90.0; });
  const double psi = s.number("dilatancy_angle", "a dilatancy angle in degrees, in [0, friction_angle]",
                              [](double v) { return v >= 0.0 && v < 90.0; }, 0.0);
  check_angle(s, warnings, "friction_angle", phi);
  check_angle(s, warnings, "dilatancy_angle", psi);
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

// The parameters of each registered model (material/material.hpp), past its elastic moduli: a new
// model adds its reader here.
LinearElastic read_parameters(Section&, const LinearElastic& elastic, std::vector<std::string>*, const LinearElastic*) {
  return elastic;
}
MohrCoulomb read_parameters(Section& s, const LinearElastic& elastic, std::vector<std::string>* warnings,
                            const MohrCoulomb*) {
  return read_mohr_coulomb(s, elastic, warnings);
}

// The names of the registered models, in registration order, and the reader of the n-th.
template <class... M>
std::vector<std::string> model_names(std::variant<M...>*) {
  return {std::string(M::name)...};
}
template <std::size_t I = 0>
ConstitutiveModel read_model(std::size_t n, Section& s, const LinearElastic& elastic, std::vector<std::string>* warnings) {
  using M = std::variant_alternative_t<I, ConstitutiveModel>;
  if (n == I) return read_parameters(s, elastic, warnings, static_cast<const M*>(nullptr));
  if constexpr (I + 1 < std::variant_size_v<ConstitutiveModel>) return read_model<I + 1>(n, s, elastic, warnings);
  else return elastic;  // unreachable: n is the index of a name
}

}  // namespace

Material read_material(Section& s, const std::vector<Material>& defined, std::vector<std::string>* warnings) {
  Material m;
  m.name = s.string("name", "a material name");
  for (const auto& other : defined)
    if (other.name == m.name) s.fail("name", fmt::format("material \"{}\" is defined twice", m.name));
  const std::vector<std::string> names = model_names(static_cast<ConstitutiveModel*>(nullptr));
  const int model = s.choice("model", names, -1);
  if (model < 0) s.need("model", fmt::format("a constitutive model name ({})", quoted_list(names)));
  m.density = s.number("density", "a positive density in kg/m^3", positive);
  const LinearElastic elastic = read_elastic(s, warnings);
  m.model = read_model(static_cast<std::size_t>(model), s, elastic, warnings);
  s.finish();
  return m;
}

}  // namespace tsuchi::io
