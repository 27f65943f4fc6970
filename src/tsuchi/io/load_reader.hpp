#pragma once
// The input's [[loads]]: surface tractions and pressures on a body's boundary particles, forces on
// grid node sets and body forces, each times an optional function of time (docs/input.md
// "[[loads]]", model/loads.hpp).
#include "tsuchi/io/toml_section.hpp"

namespace tsuchi::io {

// Reads every [[loads]] table of `top` into c.loads; needs c.bodies, c.grid and c.functions read.
void read_loads(Section& top, Config& c);

}  // namespace tsuchi::io
