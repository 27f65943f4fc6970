#pragma once
// The input of `tsuchi element`: [[materials]] tables exactly as in a run input (so one can be
// copied from the other), a [test] table giving the loading path (a lab-test preset or the
// general segment form), and an optional [iteration] table. docs/element.md describes every key.
#include "tsuchi/element/element_driver.hpp"
#include "tsuchi/element/element_path.hpp"
#include "tsuchi/material/material.hpp"

#include <string>
#include <vector>

namespace tsuchi::io {

struct ElementInput {
  std::string source;  // the file name as given
  std::string title;
  Material material;   // the one under test
  element::ElementPath path;
  element::IterationSettings iteration;
  std::vector<std::string> warnings;  // likely slips of units (io/material_reader.hpp)
};

// Both throw InputError naming the file, line, key and what was expected.
ElementInput read_element_string(const std::string& text, const std::string& file,
                                 const std::vector<std::string>& overrides = {});
ElementInput read_element_file(const std::string& path, const std::vector<std::string>& overrides = {});

// One line: the material's name, model and parameters in the units of the input.
std::string describe_material(const Material& m);

}  // namespace tsuchi::io
