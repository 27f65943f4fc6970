#pragma once
// The CSV table of an element test: '#' comment lines (what was run, the sign conventions), one
// header line, then one row per state.
#include "tsuchi/element/element_row.hpp"

#include <string>
#include <vector>

namespace tsuchi::element {

// The column names, in order, as the header line holds them.
const std::vector<std::string>& csv_columns();

// `notes` become "# " lines at the top (input file, material, path, ...), before the lines that
// state the conventions.
std::string format_csv(const std::vector<ElementRow>& rows, const std::vector<std::string>& notes);

}  // namespace tsuchi::element
