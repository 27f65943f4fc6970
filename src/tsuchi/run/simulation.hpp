#pragma once
// The time loop of a run: picks each step's dt, steps, and hands results to the output writer on
// schedule. Output times and the end time are hit exactly (the step before is shortened).
#include "tsuchi/io/output_writer.hpp"
#include "tsuchi/model/config.hpp"
#include "tsuchi/model/model.hpp"
#include "tsuchi/solver/explicit_step.hpp"

#include <functional>
#include <optional>
#include <string>

namespace tsuchi {

struct Progress {
  std::int64_t step = 0;
  double time = 0.0;
  double end_time = 0.0;
  double dt = 0.0;
  std::size_t frames = 0;
  // How far the run is, 0 to 1: by time, or by a recorder's way from its start value to its stop
  // bound when that is further along (a run a recorder will stop long before time.end).
  double fraction = 0.0;
  std::string leader;  // the recorder that gives `fraction`, or "" when the time does
  double leader_value = 0.0, leader_bound = 0.0;
  // Staged runs: the stage (1-based) of `stages` and its name; `fraction` is then the stage's.
  int stage = 1, stages = 1;
  std::string stage_name;
};

// How a stage of a staged run ended: its row of stages.csv (io/output_writer.hpp), and for messages
// the number of stages and whether it was to end in equilibrium.
struct StageReport : StageRow {
  int stages = 1;
  bool equilibrium_asked = false;
  // Ended in equilibrium: by its ratios, or at rest on the ratio's floor (run/stage_rest.hpp).
  bool reached_equilibrium() const { return end == "equilibrium" || end == "at rest"; }
};

struct RunOptions {
  std::optional<std::string> output_directory;     // overrides output.directory
  std::function<void(const Progress&)> on_progress;  // called after every step
  bool write_output = true;
  std::optional<std::string> restart;  // checkpoint to continue from
  // The command that continues this run from its checkpoint, less the checkpoint: the program,
  // the input, -o and every --set of this run ("tsuchi run m.toml -o out --set ..."), for messages.
  std::string resume_command = "tsuchi run ...";
  std::function<void(const StageReport&)> on_stage_end;  // staged runs: after each stage
  // A warning the run meets on the way (a frame label that does not grow), said once each.
  std::function<void(const std::string&)> on_warning;
  // Stop after this stage (0-based) of a staged run; -1: run them all (`tsuchi fos` stops after its stage).
  int last_stage = -1;
};

struct RunSummary {
  std::int64_t steps = 0;        // the step count at the end (a restart's included)
  std::int64_t steps_taken = 0;  // the steps this process took: steps less a restart's
  double time = 0.0;
  double wall_seconds = 0.0;
  std::size_t frames = 0;
  std::string directory;
  std::string stopped_by;  // the recorder bound that ended the run early, if one did
  std::string checkpoint;  // the final checkpoint, when the input asks for checkpoints
  std::vector<StageReport> stages;  // staged runs: the stages ended by this process
};

// A word for a POSIX shell: as it is when it holds nothing the shell would read, else in single
// quotes (for the commands that messages suggest).
std::string shell_word(const std::string& word);

// Where the checkpoint of a run writing to `output_directory` goes.
std::string checkpoint_path(const Config& config, const std::string& output_directory);

// The step size for the next step from the time settings and the current critical step;
// throws InputError (at step 0) or RunError (later) if a fixed dt exceeds the stable limit, and
// InputError at step 0 if time.courant is to scale a stable step above max_stable_step.
double next_time_step(const TimeConfig& time, double dt_crit, std::int64_t step, const std::string& source);

// How long a run is: steps and frames from `from_time` to time.end with a first step `dt`,
// counting the shortened steps that land on every frame time, and time.max_steps when set.
struct RunLength {
  double steps = 0.0;
  double frames = 0.0;
};
RunLength estimate_run_length(const Config& config, double dt, double from_time = 0.0);

// When a recorder's stop bound will end the run, where that is foreseeable: a recorder of the
// displacement of a body whose velocity along that axis is prescribed (a platen) changes at a known
// rate. The earliest such time before time.end, or nothing.
struct StopForecast {
  double time = 0.0;
  std::string recorder;
  double bound = 0.0;
};
std::optional<StopForecast> forecast_stop(const Config& config);

// A stage's equilibrium (and a factor-of-safety trial's) is judged from its this-many-th step on.
inline constexpr std::int64_t equilibrium_first_step = 20;

// Without time.max_steps a run may take at most this many steps; and no run more frames than this.
inline constexpr double default_step_limit = 1e8;
// A stable step above this (11.6 days; soil's is micro- to milliseconds) means a material without
// stiffness for its density, not a slow wave.
inline constexpr double max_stable_step = 1e6;
inline constexpr double frame_limit = 1e5;

// Refuses (InputError) a run that cannot finish: more steps than default_step_limit without an
// explicit time.max_steps, or more frames than frame_limit; counted to the forecast stop when
// there is one.
void check_run_length(const Config& config, double dt, double from_time = 0.0);

// Runs `model`, built from `config`, under the config's time, output, checkpoint and recorder
// settings.
template <int D>
RunSummary run_simulation(Model<D>& model, const Config& config, const RunOptions& options,
                          const std::function<void(const ExplicitSolver<D>&)>& after_step = {});

extern template RunSummary run_simulation<2>(Model<2>&, const Config&, const RunOptions&,
                                             const std::function<void(const ExplicitSolver<2>&)>&);
extern template RunSummary run_simulation<3>(Model<3>&, const Config&, const RunOptions&,
                                             const std::function<void(const ExplicitSolver<3>&)>&);

}  // namespace tsuchi
