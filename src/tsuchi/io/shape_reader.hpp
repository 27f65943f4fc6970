#pragma once
// Reads a shape from the table of a body, a region or an operand of a boolean: the key `shape`
// names the kind ("box" when absent, so inputs written before shapes keep their meaning) and the
// shape's own keys sit beside it in the same table. Errors name the file, line and key.
#include "tsuchi/geometry/shape.hpp"
#include "tsuchi/io/toml_section.hpp"

#include <string>

namespace tsuchi::io {

// `directory` is the folder of the input file, against which a relative file name (an STL
// surface) is taken.
geometry::ShapePtr read_shape(Section& s, int dimension, const std::string& directory);

}  // namespace tsuchi::io
