#pragma once
// `tsuchi element FILE`: drives one material point along the path of an element-test input and
// writes the states to a CSV file (docs/element.md).
#include <string>
#include <vector>

namespace tsuchi::app {

struct ElementOptions {
  std::string file;
  std::string output;  // empty: FILE's stem with ".csv", in the current directory
  std::vector<std::string> overrides;
  bool quiet = false;
};

// Returns the exit code; throws InputError, RunError or OutputError like `tsuchi run`. A run
// error still writes (atomically) every row computed before it.
int run_element_command(const ElementOptions& o);

}  // namespace tsuchi::app
