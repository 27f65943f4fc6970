#pragma once
// Checkpoints: the whole state of a run in one file, so that a run stopped by a kill, a fault or
// the end of a batch slot continues bit for bit. The layout is documented in docs/checkpoint.md:
// a header (magic, version, dimension, input fingerprint, particle count), named sections of raw
// little-endian arrays, and a CRC-32 of everything before it.
//
// What is saved: every particle array (Particles::for_each_array), the time and step counter, the
// output counters, the frames listed in the .pvd and the length and CRC-32 of the CSVs so far. Nothing else
// carries over between steps: the grid is rebuilt from the particles every step, and the random
// imperfection is drawn once at the start and lives in the particles' strength factors.
#include "tsuchi/io/output_writer.hpp"
#include "tsuchi/model/model.hpp"

#include <cstdint>
#include <functional>
#include <vector>
#include <string>
#include <string_view>

namespace tsuchi {

// 2: the CSV files are named by their length and CRC-32 instead of held whole.
// 3: particle ids are 64-bit; the material state is saved column by column under the names of the
//    state fields (p.yield_mode, p.plastic_shear_strain, ...), every column a double.
// 4: the particles' APIC affine matrix, p.C (D x D doubles, zero with the FLIP transfer).
// 5: the stage of a staged run (its index, whether it has ended, the start time and step of every
//    stage so far, the largest kinetic energy of the stage, its first frame), stages.csv's length
//    and CRC-32, and the particles and forces of the surface loads (a stage builds them on the
//    particles of its start, which a restart no longer has).
//    A run with an equilibrium stage judged at rest (run/stage_rest.hpp) adds its window: sections
//    rest.anchor (D doubles per particle id, Model::id_count of them), rest.largest and
//    rest.ratio_start; a checkpoint without them (written before they were) restarts inside such a
//    stage with a fresh window (run/simulation.cpp warns).
inline constexpr std::uint32_t checkpoint_version = 5;

// The time loop's own state at the end of a step.
struct RunProgress {
  double time = 0.0;
  std::int64_t steps = 0;
  double dt = 0.0;                 // the last step's size
  std::int64_t frame_index = 1;    // index of the next scheduled frame time
  std::int64_t row_index = 1;      // index of the next scheduled global.csv row
  std::int64_t label_index = 0;    // k of the next frame by recorder value, k * output.label_interval
  double last_frame = 0.0, last_row = 0.0;  // times of the last frame and row written
  OutputHistory output;
  // Staged runs (docs/stages.md); a single-stage run is stage 0 throughout.
  std::int64_t stage = 0;
  bool stage_done = false;                  // saved at the end of `stage`: a restart begins the next one
  std::vector<double> stage_starts;         // start time of each stage up to `stage`
  std::vector<std::int64_t> stage_start_steps;
  double stage_peak_kinetic = 0.0;          // the largest kinetic energy of the stage so far (J)
  std::int64_t stage_first_frame = 0;       // the stage's first frame, for its .pvd
  // The rest window of an equilibrium stage (run/stage_rest.hpp RestWindow), saved when `rest`.
  bool rest = false;
  std::vector<double> rest_anchor;
  double rest_largest = 0.0, rest_ratio_start = 0.0;
};

// Writes atomically (temporary file, then rename); throws OutputError.
template <int D>
void write_checkpoint(const std::string& path, const Model<D>& model, const RunProgress& progress);

// Reads a checkpoint into `model` (built from the same input) and returns the loop state. Throws
// InputError naming the file and what is wrong: not a checkpoint, another version, dimension or
// input, a bad checksum, or a truncated or inconsistent content. The model is untouched then.
// For a staged run, `before_particles` is called with the loop state before the particles are
// read: it brings the model to the checkpoint's stage (model/stage_change.hpp, restore_stage).
template <int D>
RunProgress read_checkpoint(const std::string& path, Model<D>& model,
                            const std::function<void(const RunProgress&)>& before_particles = {});

// The same from bytes in memory; `verify_checksum` is false only for fuzzing, which could not
// otherwise get past the checksum to the parser.
template <int D>
RunProgress decode_checkpoint(std::string_view bytes, const std::string& source, Model<D>& model,
                              bool verify_checksum = true,
                              const std::function<void(const RunProgress&)>& before_particles = {});

extern template void write_checkpoint<2>(const std::string&, const Model<2>&, const RunProgress&);
extern template void write_checkpoint<3>(const std::string&, const Model<3>&, const RunProgress&);
extern template RunProgress read_checkpoint<2>(const std::string&, Model<2>&, const std::function<void(const RunProgress&)>&);
extern template RunProgress read_checkpoint<3>(const std::string&, Model<3>&, const std::function<void(const RunProgress&)>&);
extern template RunProgress decode_checkpoint<2>(std::string_view, const std::string&, Model<2>&, bool, const std::function<void(const RunProgress&)>&);
extern template RunProgress decode_checkpoint<3>(std::string_view, const std::string&, Model<3>&, bool, const std::function<void(const RunProgress&)>&);

}  // namespace tsuchi
