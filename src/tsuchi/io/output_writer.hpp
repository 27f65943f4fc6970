#pragma once
// The files a run writes into its output directory:
//   particles_NNNNNN.vtu  one frame per output interval (binary VTK XML)
//   particles.pvd         the time series ParaView opens, listing only complete frames
//   grid_NNNNNN.vtu       with output.grid_fields: the frame's fields on the grid nodes
//   grid.pvd              their time series, at the times of particles.pvd (io/grid_vtu_writer.hpp)
//   global.csv            time series of whole-model quantities
//   recorders.csv         time series of the input's recorders (when it has any), same rows
//   stages.csv            staged runs: a row per stage ended (docs/stages.md), and
//   particles_stageN.pvd  the frames of stage N (grid_stageN.pvd their grid frames); global.csv and
//                         recorders.csv get a `stage` column
// Frames and the .pvd are replaced atomically; the CSVs grow by whole rows. A run holds a lock on
// the directory (io/output_lock.hpp), and removes the frames of an earlier run there, so that
// the directory only ever shows one run.
#include "tsuchi/io/appended_file.hpp"
#include "tsuchi/io/output_lock.hpp"
#include "tsuchi/io/vtu_writer.hpp"
#include "tsuchi/model/model.hpp"

#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace tsuchi {

// What the files above hold so far: the frames listed in the .pvd, and how far each CSV goes
// (its length in bytes and the CRC-32 of those bytes). A checkpoint saves it, a restart checks the
// files against it and continues them.
struct OutputHistory {
  std::vector<std::pair<double, std::string>> frames;  // (time, file name) listed in the .pvd
  std::uint64_t global_bytes = 0, recorder_bytes = 0;  // recorder_*: 0 when the input has no recorders
  std::uint32_t global_crc = 0, recorder_crc = 0;
  std::uint64_t stages_bytes = 0;  // stages.csv; 0 for a single-stage run
  std::uint32_t stages_crc = 0;
};

// A row of stages.csv: how a stage went (run/simulation.hpp's StageReport adds to it).
struct StageRow {
  int stage = 0;  // 1-based
  std::string name, end;  // end: what ended it ("duration", "steps", "equilibrium", "max_steps", ...)
  double start_time = 0.0, end_time = 0.0;
  std::int64_t start_step = 0, end_step = 0;
  double unbalanced_force_ratio = 0.0, kinetic_energy_ratio = 0.0;
  std::int64_t first_frame = 0, last_frame = -1;  // indices of the stage's frames (none: last < first)
};

// particles_NNNNNN.vtu (six or more digits): the name of a frame file.
bool is_frame_file_name(const std::string& name);
// grid_NNNNNN.vtu (six or more digits): the name of a grid frame file.
bool is_grid_frame_file_name(const std::string& name);
// A file a run writes or removes in its output directory: a frame, a .pvd, a CSV, the lock.
bool is_output_file_name(const std::string& name);

// Refuses (InputError naming the file, line and key) an output that would overwrite the input
// file, a data file it reads or another output of the run: the checkpoint file named as one of
// those, as a directory or a device, or an input or data file inside the output directory under
// the name of a file the run writes or removes there.
void check_output_paths(const Config& config, const std::string& directory, const std::string& checkpoint);

// What global.csv takes from the solver about the step that ends at a row's time.
struct StepReport {
  double unbalanced_force_ratio = std::numeric_limits<double>::quiet_NaN();  // nan before the first step
  std::int64_t released_particles = 0;  // expansions held by solver.hold_released_volume
  std::int64_t contact_nodes = -1;      // nodes where contact acted; -1: the model has no contact (no column)
};

template <int D>
class OutputWriter {
 public:
  // Creates the directory, locks it and starts the files; with `resume`, continues the files of a
  // checkpointed run instead (InputError when they are not there as the checkpoint left them).
  // recorders.csv gets a column per name in `recorder_names` (none: no file).
  // With `staged`, the CSVs get a stage column and stages.csv is written (stage_row). global.csv has
  // a contact_nodes column when the model has contact, or `contact_later` (a stage starts it).
  OutputWriter(const Model<D>& model, const OutputConfig& output, std::string directory,
               std::vector<std::string> recorder_names, const OutputHistory* resume = nullptr, bool staged = false,
               bool contact_later = false);

  // The stage the next rows belong to (1-based), for a staged run.
  void set_stage(int stage) { stage_ = stage; }
  // A row of stages.csv, and particles_stageN.pvd with the stage's frames.
  void stage_row(const StageRow& row);

  // A frame of the particles; `label` is its time in the .pvd (the time, or the value of the
  // output.frame_label recorder). With `contact`, also contact_NNNNNN.vtu and contact.pvd: the
  // grid nodes where contact acted in the step that ended at the frame.
  void frame(double label, const ContactPoints* contact = nullptr);
  // A row of global.csv, and of recorders.csv with the recorders' values (in the order of the names).
  void global_row(double time, std::int64_t step, double dt, const StepReport& report,
                  const std::vector<double>& recorder_values);
  // Writes the queued CSV rows to the files (done with every frame, at the end of a run and by the
  // run loop every half minute); with `sync`, also to disk, as before a checkpoint.
  void flush_global(bool sync = false);

  const std::string& directory() const { return dir_; }
  std::size_t frames_written() const { return h_.frames.size(); }
  // The label (.pvd time) of the last frame written, if any.
  std::optional<double> last_label() const {
    return h_.frames.empty() ? std::nullopt : std::optional<double>(h_.frames.back().first);
  }
  // The history for a checkpoint: call flush_global(true) first.
  OutputHistory history() const;

 private:
  const Model<D>& m_;
  OutputConfig output_;
  std::string dir_;
  DirectoryLock lock_;
  OutputHistory h_;
  // (label, file) of the grid frames grid.pvd lists: those of h_.frames that have one. Not in the
  // checkpoint: a restart finds them from the files (a restart may switch grid_fields on).
  std::vector<std::pair<double, std::string>> grid_frames_;
  std::vector<std::string> recorders_;
  bool view_written_ = false;  // particles_view.py, with this process's first frame
  // The frames with a contact_NNNNNN.vtu (those of the stages with contact), for contact.pvd.
  std::vector<std::pair<double, std::string>> contact_frames_;
  bool contact_column_ = false;  // global.csv's contact_nodes
  AppendedFile global_, recorder_file_, stages_file_;
  bool staged_ = false;
  int stage_ = 1;
};

extern template class OutputWriter<2>;
extern template class OutputWriter<3>;

}  // namespace tsuchi
