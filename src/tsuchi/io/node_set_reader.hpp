#pragma once
// What a [[boundary.nodes]] table says besides its box and `fix`: its name and the driven
// components of a base motion (velocity or acceleration times a function of time), docs/input.md
// "[[boundary.nodes]]".
#include "tsuchi/io/toml_section.hpp"

namespace tsuchi::io {

// Reads name, velocity / acceleration, function and initial_velocity of node set `ns` (whose `fix`
// is already read) and checks the set as a whole: it holds something, and no component is both
// fixed and driven, and its name is not taken by an earlier set of c.boundary.node_sets.
void read_node_set_motion(Section& s, const Config& c, NodeSetConfig& ns);

}  // namespace tsuchi::io
