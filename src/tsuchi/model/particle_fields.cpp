#include "tsuchi/model/particle_fields.hpp"

#include "tsuchi/material/material.hpp"

#include <fmt/format.h>

namespace tsuchi {

namespace {

constexpr const char* kVoigt[] = {"xx", "yy", "zz", "xy", "yz", "xz"};

std::vector<ParticleField> build_registry() {
  using K = FieldKind;
  using T = FieldType;
  using Q = Quantity;
  std::vector<ParticleField> r{
      {"position", K::Vector, T::Float64, "m", "current position (the points of a frame)", false, true, Q::Position},
      {"id", K::Scalar, T::Int64, "", "stable particle identity", true, false, Q::Id},
      {"displacement", K::Vector, T::Float64, "m", "displacement from the initial position", true, true, Q::Displacement},
      {"velocity", K::Vector, T::Float64, "m/s", "velocity", true, true, Q::Velocity},
      {"stress", K::Tensor, T::Float64, "Pa", "Cauchy stress, tension positive", true, true, Q::Stress},
      {"strain", K::Tensor, T::Float64, "", "accumulated small strain, eq (10b)", true, true, Q::Strain},
      {"max_shear_strain", K::Scalar, T::Float64, "", "(eps1 - eps3) of the accumulated strain", true, true,
       Q::MaxShearStrain},
      {"mean_stress", K::Scalar, T::Float64, "Pa", "p = tr(sigma) / 3, tension positive", true, true, Q::MeanStress},
      {"deviator_stress", K::Scalar, T::Float64, "Pa", "q = sqrt(3 J2)", true, true, Q::DeviatorStress},
      {"radius", K::Scalar, T::Float64, "m", "mean half-width of the GIMP domain", true, false, Q::Radius},
      {"volume", K::Scalar, T::Float64, "m^3 (m^2 in 2D)", "volume", true, true, Q::Volume},
      {"mass", K::Scalar, T::Float64, "kg (kg/m in 2D)", "mass", true, true, Q::Mass},
      {"density", K::Scalar, T::Float64, "kg/m^3", "mass / volume", true, true, Q::Density},
      {"material", K::Scalar, T::Int32, "", "index of the material", true, false, Q::MaterialIndex},
      {"body", K::Scalar, T::Int32, "", "index of the body", true, false, Q::BodyIndex},
  };
  const auto& state = material_state_fields();
  for (std::size_t k = 0; k < state.size(); ++k) {
    const StateField& s = state[k];
    ParticleField f;
    f.name = s.name;
    f.type = s.flag ? T::UInt8 : T::Float64;
    f.unit = s.unit;
    f.description = s.description;
    f.state = static_cast<int>(k);
    r.push_back(f);
    if (!s.indicator.empty()) {
      ParticleField g;
      g.name = s.indicator;
      g.description = fmt::format("1 where {} is nonzero, else 0 (its mean is the fraction)", s.name);
      g.frame = false;
      g.quantity = Q::StateIndicator;
      g.state = static_cast<int>(k);
      r.push_back(g);
    }
  }
  return r;
}

std::string component_name(const ParticleField& f, int c) {
  switch (f.kind) {
    case FieldKind::Scalar: return f.name;
    case FieldKind::Vector: return fmt::format("{}_{}", f.name, "xyz"[c]);
    case FieldKind::Tensor: return fmt::format("{}_{}", f.name, kVoigt[c]);
  }
  return f.name;
}

}  // namespace

const std::vector<ParticleField>& particle_fields() {
  static const std::vector<ParticleField> registry = build_registry();
  return registry;
}

const ParticleField* find_particle_field(std::string_view name) {
  for (const auto& f : particle_fields())
    if (f.name == name) return &f;
  return nullptr;
}

std::vector<std::string> frame_field_names() {
  std::vector<std::string> n;
  for (const auto& f : particle_fields())
    if (f.frame) n.push_back(f.name);
  return n;
}

int components(const ParticleField& f, int dim) {
  switch (f.kind) {
    case FieldKind::Scalar: return 1;
    case FieldKind::Vector: return dim;
    case FieldKind::Tensor: return dim == 2 ? 4 : 6;
  }
  return 1;
}

std::vector<std::string> recorder_quantities(int dimension) {
  std::vector<std::string> n;
  for (const auto& f : particle_fields())
    if (f.recorder)
      for (int c = 0; c < components(f, dimension); ++c) n.push_back(component_name(f, c));
  return n;
}

std::optional<std::pair<const ParticleField*, int>> find_recorder_quantity(std::string_view name, int dimension) {
  for (const auto& f : particle_fields())
    if (f.recorder)
      for (int c = 0; c < components(f, dimension); ++c)
        if (component_name(f, c) == name) return std::pair{&f, c};
  return std::nullopt;
}

}  // namespace tsuchi
