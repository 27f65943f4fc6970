#pragma once
// Names of the per-particle fields a frame can hold (output.fields in the input file).
#include <string>
#include <vector>

namespace tsuchi {

const std::vector<std::string>& all_particle_fields();
bool is_particle_field(const std::string& name);
std::string particle_field_list();  // "\"id\", \"displacement\", ..." for messages

}  // namespace tsuchi
