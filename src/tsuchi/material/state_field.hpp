#pragma once
// Material state: the per-point history a constitutive model carries from step to step (plastic
// strains, a yield mode, strength factors). A model declares its fields once, as a constexpr list
// of StateField; everything else derives from that list (model/particle_fields.hpp): the particle
// columns that store them, the frame fields and recorder quantities that show them, the checkpoint
// sections that save them, and the input check of output.fields and recorder quantities.
#include <cstddef>
#include <string>
#include <string_view>

namespace tsuchi {

struct StateField {
  std::string_view name;         // the one name: particle column, frame field, recorder quantity
  std::string_view unit;         // "" for a ratio or a strain
  double initial = 0.0;          // value of a new point
  bool flag = false;             // a small whole number (a mode), written to frames as UInt8
  std::string_view indicator;    // a flag's 0/1 quantity "is it nonzero" (its mean is a fraction), or ""
  std::string_view description;  // one line, for docs and messages
};

// Names of state fields that code outside a model's own file relies on: the imperfection scales
// the strength factors, the element-test CSV shows the yield mode and the plastic strains. A model
// that has such a field declares it under this name (a rename is then a compile error, not a
// silent 0).
namespace field_name {
inline constexpr std::string_view yield_mode = "yield_mode";
inline constexpr std::string_view plastic_shear_strain = "plastic_shear_strain";
inline constexpr std::string_view plastic_volumetric_strain = "plastic_volumetric_strain";
inline constexpr std::string_view cohesion_factor = "cohesion_factor";
inline constexpr std::string_view friction_factor = "friction_factor";
}  // namespace field_name

// The state of one point, as the update sees it: field k of the model's list is column[k][i].
// Particles keep one flat column per field; a single point (an element test) points each column
// at one number and uses i = 0.
struct StateRef {
  double* const* column = nullptr;
  std::size_t i = 0;
  double& operator[](std::size_t k) const { return column[k][i]; }
};

// Where a stress lies beyond what a model admits, for the check of a starting stress: empty when
// admissible, else the surface crossed ("Mohr-Coulomb shear"), the yield surface it belongs to
// ("Mohr-Coulomb") and how ("beyond its shear strength").
struct Inadmissible {
  std::string surface, yield_surface, detail;
  bool any() const { return !surface.empty(); }
};

}  // namespace tsuchi
