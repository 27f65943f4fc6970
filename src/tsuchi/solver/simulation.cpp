#include "tsuchi/solver/simulation.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/output_writer.hpp"
#include "tsuchi/solver/recorder.hpp"
#include "tsuchi/solver/time_step.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

namespace tsuchi {

double next_time_step(const TimeConfig& time, double dt_crit, std::int64_t step, const std::string& source) {
  if (std::isnan(dt_crit))
    throw RunError(fmt::format("step {}: a particle's velocity, volume or mass is not finite", step + 1));
  if (time.courant) return *time.courant * dt_crit;
  if (*time.dt > dt_crit) {
    const std::string msg = fmt::format(
        "time.dt = {:.6g} s is above the stable limit {:.6g} s (cell size / (P-wave speed + particle "
        "speed)); set time.dt below it, or set time.courant instead",
        *time.dt, dt_crit);
    if (step == 0) throw InputError(fmt::format("{}: {}", source, msg));
    throw RunError(fmt::format("step {}: {}", step + 1, msg));
  }
  return *time.dt;
}

template <int D>
RunSummary run_simulation(Model<D>& model, const RunOptions& options,
                          const std::function<void(const ExplicitSolver<D>&)>& after_step) {
  using clock = std::chrono::steady_clock;
  const auto wall_start = clock::now();
  const TimeConfig& tc = model.config.time;
  const OutputConfig& oc = model.config.output;
  const double end = tc.end;

  ExplicitSolver<D> solver(model);
  const std::string dir = options.output_directory.value_or(oc.directory);
  // Check the first step before anything is written: a refused dt leaves the directory untouched.
  double dt = next_time_step(tc, critical_time_step<D>(model.particles, model.config.materials, model.grid.h),
                             0, model.config.source);

  std::optional<OutputWriter<D>> out;
  if (options.write_output) {
    out.emplace(model, dir);
    out->global_row(0.0, 0, 0.0);
    out->frame(0.0);
  }
  // Recorders with a stop bound are evaluated after every step; the others only on output rows.
  std::vector<Recorder<D>> stops;
  for (const auto& rc : model.config.recorders)
    if (rc.stop_above || rc.stop_below) stops.emplace_back(rc, model);
  std::string stopped_by;
  std::int64_t frame_index = 1, row_index = 1;
  auto frame_time = [&](std::int64_t k) { return oc.interval > 0 ? std::min(end, static_cast<double>(k) * oc.interval) : end; };
  double next_frame = frame_time(frame_index);
  double next_row = oc.global_interval * static_cast<double>(row_index);
  double last_frame = 0.0, last_row = 0.0;
  auto last_flush = clock::now();

  try {
    while (solver.time() < end * (1.0 - 1e-12)) {
      if (tc.max_steps > 0 && solver.steps() >= tc.max_steps) break;
      const double t = solver.time();
      if (solver.steps() > 0)
        dt = next_time_step(tc, critical_time_step<D>(model.particles, model.config.materials, model.grid.h),
                            solver.steps(), model.config.source);
      // Land exactly on the next frame (or the end); split the approach in two equal steps rather
      // than leave a sliver of a step.
      const double target = std::min(end, next_frame);
      if (t + dt * (1.0 + 1e-6) >= target) dt = target - t;
      else if (t + 2.0 * dt > target) dt = 0.5 * (target - t);
      solver.step(dt);
      const double now = solver.time();
      const double tol = 1e-6 * dt;  // above the round-off of summing thousands of steps
      if (after_step) after_step(solver);
      if (out) {
        if (oc.global_interval <= 0.0 || now >= next_row - tol) {
          out->global_row(now, solver.steps(), dt);
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
      if (now >= next_frame - tol) {
        if (out) {
          out->frame(now);
          last_frame = now;
        }
        while (next_frame <= now + tol && next_frame < end) next_frame = frame_time(++frame_index);
      }
      if (options.on_progress)
        options.on_progress({solver.steps(), now, end, dt, out ? out->frames_written() : 0});
      for (const auto& r : stops) {
        stopped_by = r.stop_reason(r.value(model.particles));
        if (!stopped_by.empty()) break;
      }
      if (!stopped_by.empty()) break;
    }
  } catch (...) {
    if (out) out->flush_global();  // keep the history up to the failure
    throw;
  }
  if (out) {
    if (solver.time() > last_row) out->global_row(solver.time(), solver.steps(), dt);  // the final state
    if (solver.time() > last_frame) out->frame(solver.time());
    out->flush_global();
  }
  RunSummary s;
  s.steps = solver.steps();
  s.time = solver.time();
  s.wall_seconds = std::chrono::duration<double>(clock::now() - wall_start).count();
  s.frames = out ? out->frames_written() : 0;
  s.directory = dir;
  s.stopped_by = stopped_by;
  return s;
}

template RunSummary run_simulation<2>(Model<2>&, const RunOptions&,
                                      const std::function<void(const ExplicitSolver<2>&)>&);
template RunSummary run_simulation<3>(Model<3>&, const RunOptions&,
                                      const std::function<void(const ExplicitSolver<3>&)>&);

}  // namespace tsuchi
