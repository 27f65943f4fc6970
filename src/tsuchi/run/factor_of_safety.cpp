#include "tsuchi/run/factor_of_safety.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/atomic_file.hpp"
#include "tsuchi/io/vtu_writer.hpp"
#include "tsuchi/model/model.hpp"
#include "tsuchi/run/simulation.hpp"
#include "tsuchi/solver/explicit_step.hpp"
#include "tsuchi/solver/time_step.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <optional>

namespace tsuchi {

namespace {

bool reducible(const Material& m) {
  return std::visit([](const auto& model) { return requires { model.reduced(1.0, false); }; }, m.model);
}

// One trial: the analysis' end state with every reducible strength divided by F, stepped to
// equilibrium or collapse (factor_of_safety.hpp gives the criteria). `frame` gets the end state.
template <int D>
FosTrial run_trial(const Model<D>& base, const Config& during, const FosConfig& f, double F, double t0,
                   std::int64_t steps0, const std::vector<std::string>& fields, std::string& frame) {
  const auto wall = std::chrono::steady_clock::now();
  Model<D> m = base;
  for (Material& mat : m.materials)
    std::visit([&](auto& model) {
      if constexpr (requires { model.reduced(1.0, false); }) model = model.reduced(F, f.reduce_dilatancy);
    }, mat.model);
  // Displacements from the state the trial starts from.
  std::fill(m.particles.u_p.begin(), m.particles.u_p.end(), Vec<D>::Zero());
  ExplicitSolver<D> solver(m);
  solver.resume(t0, steps0);
  FosTrial t;
  t.factor = F;
  // The verdict at the budget's end comes from the trend of the movement (issue 41, defect 7): the
  // largest displacement sampled every fifth of fos.max_steps from two fifths before its end, so the
  // growth over the last window (g) and the one before (g_prev) are known there. A trial that has
  // not stood or failed by then and is still slowing down (g < 0.8 g_prev: the movement falls by a
  // fifth or more per window, a creep coming to rest) is given another window, up to
  // fos.extend x max_steps; a trial moving steadily or faster fails. A fixed window alone stood
  // the same slope at one budget and failed it at the next.
  const std::int64_t window = std::max<std::int64_t>(1, f.max_steps / 5);
  const std::int64_t first_sample = f.max_steps - 2 * window;
  const std::int64_t cap = f.max_steps * f.extend;
  std::int64_t budget = f.max_steps;
  std::vector<double> samples;  // D at first_sample, first_sample + window, ...
  auto max_displacement = [&] {
    double most = 0.0;
    for (const auto& u : m.particles.u_p) most = std::max(most, u.squaredNorm());
    return std::sqrt(most);
  };
  try {
    for (std::int64_t n = 1; n <= budget; ++n) {
      const double dt = next_time_step(during.time, critical_time_step<D>(m.particles, m.materials, m.grid.h),
                                       solver.steps(), during.source);
      solver.step(dt);
      t.steps = n;
      t.max_displacement = max_displacement();
      t.unbalanced_force_ratio = solver.unbalanced_force_ratio();
      if (f.displacement_limit && t.max_displacement > *f.displacement_limit) {
        t.failed = true, t.reason = "displacement";
        break;
      }
      // The reduced strength acts from the first stress update on, and the forces it leaves out of
      // balance show in the solves after it: the ratio of the first steps still reflects the old state.
      if (n >= equilibrium_first_step && t.unbalanced_force_ratio < f.unbalanced_force_ratio) {
        t.reason = "equilibrium";
        break;
      }
      if (n >= first_sample && (n - first_sample) % window == 0) samples.push_back(t.max_displacement);
      if (n == budget && samples.size() >= 3) {
        const double g = samples.back() - samples[samples.size() - 2];
        const double g_prev = samples[samples.size() - 2] - samples[samples.size() - 3];
        t.late_growth = g;
        const bool resting = f.displacement_limit && g < 0.01 * *f.displacement_limit;
        if (!resting && f.displacement_limit && g < 0.8 * g_prev && budget + window <= cap) budget += window;
      }
    }
  } catch (const RunError& e) {
    // A collapse may carry particles out of the grid or crush them: a failure, not a fault.
    t.failed = true, t.reason = fmt::format("run fault ({})", e.what());
  }
  if (t.reason.empty()) {
    const bool at_rest = f.displacement_limit && t.late_growth < 0.01 * *f.displacement_limit;
    t.failed = !at_rest;
    const std::string when = budget > f.max_steps ? fmt::format(" (slowing: extended to {} steps)", budget) : "";
    t.reason = (at_rest ? "at rest at max_steps" : "max_steps") + when;
  }
  frame = vtu_document<D>(m, fields);
  t.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
  return t;
}

}  // namespace

template <int D>
FosResult factor_of_safety(const Config& config, Model<D> model, const FosOptions& options) {
  if (!config.fos.given)
    throw InputError(fmt::format("{}: missing table [fos]: expected the factor of safety's settings, at least "
                                 "fos.max_steps (the steps a trial may take to reach equilibrium); docs/stages.md",
                                 config.source));
  const FosConfig& f = config.fos;
  const Config& during = config.staged() ? *config.stages[static_cast<std::size_t>(f.after_stage)].config : config;
  if (std::none_of(during.materials.begin(), during.materials.end(), reducible)) {
    std::string names;
    for (const auto& m : during.materials) names += fmt::format("{}\"{}\"", names.empty() ? "" : ", ", m.name);
    throw InputError(fmt::format("{}: key 'fos': no material to reduce: the factor of safety divides the strength of "
                                 "Mohr-Coulomb-family materials (mohr_coulomb, drucker_prager, mohr_coulomb_softening), "
                                 "and the input's materials ({}) are none of them",
                                 config.source, names));
  }
  // The analysis, to the end of its [fos] stage: the state the trials start from.
  RunOptions ro;
  ro.output_directory = options.output_directory;
  ro.last_stage = f.after_stage;
  ro.on_stage_end = [&](const StageReport& r) {
    if (options.on_note)
      options.on_note(fmt::format("stage {}/{} \"{}\": {} at step {} (t = {:.6g} s), unbalanced-force ratio {:.3g}",
                                  r.stage, r.stages, r.name, r.end, r.end_step, r.end_time, r.unbalanced_force_ratio));
  };
  const RunSummary run = run_simulation<D>(model, config, ro);
  // The trials start from the end of the [fos] stage, or of the whole run: not from a state the
  // analysis stopped at on the way.
  // (A single-stage run may end by a recorder's bound on the ratio: its equilibrium.)
  const bool finished = config.staged() ? run.stopped_by.empty() && !run.stages.empty() &&
                                              run.stages.back().stage == f.after_stage + 1
                                        : !run.stopped_by.empty() || run.time >= config.time.end * (1.0 - 1e-12);
  if (!finished)
    throw RunError(fmt::format("the analysis stopped before {} ({}); the factor of safety is sought from its end",
                               config.staged() ? fmt::format("the end of stage \"{}\"", config.stages[static_cast<std::size_t>(f.after_stage)].name)
                                               : std::string("time.end"),
                               run.stopped_by.empty() ? std::string("time.max_steps") : run.stopped_by),
                   Fault::Other);
  // The search takes F = 1 (the analysis' state) to stand: say so when that state is not at rest.
  if (!run.stages.empty() && run.stages.back().equilibrium_asked && !run.stages.back().reached_equilibrium() &&
      options.on_note)
    options.on_note(fmt::format("warning: stage \"{}\" reached {} before equilibrium; the trials start from a state "
                                "that is not at rest, and F = 1 is taken to stand",
                                run.stages.back().name, run.stages.back().end));

  FosResult result;
  result.directory = options.output_directory + "/fos";
  std::filesystem::create_directories(result.directory);
  std::vector<std::string> fields = config.output.fields;
  for (const char* name : {"displacement", "plastic_shear_strain", "max_shear_strain"})
    if (std::find(fields.begin(), fields.end(), name) == fields.end()) fields.emplace_back(name);

  std::string stable_frame = vtu_document<D>(model, fields), failed_frame;
  // A round of trials, side by side where there are threads (one thread each then: the same bits).
  auto round = [&](const std::vector<double>& factors) {
    std::vector<FosTrial> trials(factors.size());
    std::vector<std::string> frames(factors.size());
    std::vector<std::exception_ptr> errors(factors.size());
    const int outer = std::min<int>(static_cast<int>(factors.size()), omp_get_max_threads());
    auto one = [&](std::size_t i) {
      try {
        trials[i] = run_trial<D>(model, during, f, factors[i], run.time, run.steps, fields, frames[i]);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    };
    if (outer > 1) {
      const int levels = omp_get_max_active_levels();
      omp_set_max_active_levels(1);
#pragma omp parallel for num_threads(outer) schedule(static, 1)
      for (std::size_t i = 0; i < factors.size(); ++i) one(i);
      omp_set_max_active_levels(levels);
    } else {
      for (std::size_t i = 0; i < factors.size(); ++i) one(i);
    }
    for (const auto& e : errors)
      if (e) std::rethrow_exception(e);
    for (std::size_t i = 0; i < trials.size(); ++i) {
      trials[i].index = static_cast<int>(result.trials.size()) + 1;
      result.trials.push_back(trials[i]);
      if (options.on_trial) options.on_trial(trials[i]);
    }
    return std::pair{trials, frames};
  };

  double lo = f.lower, hi = f.upper;
  if (lo != 1.0) {
    auto [t, fr] = round({lo});
    if (t[0].failed)
      throw InputError(fmt::format("{}: key 'fos.bracket': the trial at the lower end F = {:g} fails ({}); expected a "
                                   "lower end at which the ground stands",
                                   config.source, lo, t[0].reason));
    stable_frame = fr[0];
  }
  constexpr double highest = 100.0;
  for (;;) {
    auto [t, fr] = round({hi});
    if (t[0].failed) {
      failed_frame = fr[0];
      break;
    }
    lo = hi, stable_frame = fr[0];
    if (hi * 2.0 > highest)
      throw RunError(fmt::format("the ground stands at F = {:g}, beyond which no factor of safety is sought; check "
                                 "fos.displacement_limit and fos.unbalanced_force_ratio",
                                 hi),
                     Fault::Other);
    hi *= 2.0;
  }
  const int k = f.trials_at_once;
  while ((hi - lo) / lo > f.tolerance) {
    std::vector<double> factors;
    for (int i = 1; i <= k; ++i) factors.push_back(lo + (hi - lo) * i / (k + 1));
    auto [t, fr] = round(factors);
    // The first failure of the round is the new upper end; the last stand below it the lower one.
    std::size_t first_fail = t.size();
    for (std::size_t i = 0; i < t.size(); ++i)
      if (t[i].failed) {
        first_fail = i;
        break;
      }
    if (first_fail < t.size()) hi = factors[first_fail], failed_frame = fr[first_fail];
    if (first_fail > 0) lo = factors[first_fail - 1], stable_frame = fr[first_fail - 1];
  }
  result.lower = lo, result.upper = hi, result.factor = 0.5 * (lo + hi);
  // The failure that set the upper end: a trial that ran out of steps while still moving, far from
  // the displacement limit, has not collapsed; a larger budget may stand it (issue 41, defect 7:
  // an embankment gave 1.006 at 4,000 steps a trial, 1.315 at 20,000, 1.241 at 40,000, its trials
  // failing at max_steps with 4 cm of movement against a 0.3 m limit). The factor is then a bound.
  // A trial on its way to collapse passes the limit within another budget at the rate of its last
  // fifth (5 x late_growth more); one that would not is undecided: the budget, not the ground, failed it.
  for (auto it = result.trials.rbegin(); it != result.trials.rend(); ++it) {
    if (it->factor != hi || !it->failed) continue;
    const bool short_of_limit =
        !f.displacement_limit || it->max_displacement + 5.0 * it->late_growth < *f.displacement_limit;
    if (it->reason.rfind("max_steps", 0) == 0 && short_of_limit)
      result.bound = fmt::format(
          "the trial at F = {:.6g} failed only by running out of steps (fos.max_steps = {}{}) with {:.3g} m of "
          "movement{}, {:.3g} m of it in its last fifth: at that rate it would not reach the limit in as many steps "
          "again, so it was creeping, not collapsing, F = {:.6g} is a lower bound and the factor may be higher; "
          "raise fos.max_steps (say to {}) until the factor stops changing",
          hi, f.max_steps, it->steps > f.max_steps ? fmt::format(", slowing, extended to {}", it->steps) : std::string{},
          it->max_displacement,
          f.displacement_limit ? fmt::format(" against a limit of {:.3g} m", *f.displacement_limit) : std::string{},
          it->late_growth, lo, 4 * f.max_steps);
    break;
  }

  std::string csv = "trial,factor,result,reason,steps,unbalanced_force_ratio,max_displacement,wall_seconds\n";
  for (const auto& t : result.trials)
    csv += fmt::format("{},{:.9g},{},\"{}\",{},{:.6g},{:.9g},{:.3f}\n", t.index, t.factor, t.failed ? "fails" : "stands",
                       t.reason, t.steps, t.unbalanced_force_ratio, t.max_displacement, t.wall_seconds);
  write_file_atomically(result.directory + "/trials.csv", csv);
  write_file_atomically(result.directory + "/stable.vtu", stable_frame);
  write_file_atomically(result.directory + "/mechanism.vtu", failed_frame);
  write_file_atomically(result.directory + "/fos.pvd", pvd_document({{lo, "stable.vtu"}, {hi, "mechanism.vtu"}}));
  return result;
}

template FosResult factor_of_safety<2>(const Config&, Model<2>, const FosOptions&);
template FosResult factor_of_safety<3>(const Config&, Model<3>, const FosOptions&);

}  // namespace tsuchi
