#pragma once
// The CSV table of an element test: '#' comment lines (what was run, the sign conventions), one
// header line, then one row per state.
#include "tsuchi/element/element_row.hpp"
#include "tsuchi/material/material.hpp"

#include <string>
#include <vector>

namespace tsuchi::element {

// The columns every element CSV has, in order.
const std::vector<std::string>& csv_columns();

// All columns of a test of `material`, as the header line holds them: the above, then the model's
// own state fields (a preconsolidation pressure, a specific volume, a softening parameter).
std::vector<std::string> csv_columns(const Material& material);

// `notes` become "# " lines at the top (input file, material, path, ...), before the lines that
// state the conventions.
std::string format_csv(const std::vector<ElementRow>& rows, const std::vector<std::string>& notes);

}  // namespace tsuchi::element
