#pragma once
// Reading [[stages]] (docs/stages.md). A stage changes parts of the input at its start: its tables
// `model` (gravity), `solver`, `time` (the step), `boundary`, `loads`, `materials.NAME`
// and `bodies.NAME` (motion and material) are merged into the file's own, tables key by key and
// arrays whole, and stay in force for the later stages. The input as it stands during stage k is
// then read like any input, so every value a stage sets is checked as the file's own are.
#include "tsuchi/io/toml_section.hpp"
#include "tsuchi/model/config.hpp"

#include <toml++/toml.h>

#include <cstddef>
#include <string>

namespace tsuchi::io {

// The number of [[stages]] tables of an input (0 when it has none); InputError unless `stages` is
// an array of tables.
std::size_t stage_count(const toml::table& root, const std::string& file);

// `root` with the changes of stages 0..last merged in and `stages` taken out: the input as it stands
// during stage `last`. Refuses (InputError naming the stage and key) a change a stage cannot make
// and a material or body that the input does not define.
toml::table merge_stages(toml::table root, std::size_t last, const std::string& file);

// Stage k's own keys (its name, end, bodies and parts of bodies removed and added, reset), with
// `during` the input as it stands in stage k (its bodies and recorders; a file a region's shape reads
// and a warning about it are added to it), and the parts of the input it changes.
StageConfig read_stage(const toml::table& root, std::size_t k, Config& during, const std::string& file);

// Checks the stages as a sequence: names unique, no reset in the first stage, a body added while
// absent (whole once, or by parts in any number of stages until then) and removed (whole once, or
// by parts) while present. Sets Config::body_starts_dormant.
void check_stage_sequence(Config& c, const toml::table& root);

// [fos] of the input (after the stages are read: it names one).
void read_fos(Section& top, Config& c);

}  // namespace tsuchi::io
