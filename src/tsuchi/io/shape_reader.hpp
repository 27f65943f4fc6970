#pragma once
// Reads a shape from the table of a body, a region or an operand of a boolean: the key `shape`
// names the kind ("box" when absent, so inputs written before shapes keep their meaning) and the
// shape's own keys sit beside it in the same table, with the booleans `add`, `intersect` and
// `subtract` (arrays of inline tables, each a shape). Errors name the file, line and key.
// The kinds and their keys: docs/shapes.md; the table of kinds: shape_reader.cpp.
#include "tsuchi/geometry/shape.hpp"
#include "tsuchi/io/toml_section.hpp"
#include "tsuchi/model/config.hpp"

#include <string>
#include <vector>

namespace tsuchi::io {

// Whether the shape read may be unbounded. A body's may not (it is filled with particles), so
// that is the default; a region that selects "everything below a plane" may be.
enum class Extent { Bounded, MayBeUnbounded };

// `directory` is the folder of the input file, against which a relative file name (an STL
// surface) is taken; each file read is added to `files` when given, and what is valid but likely
// not meant (overlapping STL shells) to `warnings`.
geometry::ShapePtr read_shape(Section& s, int dimension, const std::string& directory,
                              Extent extent = Extent::Bounded, std::vector<DataFile>* files = nullptr,
                              std::vector<std::string>* warnings = nullptr);

// The kind of shape a table describes, as written ("box" when it has no `shape`; a boolean as
// "box minus 1 shape"), for the summary and messages.
std::string shape_kind(Section& s);

}  // namespace tsuchi::io
