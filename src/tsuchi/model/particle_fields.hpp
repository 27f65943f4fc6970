#pragma once
// The particle field registry: every per-particle quantity a user can ask for, under one name.
// Frame fields (output.fields, the .vtu writer), recorder quantities (a scalar field by its name,
// a vector's components as NAME_x, a tensor's as NAME_xx ...) and their input checks all read this
// list. It holds the built-in kinematic and stress fields, then every material state field of the
// registered constitutive models (material/material.hpp), so a new model's fields appear here
// without an edit.
#include "tsuchi/core/principal.hpp"
#include "tsuchi/particles/particles.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace tsuchi {

enum class FieldKind { Scalar, Vector, Tensor };  // 1, D (3 in frames) or Voigt (6 in frames) components
enum class FieldType { Float64, Int64, Int32, UInt8 };  // as written in frames

// The built-in quantities; material state fields are State.
enum class Quantity {
  Position, Id, Displacement, Velocity, Stress, Strain, MaxShearStrain, MeanStress, DeviatorStress, Radius,
  Volume, Mass, Density, MaterialIndex, BodyIndex, State, StateIndicator
};

struct ParticleField {
  std::string name;
  FieldKind kind = FieldKind::Scalar;
  FieldType type = FieldType::Float64;
  std::string unit;
  std::string description;
  bool frame = true;     // offered in output.fields (and written by default)
  bool recorder = true;  // offered as recorder quantities
  Quantity quantity = Quantity::State;
  int state = -1;        // State, StateIndicator: the column in Particles::state
};

// The registry, in the order frames list their fields by default.
const std::vector<ParticleField>& particle_fields();
const ParticleField* find_particle_field(std::string_view name);

// output.fields: the names of the frame fields.
std::vector<std::string> frame_field_names();

// Components field f has in a model of `dimension`: 1, D, or the Voigt entries (4 in 2D, 6 in 3D).
int components(const ParticleField& f, int dimension);

// Recorder quantities of a model of `dimension`: each recorder field's name or component names.
std::vector<std::string> recorder_quantities(int dimension);
// The field and component (axis, or Voigt index) a recorder quantity names, if it names one.
std::optional<std::pair<const ParticleField*, int>> find_recorder_quantity(std::string_view name, int dimension);

// Component c of field f of particle i (c: axis of a vector, Voigt index of a tensor).
template <int D>
double field_value(const ParticleField& f, const Particles<D>& p, std::size_t i, int c) {
  switch (f.quantity) {
    case Quantity::Position: return p.x_p[i][c];
    case Quantity::Id: return static_cast<double>(p.id_p[i]);  // exact below 2^53 (frames write the ids as they are)
    case Quantity::Displacement: return p.u_p[i][c];
    case Quantity::Velocity: return p.v_p[i][c];
    case Quantity::Stress: return p.sigma_p[i][c];
    case Quantity::Strain: return p.eps_p[i][c];
    case Quantity::MaxShearStrain: return max_shear_strain<D>(p.eps_p[i]);
    case Quantity::MeanStress: return trace<D>(p.sigma_p[i]) / 3.0;  // p, tension positive (sigma_zz included in 2D)
    case Quantity::DeviatorStress: return von_mises<D>(p.sigma_p[i]);  // q = sqrt(3 J2)
    // Half the side of the GIMP domain, the mean over the axes: the size ParaView's Point Gaussian
    // representation draws each particle with (docs/input.md).
    case Quantity::Radius: return p.l_p[i].mean();
    case Quantity::Volume: return p.V_p[i];
    case Quantity::Mass: return p.m_p[i];
    case Quantity::Density: return p.m_p[i] / p.V_p[i];
    case Quantity::MaterialIndex: return p.material_p[i];
    case Quantity::BodyIndex: return p.body_p[i];
    case Quantity::State: return p.state_value(static_cast<std::size_t>(f.state), i);
    case Quantity::StateIndicator: return p.state_value(static_cast<std::size_t>(f.state), i) != 0.0 ? 1.0 : 0.0;
  }
  return 0.0;
}

}  // namespace tsuchi
