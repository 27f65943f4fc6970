#include "tsuchi/io/particle_fields.hpp"

#include "tsuchi/io/toml_section.hpp"

#include <algorithm>

namespace tsuchi {

const std::vector<std::string>& all_particle_fields() {
  static const std::vector<std::string> names{
      "id",     "displacement", "velocity", "stress",   "strain", "max_shear_strain", "mean_stress", "deviator_stress",
      "radius", "volume",       "mass",     "density",  "material", "body",
      "yield_mode", "plastic_shear_strain", "plastic_volumetric_strain", "cohesion_factor", "friction_factor"};
  return names;
}

bool is_particle_field(const std::string& name) {
  const auto& n = all_particle_fields();
  return std::find(n.begin(), n.end(), name) != n.end();
}

std::string particle_field_list() { return io::quoted_list(all_particle_fields()); }

}  // namespace tsuchi
