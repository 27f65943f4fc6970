#pragma once
// Reads and validates a TOML input file into a Config. Every key is checked for type and range;
// unknown keys are errors. Messages read "FILE:LINE:COL: key 'a.b': expected ..., got ...".
#include "tsuchi/model/config.hpp"

#include <string>
#include <vector>

namespace tsuchi {

// `overrides` are "dotted.key=value" assignments (value in TOML syntax) applied before validation,
// e.g. "grid.cell_size=0.01" or "bodies.0.velocity=[1.0, 0.0]".
Config read_config_file(const std::string& path, const std::vector<std::string>& overrides = {});
Config read_config_string(const std::string& text, const std::string& source_name,
                          const std::vector<std::string>& overrides = {});

}  // namespace tsuchi
