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

// Soils, rocks and concrete weigh 1,000 to 3,000 kg/m^3 and nothing solid over 22,600 (osmium):
// below 100 a density was most likely given in t/m^3 (or g/cm^3), above 100,000 in g/m^3 or so.
void check_density(const Section& s, std::vector<std::string>* warnings, double v) {
  if (v < 100.0)
    warn(s, warnings, "density",
         fmt::format("{:g} kg/m^3 is below any soil's; densities are in kg/m^3 (for {:g} t/m^3 write {:g})", v, v, v * 1e3));
  else if (v > 1e5)
    warn(s, warnings, "density", fmt::format("{:g} kg/m^3 is above any solid's (osmium: 22,600); densities are in kg/m^3", v));
}

LinearElastic read_elastic(Section& s, std::vector<std::string>* warnings) {
  const double nu = s.number("poisson_ratio", "a Poisson's ratio in (-1, 0.5)",
                             [](double v) { return v > -1.0 && v < 0.5; });
  const bool has_E = s.has("youngs_modulus"), has_G = s.has("shear_modulus");
  if (has_E == has_G)
    s.fail_one_of({"youngs_modulus", "shear_modulus"}, "give exactly one of 'youngs_modulus' and 'shear_modulus' (Pa)");
  const char* key = has_E ? "youngs_modulus" : "shear_modulus";
  const double modulus = s.number(key, "a positive modulus in Pa", positive);
  check_modulus(s, warnings, key, modulus);
  return has_E ? LinearElastic::from_young(modulus, nu) : LinearElastic::from_shear(modulus, nu);
}

// Whether the n-th registered model reads its own elasticity (a pressure-dependent one does).
template <std::size_t I = 0>
bool reads_own_elasticity(std::size_t n) {
  using M = std::variant_alternative_t<I, ConstitutiveModel>;
  if (n == I) {
    if constexpr (requires { M::reads_own_elasticity; }) return M::reads_own_elasticity;
    else return false;
  }
  if constexpr (I + 1 < std::variant_size_v<ConstitutiveModel>) return reads_own_elasticity<I + 1>(n);
  else return false;
}

// The names of the registered models, in registration order, and the reader of the n-th.
template <class... M>
std::vector<std::string> model_names(std::variant<M...>*) {
  return {std::string(M::name)...};
}
template <std::size_t I = 0>
ConstitutiveModel read_model(std::size_t n, Section& s, const LinearElastic& elastic, std::vector<std::string>* warnings) {
  using M = std::variant_alternative_t<I, ConstitutiveModel>;
  // Each model reads its own parameters (read_model_parameters, beside the model in material/).
  const auto note = [&](std::string_view key, const std::string& msg) { warn(s, warnings, key, msg); };
  if (n == I) return read_model_parameters(s, elastic, note, std::type_identity<M>{});
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
  check_density(s, warnings, m.density);
  const LinearElastic elastic =
      reads_own_elasticity(static_cast<std::size_t>(model)) ? LinearElastic{} : read_elastic(s, warnings);
  m.model = read_model(static_cast<std::size_t>(model), s, elastic, warnings);
  s.finish();
  return m;
}

}  // namespace tsuchi::io
