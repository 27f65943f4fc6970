#pragma once
// The input's [[functions]]: named functions of time that loads are multiplied by
// (core/time_function.hpp, docs/input.md "[[functions]]").
#include "tsuchi/io/toml_section.hpp"

namespace tsuchi::io {

// Reads every [[functions]] table of `top` into c.functions (and their files' digests).
void read_functions(Section& top, Config& c);

// The index in c.functions of the function named by `key` (a string), or -1 when the key is absent.
int read_function_ref(Section& s, std::string_view key, const Config& c);

}  // namespace tsuchi::io
