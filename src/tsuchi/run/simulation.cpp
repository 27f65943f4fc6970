#include "tsuchi/run/simulation.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/core/interrupt.hpp"
#include "tsuchi/io/atomic_file.hpp"
#include "tsuchi/io/checkpoint.hpp"
#include "tsuchi/io/output_writer.hpp"
#include "tsuchi/model/stage_change.hpp"
#include "tsuchi/run/recorder.hpp"
#include "tsuchi/run/stage_rest.hpp"
#include "tsuchi/solver/global_quantities.hpp"
#include "tsuchi/solver/time_step.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <string_view>
#include <cmath>
#include <limits>
#include <optional>

namespace tsuchi {

double next_time_step(const TimeConfig& time, double dt_crit, std::int64_t step, const std::string& source) {
  if (std::isnan(dt_crit))
    throw RunError("got a non-finite velocity, volume or mass; the run is unstable there: reduce time.courant or "
                   "time.dt, add solver.damping, or check the material parameters",
                   Fault::NonFinite);
  if (time.courant) {
    // A model whose fastest wave takes ages to cross a cell (no stiffness for its density: E = 1e-300,
    // density 1e308, a Cam-Clay soil at zero pressure) gives a step that is no bound at all: the
    // whole run would be one step, and the fault that follows would blame the step.
    if (step == 0 && !(dt_crit <= max_stable_step))
      throw InputError(fmt::format(
          "{}: the stable time step is {:.3g} s (cell size / P-wave speed), above {:.0e} s: the materials carry "
          "almost no signal across a cell, so time.courant bounds nothing and the run would be one step; check the "
          "moduli (Pa), the densities (kg/m^3) and, for a pressure-dependent soil, its initial stress",
          source, dt_crit, max_stable_step));
    return *time.courant * dt_crit;
  }
  if (*time.dt > dt_crit) {
    // --set cannot remove time.dt from the file, so the advice that works from the command line
    // is a smaller time.dt; time.courant needs an edit of the file.
    // Half the step, or less when that is still above 0.9 of the limit: a limit that fell during a
    // run (particles speeding up) may go on falling. The restart command of a fault names the same.
    const double smaller = std::min(0.5 * *time.dt, 0.9 * dt_crit);
    const std::string msg = fmt::format(
        "time.dt = {:.6g} s is above the stable limit {:.6g} s (cell size / (P-wave speed + particle speed)); set "
        "a smaller time.dt (--set time.dt={:.3g}), or replace time.dt by time.courant in {}",
        *time.dt, dt_crit, smaller, source);
    if (step == 0)
      throw InputError(time.dt_where.empty() ? fmt::format("{}: {}", source, msg)
                                             : fmt::format("{}: key 'time.dt': {}", time.dt_where, msg));
    RunError e(msg, Fault::UnstableStep);
    e.suggested_dt = smaller;
    throw e;
  }
  return *time.dt;
}

RunLength estimate_run_length(const Config& c, double dt, double from_time) {
  const double end = c.time.end, interval = c.output.interval;
  const double span = std::max(0.0, end - from_time);
  // A stretch of length L takes ceil(L / dt) steps: the last one is shortened onto its end (or the
  // last two split it), as the time loop does.
  auto steps_over = [&](double L) { return L <= dt * (1.0 + 1e-6) ? (L > 0.0 ? 1.0 : 0.0) : std::ceil(L / dt - 1e-9); };
  RunLength r;
  if (interval > 0.0 && interval < end) {
    const double first = std::floor(from_time / interval) + 1.0;  // the first frame time k * interval after now
    const double last = std::ceil(end / interval * (1.0 - 1e-12)) - 1.0;  // the last one before end
    const double full = std::max(0.0, last - first);
    const double lead = std::min(first * interval, end) - from_time;
    const double tail = end - std::max(last * interval, from_time);
    r.steps = full > 0.0 || last >= first ? steps_over(lead) + full * steps_over(interval) + steps_over(tail)
                                          : steps_over(span);
    r.frames = (from_time > 0.0 ? 0.0 : 1.0) + std::max(0.0, last - first + 1.0) + 1.0;
  } else {
    r.steps = steps_over(span);
    r.frames = from_time > 0.0 ? 1.0 : 2.0;
  }
  if (c.time.max_steps > 0 && r.steps > static_cast<double>(c.time.max_steps)) {
    r.steps = static_cast<double>(c.time.max_steps);
    r.frames = std::min(r.frames, r.steps + 1.0);
  }
  if (!c.output.write_frames) r.frames = 0.0;
  return r;
}

std::optional<StopForecast> forecast_stop(const Config& c) {
  std::optional<StopForecast> best;
  for (const auto& r : c.recorders) {
    if (r.body < 0 || r.quantity.size() != 14 || r.quantity.rfind("displacement_", 0) != 0) continue;
    const int d = r.quantity.back() - 'x';
    const BodyConfig& b = c.bodies[static_cast<std::size_t>(r.body)];
    if (d < 0 || d >= c.dimension || !b.prescribed[d]) continue;
    if (b.prescribed_velocity_function >= 0) continue;  // v0 f(t): no constant rate to forecast by
    if (std::any_of(b.prescribed_gradient[d].begin(), b.prescribed_gradient[d].end(), [](double g) { return g != 0.0; }))
      continue;
    // Every particle of the body moves at v0 from t = 0: the column is scale * v0 * t + offset
    // whatever the reduction (the sum scales with the particle count: left out).
    if (r.reduction == RecorderConfig::Reduction::Sum) continue;
    const double rate = r.scale * b.prescribed_velocity[d];
    for (const auto& bound : {r.stop_above, r.stop_below}) {
      if (!bound || rate == 0.0) continue;
      const double t = (*bound - r.offset) / rate;
      const bool ahead = bound == r.stop_above ? rate > 0.0 : rate < 0.0;
      if (ahead && t > 0.0 && t < c.time.end && (!best || t < best->time)) best = StopForecast{t, r.name, *bound};
    }
  }
  return best;
}

void check_run_length(const Config& config, double dt, double from_time) {
  Config c = config;
  if (const auto stop = forecast_stop(config)) c.time.end = stop->time;
  const RunLength r = estimate_run_length(c, dt, from_time);
  if (c.time.max_steps == 0 && r.steps > default_step_limit)
    throw InputError(fmt::format(
        "{}: the run would take about {:.3g} steps of {:.3g} s to time.end = {} s{}, more than the {:.0e} a run "
        "takes without time.max_steps: check time.end, time.dt{}, the moduli and densities; or set time.max_steps "
        "to the number of steps you mean to allow",
        c.source, r.steps, dt, c.time.end,
        c.output.interval > 0.0 && c.output.interval < c.time.end
            ? fmt::format(" with a frame every output.interval = {} s", c.output.interval)
            : std::string{},
        default_step_limit, c.output.interval > 0.0 ? ", output.interval" : ""));
  if (r.frames > frame_limit)
    throw InputError(fmt::format("{}: the run would write about {:.3g} frames (output.interval = {} s to time.end = "
                                 "{} s), more than {:.0e}; choose a larger output.interval",
                                 c.source, r.frames, c.output.interval, c.time.end, frame_limit));
}

std::string shell_word(const std::string& w) {
  const bool plain = !w.empty() && std::all_of(w.begin(), w.end(), [](unsigned char ch) {
    return std::isalnum(ch) || std::string_view("/._-+=,:@%").find(static_cast<char>(ch)) != std::string_view::npos;
  });
  if (plain) return w;
  std::string r = "'";
  for (const char ch : w) r += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return r + "'";
}

template <int D>
StepReport step_report(const ExplicitSolver<D>& solver) {
  return {solver.unbalanced_force_ratio(), solver.released_particles(), solver.contact_node_count()};
}

std::string checkpoint_path(const Config& config, const std::string& output_directory) {
  const std::string& f = config.checkpoint.file;
  return f.front() == '/' ? f : output_directory + "/" + f;
}

namespace {

// When the functions of time that stage k sets stop changing (model/stage_change.hpp): its
// equilibrium is judged only after that, so that a slow ramp of gravity or of a load is not taken
// for equilibrium.
template <int D>
double stage_settles_at(const Model<D>& m, const Config& run, std::size_t k) {
  double t = -std::numeric_limits<double>::infinity();
  const bool all = !run.staged() || k == 0;
  const StageConfig* st = run.staged() ? &run.stages[k] : nullptr;
  if (all || st->sets_gravity_function) t = std::max(t, m.step.gravity_function.settles_at());
  if (all || st->changes_loads) {
    for (const auto& l : m.loads.surface) t = std::max(t, l.function.settles_at());
    for (const auto& l : m.loads.nodal) t = std::max(t, l.function.settles_at());
    for (const auto& l : m.loads.body) t = std::max(t, l.function.settles_at());
  }
  if (all || st->sets_node_sets)
    for (const auto& n : m.node_sets) t = std::max(t, n.f.settles_at());
  for (std::size_t b = 0; b < m.motion.size(); ++b)
    if (all || std::find(st->changes_motion.begin(), st->changes_motion.end(), static_cast<int>(b)) != st->changes_motion.end())
      t = std::max(t, m.motion[b].function.settles_at());
  return t;
}

}  // namespace

template <int D>
RunSummary run_simulation(Model<D>& model, const Config& config, const RunOptions& options,
                          const std::function<void(const ExplicitSolver<D>&)>& after_step) {
  using clock = std::chrono::steady_clock;
  const auto wall_start = clock::now();
  const OutputConfig& oc = config.output;
  const CheckpointConfig& kc = config.checkpoint;
  const bool staged = config.staged();
  const std::size_t last_stage = staged ? (options.last_stage >= 0 ? static_cast<std::size_t>(options.last_stage)
                                                                   : config.stages.size() - 1)
                                        : 0;
  // The stage being run: its input (its time step settings) and its end. A single-stage run is
  // stage 0, which ends at time.end or time.max_steps.
  std::size_t stage = 0;
  auto stage_config = [&]() -> const Config& { return staged ? *config.stages[stage].config : config; };
  double end = staged ? std::numeric_limits<double>::infinity() : config.time.end;

  std::optional<ExplicitSolver<D>> solver;
  solver.emplace(model);
  const std::string dir = options.output_directory.value_or(oc.directory);
  const std::string ck_path = checkpoint_path(config, dir);
  // Particle sets are chosen on the initial state, before a checkpoint replaces it.
  std::vector<Recorder<D>> recorders = make_recorders<D>(config, model);
  std::vector<std::string> recorder_names;
  for (const auto& r : recorders) recorder_names.push_back(r.config().name);
  std::vector<double> recorder_values(recorders.size());
  auto recorder_row = [&]() -> const std::vector<double>& {
    for (std::size_t k = 0; k < recorders.size(); ++k) recorder_values[k] = recorders[k].value(*solver);
    return recorder_values;
  };
  // Where each recorder with a stop bound starts (the initial state, also for a restart), for the
  // progress it makes towards the bound.
  std::vector<double> recorder_start(recorders.size(), 0.0);
  for (std::size_t k = 0; k < recorders.size(); ++k)
    if ((recorders[k].config().stop_above || recorders[k].config().stop_below) && !recorders[k].from_solver())
      recorder_start[k] = recorders[k].value(*solver);
  if (options.write_output) check_output_paths(config, dir, ck_path);
  RunProgress start;
  bool fresh_rest_window = false;  // a restart inside a stage judged at rest, from a checkpoint without its window
  if (options.restart) {
    start = read_checkpoint<D>(*options.restart, model, [&](const RunProgress& r) {
      if (staged) restore_stage(model, config, static_cast<std::size_t>(r.stage), r.stage_starts);
    });
    for (auto& r : recorders) r.rebind(model);
    // Past the end there is nothing to run, and a last frame there would lie beyond time.end.
    if (!staged && start.time > end * (1.0 + 1e-12))
      throw InputError(fmt::format("{}: the checkpoint {} is at t = {:.9g} s, past time.end = {:.9g} s: nothing to "
                                   "run; give a later time.end (--set time.end=...)",
                                   config.source, *options.restart, start.time, end));
    if (staged && start.stage_done && static_cast<std::size_t>(start.stage) >= last_stage)
      throw InputError(fmt::format("{}: the checkpoint {} is at the end of the last stage (\"{}\", t = {:.9g} s): "
                                   "nothing to run",
                                   config.source, *options.restart, config.stages[static_cast<std::size_t>(start.stage)].name,
                                   start.time));
    stage = static_cast<std::size_t>(start.stage);
    // Inside a stage judged at rest, the window is state (run/stage_rest.hpp). A checkpoint of an
    // earlier version has none: the verdict starts afresh there (below), said in a warning.
    fresh_rest_window = staged && !start.stage_done && config.stages[stage].end.judged_at_rest() &&
                        (!start.rest || start.rest_anchor.size() != static_cast<std::size_t>(model.id_count) * D);
    solver->resume(start.time, start.steps);
  }
  // Check the first step before anything is written: a refused dt leaves the directory untouched.
  double dt = next_time_step(stage_config().time,
                             critical_time_step<D>(model.particles, model.materials, model.grid.h), 0, config.source);
  if (!staged) check_run_length(config, dt, start.time);
  if (options.restart && start.steps > 0) dt = start.dt;  // only for a final row; every later step recomputes it

  std::optional<OutputWriter<D>> out;
  if (options.write_output) {
    out.emplace(model, oc, dir, recorder_names, options.restart ? &start.output : nullptr, staged,
                contact_in_some_stage(model, config));
    out->set_stage(static_cast<int>(stage) + 1);
    prepare_checkpoint_directory(ck_path);  // a checkpoint hours later must not be the first to find it unwritable
  }
  // Frames are labelled by time, or by the value of the output.frame_label recorder.
  const Recorder<D>* label = oc.frame_label_recorder >= 0 ? &recorders[static_cast<std::size_t>(oc.frame_label_recorder)] : nullptr;
  bool label_warned = false;
  auto write_frame = [&](double time) {
    ContactPoints points;
    const bool contact = model.contact.active();  // a stage may start or end it
    if (contact)
      for (const auto& n : solver->contact_nodes()) {
        std::array<double, 3> x{}, normal{}, force{};
        for (int d = 0; d < D; ++d) x[d] = n.x[d], normal[d] = n.normal[d], force[d] = n.force[d];
        points.x.push_back(x), points.normal.push_back(normal), points.force.push_back(force), points.kind.push_back(n.kind);
      }
    const double value = label ? label->value(*solver) : time;
    // ParaView orders a .pvd's frames by their time: labels that fall back or repeat play the
    // frames out of the run's order (or hide one behind another). Written as asked, said once.
    if (label && !label_warned && out->last_label() && !(value > *out->last_label()) && options.on_warning) {
      label_warned = true;
      options.on_warning(fmt::format(
          "frame {} is labelled {:.6g} by recorder \"{}\" (output.frame_label), not above the {:.6g} of the frame "
          "before: ParaView orders the frames of the .pvd by label, so they will not play in the order of the run; "
          "label the frames by a recorder that grows (docs/input.md, [output])",
          out->frames_written(), value, oc.frame_label, *out->last_label()));
    }
    out->frame(value, contact ? &points : nullptr);
  };
  if (out && !options.restart) {
    out->global_row(0.0, 0, 0.0, step_report(*solver), recorder_row());
    write_frame(0.0);
  }
  std::string stopped_by;
  std::int64_t frame_index = start.frame_index, row_index = start.row_index, label_index = start.label_index;
  // Frames by a recorder's value (output.label_interval): one after the step that passes each
  // multiple k * label_interval, as rows of global.csv follow global_interval.
  auto label_due = [&](double value) {
    return label && oc.label_interval > 0.0 && value >= oc.label_interval * static_cast<double>(label_index);
  };
  auto next_label = [&](double value) {
    label_index = static_cast<std::int64_t>(std::floor(value / oc.label_interval)) + 1;
  };
  if (!options.restart && label && oc.label_interval > 0.0) next_label(label->value(*solver));
  // Frame k at k * interval, the run's end once that lies beyond it. An end that is a frame time
  // up to rounding (time.end = 0.3 with interval 0.1, where 3 * 0.1 = 0.30000000000000004) is
  // reached by landing on the frame time itself: then a run to that end stops at the very time
  // and state that a run to a later end passes through, and a restart from its end-of-run
  // checkpoint with a later time.end continues without a sliver of a step to the frame time.
  auto frame_time = [&](std::int64_t k) {
    if (!(oc.interval > 0)) return end;
    const double t = static_cast<double>(k) * oc.interval;
    return t <= end * (1.0 + 1e-12) ? t : end;
  };
  // The frame after those reached at time `now`: a frame within 1e-6 of the step `step` of it
  // counts as reached (above the round-off of summing thousands of steps). The step loop and a
  // restart's first step both take this rule, so a restart skips exactly the frames the
  // uninterrupted run had written.
  auto frame_after = [&](double now, double step) {
    while (frame_time(frame_index) <= now + 1e-6 * step && frame_time(frame_index) < end) ++frame_index;
    return frame_time(frame_index);
  };
  // A restart's counters are the indices of the next frame and global.csv row. The run that wrote
  // the checkpoint left each at most one past the last time k * interval reached, a time within
  // 1e-6 of a step counting as reached (frame_after, the row rule of the step loop). A larger one (a
  // crafted checkpoint: 2^62 wrote no more frames; a restart with a longer interval, the stored
  // index counting in the old one) is brought back to that bound, and frame_after and the step loop
  // advance it from there; a counter within it is kept, so a fair restart goes on bit for bit.
  if (options.restart) {
    auto bound = [&](double interval, std::int64_t& index) {
      if (!(interval > 0.0)) return;
      const double now = solver->time(), tol = 1e-6 * std::max(interval, start.dt);
      const double k = std::floor((now + tol) / interval) + 1.0;
      if (k < static_cast<double>(index)) index = static_cast<std::int64_t>(k);
    };
    bound(oc.interval, frame_index);
    bound(oc.global_interval, row_index);
    // The label counter follows a recorder's value, which need not grow (the run warns when it does
    // not), so no bound on it is sure to keep a fair restart as it was: left as read.
  }
  double last_frame = start.last_frame, last_row = start.last_row;
  auto last_flush = clock::now();
  auto last_checkpoint = clock::now();
  std::pair<std::int64_t, std::string> saved{-1, ""};  // step and file of the latest checkpoint
  if (options.restart) saved = {start.steps, *options.restart};
  const auto checkpoint_wall = std::chrono::duration<double>(60.0 * kc.every_minutes);

  // The stage's own bookkeeping (RunProgress keeps it in a checkpoint).
  std::vector<double> stage_starts = start.stage_starts;
  std::vector<std::int64_t> stage_start_steps = start.stage_start_steps;
  double peak_kinetic = start.stage_peak_kinetic;
  // The rest verdict of equilibrium stages (run/stage_rest.hpp), kept in a checkpoint when some
  // stage takes it.
  const bool rest_judged = staged && std::any_of(config.stages.begin(), config.stages.end(),
                                                 [](const StageConfig& s) { return s.end.judged_at_rest(); });
  const std::int64_t rest_window = rest_window_steps(model.grid);
  RestWindow rest;
  rest.anchor = start.rest_anchor, rest.largest = start.rest_largest, rest.ratio_start = start.rest_ratio_start;
  if (fresh_rest_window) {
    // The movement before the restart is unknown: the windows from here are judged against the
    // largest of their own, so a ground already still may run on to the stage's other ends.
    rest.largest = 0.0;
    open_rest_window(model, std::numeric_limits<double>::quiet_NaN(), rest);
    if (options.on_warning)
      options.on_warning(fmt::format(
          "{}: the checkpoint holds no rest window for stage {} \"{}\" (written by an earlier version of tsuchi): "
          "its at-rest verdict starts afresh at step {}, judged on the movement from there on; the stage may end "
          "later than the run would have, or by its max_steps",
          *options.restart, stage + 1, config.stages[stage].name, start.steps));
  }
  std::int64_t stage_first_frame = start.stage_first_frame;
  bool stage_done = false;
  double settles = -std::numeric_limits<double>::infinity();
  std::int64_t step_limit = 0;  // absolute step count at which the stage (or run) stops; 0: none
  // What the step limit is, once reached: the stage's step count, or its (or the run's) maximum.
  auto step_limit_end = [&]() -> std::string {
    const bool by_steps = staged && config.stages[stage].end.steps > 0 &&
                          solver->steps() >= stage_start_steps[stage] + config.stages[stage].end.steps;
    return by_steps ? "steps" : "max_steps";
  };
  double latest_kinetic_ratio = std::numeric_limits<double>::quiet_NaN();
  std::vector<StageReport> reports;

  // The state at the end of a step, before any end-of-run extras, so that a restart from it
  // continues exactly as the run would have.
  auto save = [&] {
    if (!out) return;
    out->flush_global(true);  // the rows the checkpoint names are on disk before it
    RunProgress now;
    now.time = solver->time(), now.steps = solver->steps(), now.dt = dt;
    now.frame_index = frame_index, now.row_index = row_index, now.label_index = label_index;
    now.last_frame = last_frame, now.last_row = last_row, now.output = out->history();
    now.stage = static_cast<std::int64_t>(stage), now.stage_done = stage_done;
    now.stage_starts = stage_starts, now.stage_start_steps = stage_start_steps;
    now.stage_peak_kinetic = peak_kinetic, now.stage_first_frame = stage_first_frame;
    now.rest = rest_judged;
    if (rest_judged) now.rest_anchor = rest.anchor, now.rest_largest = rest.largest, now.rest_ratio_start = rest.ratio_start;
    write_checkpoint<D>(ck_path, model, now);
    last_checkpoint = clock::now();
    saved = {solver->steps(), ck_path};
  };

  // A signal's stop, once the state is saved.
  auto stop_for_signal = [&](int sig) {
    const std::string message =
        out ? fmt::format("signal {} at step {} (t = {:.6g} s); the state is saved in {}; continue with {} --restart {}",
                          sig, solver->steps(), solver->time(), ck_path, options.resume_command, shell_word(ck_path))
            : fmt::format("signal {} at step {} (t = {:.6g} s)", sig, solver->steps(), solver->time());
    interrupt_saved(message.c_str());  // a signal from now on exits at once, with this message
    throw Interrupted(message, sig);
  };

  // A restart at the end of a stage begins the next one.
  bool resuming = options.restart.has_value();
  bool run_limit_hit = false;
  if (resuming && start.stage_done) ++stage, resuming = false;
  try {
    for (;; ++stage) {
      const double t0 = solver->time();
      if (!resuming) {
        if (staged && stage > 0) {
          try {
            begin_stage(model, config, stage, t0);
            for (auto& r : recorders) r.rebind(model);
          } catch (const InputError& e) {
            throw InputError(fmt::format("stage {} \"{}\" (t = {:.6g} s): {}", stage + 1, config.stages[stage].name, t0,
                                         e.what()));
          }
          const std::int64_t steps = solver->steps();
          solver.emplace(model);  // its per-step arrays start again from the new model, as on a restart
          solver->resume(t0, steps);
        }
        stage_starts.resize(stage + 1), stage_start_steps.resize(stage + 1);
        stage_starts[stage] = t0, stage_start_steps[stage] = solver->steps();
        peak_kinetic = 0.0;
        latest_kinetic_ratio = std::numeric_limits<double>::quiet_NaN();
        rest.largest = 0.0;
        open_rest_window(model, std::numeric_limits<double>::quiet_NaN(), rest);
        // The stage's frames open with the one of its start: the run's first, or the previous stage's last.
        stage_first_frame = out ? std::max<std::int64_t>(0, static_cast<std::int64_t>(out->frames_written()) - 1) : 0;
      }
      resuming = false;
      stage_done = false;
      if (out) out->set_stage(static_cast<int>(stage) + 1);
      const Config& sc = stage_config();
      const TimeConfig& tc = sc.time;
      std::string stage_end;  // what ended the stage
      if (staged) {
        const StageEnd& e = config.stages[stage].end;
        end = e.duration ? stage_starts[stage] + *e.duration : std::numeric_limits<double>::infinity();
        const std::int64_t from = stage_start_steps[stage];
        step_limit = e.steps > 0 ? from + e.steps : 0;
        if (e.max_steps > 0) step_limit = step_limit > 0 ? std::min(step_limit, from + e.max_steps) : from + e.max_steps;
        settles = stage_settles_at(model, config, stage);
        if (e.duration && e.max_steps == 0 && e.steps == 0) {
          Config c = sc;
          c.time.end = end;
          check_run_length(c, next_time_step(tc, critical_time_step<D>(model.particles, model.materials, model.grid.h),
                                             0, config.source),
                           solver->time());
        }
      } else {
        step_limit = tc.max_steps;
      }
      // A restart may come with another output interval or end time: skip frame times already past.
      double next_frame = frame_after(solver->time(), dt);
      double next_row = oc.global_interval * static_cast<double>(row_index);

      while (solver->time() < end * (1.0 - 1e-12)) {
        // time.max_steps of a staged run: the whole run stops there, in whatever stage (a batch slot's
        // end; a restart from its checkpoint continues the stage).
        if (staged && tc.max_steps > 0 && solver->steps() >= tc.max_steps) {
          run_limit_hit = true;
          stopped_by = fmt::format("time.max_steps = {} reached in stage {} \"{}\"", tc.max_steps, stage + 1,
                                   config.stages[stage].name);
          break;
        }
        if (step_limit > 0 && solver->steps() >= step_limit) {
          stage_end = step_limit_end();
          break;
        }
        const double t = solver->time();
        if (solver->steps() > 0) {
          try {
            dt = next_time_step(tc, critical_time_step<D>(model.particles, model.materials, model.grid.h),
                                solver->steps(), config.source);
          } catch (const RunError& e) {
            RunError located(fmt::format("step {} (t = {:.6g} s): {}: {}", solver->steps() + 1, solver->time(),
                                         solver->describe_particle(limiting_particle(model.particles, model.materials)), e.what()),
                             e.fault);
            located.suggested_dt = e.suggested_dt;
            // The state is still that of a good step: worth saving for a restart with a smaller dt.
            if (e.fault == Fault::UnstableStep && out) {
              save();
              if (solver->time() > last_frame) write_frame(solver->time());
            }
            throw located;
          }
        }
        // Land exactly on the next frame (or the end); split the approach in two equal steps rather
        // than leave a sliver of a step.
        const double target = next_frame;  // never beyond the end but for its rounding (frame_time)
        if (t + dt * (1.0 + 1e-6) >= target) dt = target - t;
        else if (t + 2.0 * dt > target) dt = 0.5 * (target - t);
        try {
          solver->step(dt);
        } catch (const RunError& e) {
          // A particle outside the grid or collapsed is worth seeing; a non-finite state is not, and
          // none of them can be stepped on, so no checkpoint.
          if (out && e.fault != Fault::NonFinite) write_frame(solver->time() + dt);
          if (staged)
            throw RunError(fmt::format("stage {} \"{}\": {}", stage + 1, config.stages[stage].name, e.what()), e.fault);
          throw;
        }
        const double now = solver->time();
        const double tol = 1e-6 * dt;  // above the round-off of summing thousands of steps
        if (after_step) after_step(*solver);
        if (out) {
          if (oc.global_interval <= 0.0 || now >= next_row - tol) {
            out->global_row(now, solver->steps(), dt, step_report(*solver), recorder_row());
            last_row = now;
            if (oc.global_interval > 0.0) {
              row_index = static_cast<std::int64_t>(std::floor((now + tol) / oc.global_interval)) + 1;
              next_row = oc.global_interval * static_cast<double>(row_index);
            }
          }
          if (clock::now() - last_flush > std::chrono::seconds(30)) {
            out->flush_global();
            last_flush = clock::now();
          }
        }
        const double label_value = label && oc.label_interval > 0.0 ? label->value(*solver) : 0.0;
        const bool by_label = label_due(label_value);
        if (now >= next_frame - tol || by_label) {
          if (out) {
            write_frame(now);
            last_frame = now;
          }
          next_frame = frame_after(now, dt);
          if (by_label) next_label(label_value);
        }
        Progress progress;
        progress.step = solver->steps(), progress.time = now, progress.end_time = end, progress.dt = dt;
        progress.frames = out ? out->frames_written() : 0;
        progress.fraction = std::isfinite(end) && end > 0.0 ? std::clamp((now - stage_starts[stage]) / (end - stage_starts[stage]), 0.0, 1.0)
                            : 0.0;
        if (step_limit > 0)
          progress.fraction = std::max(progress.fraction, std::clamp(static_cast<double>(solver->steps() - stage_start_steps[stage]) /
                                                                         static_cast<double>(step_limit - stage_start_steps[stage]),
                                                                     0.0, 1.0));
        if (staged) {
          progress.stage = static_cast<int>(stage) + 1, progress.stages = static_cast<int>(config.stages.size());
          progress.stage_name = config.stages[stage].name;
        }
        for (std::size_t k = 0; k < recorders.size(); ++k) {
          const auto& r = recorders[k];
          const auto& rc = r.config();
          if (!rc.stop_above && !rc.stop_below) continue;  // evaluated on output rows only
          const double value = r.value(*solver);
          // The way from the start value to each bound that lies ahead of it. Not for the
          // unbalanced-force ratio: it has no start value (NaN before the first step) and decays
          // neither linearly nor monotonically, so the time fraction stands for it.
          for (const auto& [bound, sign] : {std::pair{rc.stop_above, 1.0}, std::pair{rc.stop_below, -1.0}}) {
            if (!bound || r.from_solver() || sign * (*bound - recorder_start[k]) <= 0.0) continue;
            const double f = std::clamp((value - recorder_start[k]) / (*bound - recorder_start[k]), 0.0, 1.0);
            if (f > progress.fraction)
              progress.fraction = f, progress.leader = rc.name, progress.leader_value = value, progress.leader_bound = *bound;
          }
          if (stopped_by.empty()) stopped_by = r.stop_reason(value);
        }
        // The stage's own ends: equilibrium (once its functions of time have settled) and a recorder.
        if (staged) {
          const StageEnd& e = config.stages[stage].end;
          const bool rest_rule = e.judged_at_rest();
          if (e.kinetic_energy_ratio || rest_rule) {
            const double ke = kinetic_energy(model.particles);
            peak_kinetic = std::max(peak_kinetic, ke);
            latest_kinetic_ratio = peak_kinetic > 0.0 ? ke / peak_kinetic : 0.0;
          }
          // Not before the stage's equilibrium_first_step-th step: the first solves of a stage still
          // see the stresses of the state before its changes.
          const bool judged = solver->steps() - stage_start_steps[stage] >= equilibrium_first_step;
          if (e.equilibrium() && now >= settles && judged) {
            const bool force_ok = !e.unbalanced_force_ratio || solver->unbalanced_force_ratio() < *e.unbalanced_force_ratio;
            const bool energy_ok = !e.kinetic_energy_ratio || latest_kinetic_ratio < *e.kinetic_energy_ratio;
            if (force_ok && energy_ok) stage_end = "equilibrium";
          }
          // Every window closes, judged or not, so that the windows are those of the stage's steps.
          const std::int64_t stage_steps = solver->steps() - stage_start_steps[stage];
          if (rest_rule && stage_steps > 0 && stage_steps % rest_window == 0) {
            const bool at_rest = close_rest_window(model, solver->unbalanced_force_ratio(), latest_kinetic_ratio, rest,
                                                   e.kinetic_energy_ratio.value_or(rest_kinetic_fraction));
            if (at_rest && now >= settles && judged && stage_end.empty()) stage_end = "at rest";
          }
          if (e.recorder >= 0 && stage_end.empty()) {
            const double v = recorders[static_cast<std::size_t>(e.recorder)].value(*solver);
            if ((e.above && v >= *e.above) || (e.below && v <= *e.below))
              stage_end = fmt::format("recorder {}", recorders[static_cast<std::size_t>(e.recorder)].config().name);
          }
          // The step and duration ends at once, so that no checkpoint is saved at a stage's end
          // before that end has been taken (a restart would end the stage without a step).
          if (stage_end.empty() && step_limit > 0 && solver->steps() >= step_limit) stage_end = step_limit_end();
          if (stage_end.empty() && now >= end * (1.0 - 1e-12)) stage_end = "duration";
          if (!stage_end.empty()) progress.fraction = 1.0;
        }
        if (!stopped_by.empty()) progress.fraction = 1.0;
        if (options.on_progress) options.on_progress(progress);
        // A signal at the step a stage ends is taken after that end (below): a checkpoint saved
        // here would hold the stage as not ended, and its restart would end it later, or
        // (a rest verdict's window already reopened) a whole window later.
        if (stage_end.empty())
          if (const int sig = pending_interrupt()) {
            save();
            stop_for_signal(sig);
          }
        if (!stopped_by.empty() || !stage_end.empty()) break;
        if ((kc.every_steps > 0 && solver->steps() % kc.every_steps == 0) ||
            (kc.every_minutes > 0.0 && clock::now() - last_checkpoint >= checkpoint_wall))
          save();
      }
      // A recorder's stop bound stops the run, not the stage: a restart (with another bound)
      // continues the stage where it stopped. At the step the stage ends, the stage's end is
      // taken first, as for a signal.
      if (!staged || run_limit_hit || (!stopped_by.empty() && stage_end.empty())) {
        run_limit_hit = run_limit_hit || staged;
        break;
      }
      // The end of a stage: its last row and frame, its row of stages.csv and .pvd, a checkpoint.
      if (stage_end.empty()) stage_end = "duration";
      StageReport rep;
      rep.stage = static_cast<int>(stage) + 1, rep.stages = static_cast<int>(config.stages.size());
      rep.name = config.stages[stage].name, rep.end = stage_end;
      rep.start_time = stage_starts[stage], rep.end_time = solver->time();
      rep.start_step = stage_start_steps[stage], rep.end_step = solver->steps();
      rep.unbalanced_force_ratio = solver->unbalanced_force_ratio();
      // Reported when asked for (a rest verdict computes it too, but the column stays as it was).
      rep.kinetic_energy_ratio = config.stages[stage].end.kinetic_energy_ratio ? latest_kinetic_ratio
                                                                               : std::numeric_limits<double>::quiet_NaN();
      rep.equilibrium_asked = config.stages[stage].end.equilibrium();
      if (out) {
        if (solver->time() > last_row) {
          out->global_row(solver->time(), solver->steps(), dt, step_report(*solver), recorder_row());
          last_row = solver->time();
        }
        if (solver->time() > last_frame || out->frames_written() == 0) {
          write_frame(solver->time());
          last_frame = solver->time();
        }
        rep.first_frame = stage_first_frame;
        rep.last_frame = static_cast<std::int64_t>(out->frames_written()) - 1;
        out->stage_row(rep);
      }
      reports.push_back(rep);
      if (options.on_stage_end) options.on_stage_end(rep);
      stage_done = true;
      save();
      if (stage >= last_stage) break;
      if (!stopped_by.empty()) break;  // the checkpoint at the stage's end is the run's last
      if (const int sig = pending_interrupt()) stop_for_signal(sig);
    }
  } catch (const Interrupted&) {
    throw;
  } catch (const RunError& e) {
    if (out) out->flush_global();  // keep the history up to the failure
    if (saved.first < 0) throw;
    throw RunError(fmt::format("{}\nthe latest checkpoint is step {}: {} (continue with {}{} --restart {})", e.what(),
                               saved.first, saved.second, options.resume_command,
                               // the time step the message above suggests, when it gave one
                               e.fault == Fault::UnstableStep && stage_config().time.dt
                                   ? fmt::format(" --set time.dt={:.3g}",
                                                 e.suggested_dt > 0.0 ? e.suggested_dt : 0.5 * *stage_config().time.dt)
                                   : std::string{},
                               shell_word(saved.second)),
                   e.fault);
  } catch (const OutputError& e) {
    try {
      if (out) out->flush_global();  // the CSVs are small: they may still fit where a frame did not
    } catch (const OutputError&) {
    }
    throw OutputError(fmt::format("step {} (t = {:.6g} s): {}; the files written before are complete{}", solver->steps(),
                                  solver->time(), e.what(),
                                  saved.first < 0 ? std::string{}
                                                  : fmt::format(", and the latest checkpoint is step {}: {}",
                                                                saved.first, saved.second)));
  } catch (...) {
    if (out) out->flush_global();
    throw;
  }
  if ((!staged && kc.enabled()) || run_limit_hit) save();
  if (out) {
    if (solver->time() > last_row) out->global_row(solver->time(), solver->steps(), dt, step_report(*solver), recorder_row());  // the final state
    if (solver->time() > last_frame) write_frame(solver->time());
    out->flush_global();
  }
  RunSummary s;
  s.steps = solver->steps();
  s.steps_taken = solver->steps() - start.steps;
  s.time = solver->time();
  s.wall_seconds = std::chrono::duration<double>(clock::now() - wall_start).count();
  s.frames = out ? out->frames_written() : 0;
  s.directory = dir;
  s.stopped_by = stopped_by;
  s.checkpoint = (kc.enabled() || staged) && out ? ck_path : std::string{};
  s.stages = reports;
  return s;
}

template RunSummary run_simulation<2>(Model<2>&, const Config&, const RunOptions&,
                                      const std::function<void(const ExplicitSolver<2>&)>&);
template RunSummary run_simulation<3>(Model<3>&, const Config&, const RunOptions&,
                                      const std::function<void(const ExplicitSolver<3>&)>&);

}  // namespace tsuchi
