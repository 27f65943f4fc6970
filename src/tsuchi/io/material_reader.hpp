#pragma once
// One [[materials]] table: the density, the elastic moduli and, for "mohr_coulomb", the strength.
// Shared by the run input and the element-test input.
#include "tsuchi/io/toml_section.hpp"
#include "tsuchi/material/material.hpp"

#include <vector>

namespace tsuchi::io {

// `defined` are the materials read so far (names must be unique). Calls s.finish().
// Values that are valid but most likely a slip of units (an angle below 1 degree, given in
// radians; a modulus below 1 kPa, given in MPa) add a warning to `warnings` when it is given.
Material read_material(Section& s, const std::vector<Material>& defined, std::vector<std::string>* warnings = nullptr);

}  // namespace tsuchi::io
