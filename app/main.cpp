// tsuchi: the command-line program. `tsuchi run FILE` runs a model, `tsuchi check FILE` validates
// it and prints what a run would do, `tsuchi fos FILE` finds a factor of safety by strength reduction, `tsuchi element FILE` drives one material point along a
// lab-test path. Exit codes (core/errors.hpp): 0 ok, 1 usage, 2 input, 3 run fault, 4 output,
// 5 internal error, 6 non-finite state, 7 particle left the grid, 8 volume collapse, 9 unstable
// time step, 128 + signal when interrupted (the state is saved first).
#include "element_command.hpp"
#include "console.hpp"
#include "cpus.hpp"
#include "disk_space.hpp"
#include "progress.hpp"

#include "tsuchi/comm/communicator.hpp"
#include "tsuchi/core/errors.hpp"
#include "tsuchi/core/interrupt.hpp"
#include "tsuchi/core/memory_limit.hpp"
#include "tsuchi/core/version.hpp"
#include "tsuchi/io/element_reader.hpp"
#include "tsuchi/io/output_writer.hpp"
#include "tsuchi/io/vtu_writer.hpp"
#include "tsuchi/io/grid_vtu_writer.hpp"
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/model/model.hpp"
#include "tsuchi/model/stage_change.hpp"
#include "tsuchi/model/start_warnings.hpp"
#include "tsuchi/run/factor_of_safety.hpp"
#include "tsuchi/run/first_step.hpp"
#include "tsuchi/run/recorder.hpp"
#include "tsuchi/run/simulation.hpp"
#include "tsuchi/solver/time_step.hpp"

#include <CLI/CLI.hpp>
#include <omp.h>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <csignal>
#include <cstdio>
#include <limits>
#include <string_view>

using tsuchi::app::say;

namespace {

using namespace tsuchi;

struct Options {
  std::string file;
  std::string output;
  std::vector<std::string> overrides;
  bool quiet = false;
  int threads = 0;  // 0: OpenMP's default (OMP_NUM_THREADS, else every core)
  std::string restart;
};

// The velocity fields of contact with their bodies, each [[contact]] pair's law, and the walls.
template <int D>
void print_contact(const Config& c, const Model<D>& m) {
  const Contact<D>& k = m.contact;
  const auto name = [&](int b) { return fmt::format("\"{}\"", c.bodies[static_cast<std::size_t>(b)].name); };
  const auto law = [](const ContactConfig& p) {
    return p.law == ContactConfig::Law::Bonded  ? std::string("bonded")
           : p.law == ContactConfig::Law::Rough ? std::string("rough")
                                                : fmt::format("friction {}", p.friction);
  };
  if (k.fields > 0) {
    std::string fields;
    for (int f = 0; f < k.fields; ++f) {
      std::string names;
      for (const int b : k.bodies_of_field[static_cast<std::size_t>(f)]) names += (names.empty() ? "" : ", ") + name(b);
      const int rigid = k.rigid_body[static_cast<std::size_t>(f)];
      fields += fmt::format("{}{}{}", f ? " | " : "", names, rigid >= 0 ? " (rigid)" : "");
    }
    say("contact    {} velocity fields: {}\n", k.fields, fields);
  } else if (!c.contacts.empty()) {
    say("contact    bonded pairs only: one velocity field, as without contact\n");
  }
  if (k.fields > 0)
    for (const auto& p : c.contacts) say("           {} | {}: {}\n", name(p.body_a), name(p.body_b), law(p));
  for (const auto& w : k.walls) {
    const double mu = w.friction;
    say("wall       {}: frictional wall, {}\n", face_name(w.face),
               std::isinf(mu) ? std::string("rough (no slip)") : fmt::format("mu {}", mu));
  }
}

void print_stages(const Config& c);

// [fos]: what `tsuchi fos` would do after the analysis.
void print_fos(const Config& c) {
  const FosConfig& f = c.fos;
  say("fos        after {}: c and tan(phi) divided by F{}, F from [{:g}, {:g}] to {:g} %, {} trial{} a round; a "
             "trial stands at ratio < {:g}, fails {}after {} steps\n",
             f.after_stage >= 0 ? fmt::format("stage \"{}\"", c.stages[static_cast<std::size_t>(f.after_stage)].name)
                                : std::string("the run"),
             f.reduce_dilatancy ? " (and tan(psi))" : "", f.lower, f.upper, 100.0 * f.tolerance, f.trials_at_once,
             f.trials_at_once > 1 ? "s" : "", f.unbalanced_force_ratio,
             f.displacement_limit ? fmt::format("beyond {:g} m of displacement or ", *f.displacement_limit) : std::string{},
             f.max_steps);
}
void print_length(const Config& c, double dt, const std::string& output_dir, double frame_bytes);

// The model's own warnings (model/start_warnings.hpp), after the input's.
template <int D>
void warn_at_start(const Config& c, const Model<D>& m) {
  for (const auto& w : start_warnings<D>(c, m)) say(stderr, "warning: {}\n", tsuchi::app::shown(w));
  if (const auto w = long_first_step_warning<D>(c, m)) say(stderr, "warning: {}\n", tsuchi::app::shown(*w));
}

template <int D>
void print_summary(const Config& c, const Model<D>& m, const std::string& output_dir) {
  const double dt_crit = critical_time_step<D>(m.particles, c.materials, m.grid.h);
  const double dt = next_time_step(c.time, dt_crit, 0, c.source);
  say("tsuchi     {}\n", version);
  // The title as the terminal may show it, and 200 characters at most (a 10 MB title was echoed whole).
  say("model      {}{}\n", c.source, c.title.empty() ? "" : fmt::format(" ({})", io::printable(c.title, 200)));
  say("dimension  {}\n", D == 2 ? "2 (plane strain)" : "3");
  std::string cells;
  for (int d = 0; d < D; ++d) cells += fmt::format("{}{}", d ? " x " : "", c.grid.cells[d]);
  say("grid       {} cells of {} m, {} nodes\n", cells, m.grid.h, m.grid.node_count());
  // The model's materials: set for the grid (material.hpp, with_cell_size).
  for (const auto& mat : m.materials) say("material   {}\n", io::describe_material(mat));
  for (std::size_t b = 0; b < c.bodies.size(); ++b) {
    const BodyConfig& bc = c.bodies[b];
    std::string materials = fmt::format("material \"{}\"", bc.material);
    for (const auto& r : bc.regions) materials += fmt::format(", \"{}\" in a {}", r.material, r.kind);
    // A free rigid body moves with its rigid_mass, not with its particles' mass: say both.
    std::string rigid;
    if (bc.rigid_mass > 0.0) {
      double particle_mass = 0.0;
      for (std::size_t i = 0; i < m.particles.size(); ++i)
        if (static_cast<std::size_t>(m.particles.body_p[i]) == b) particle_mass += m.particles.m_p[i];
      rigid = fmt::format(", free rigid body of mass {:.6g} {} (its particles' {:.6g})", bc.rigid_mass,
                          D == 2 ? "kg/m" : "kg", particle_mass);
    }
    say("body       {:<16} {:>9} particles, {} {:.6g} {}, {}{}{}\n", bc.name, m.body_particles[b],
               bc.shape_kind == "file" ? "from a file," : fmt::format("a {},", bc.shape_kind), m.body_volume[b],
               D == 2 ? "m^2" : "m^3", materials, bc.priority != 0 ? fmt::format(", priority {}", bc.priority) : "",
               rigid);
  }
  say("particles  {}\n", m.particles.size());
  print_contact<D>(c, m);
  say("solver     {}, {} shape functions, {}, anti-locking {}, damping {}\n", to_string(c.solver.scheme),
             to_string(c.solver.shape),
             c.solver.velocity_transfer == VelocityTransfer::Apic ? std::string("APIC transfer")
                                                                   : fmt::format("FLIP, PIC fraction {}", c.solver.pic_fraction),
             to_string(c.solver.anti_locking), c.solver.damping);
  // Each material whose remedy is not the line above's: its own key, or a dilatant material's default.
  for (std::size_t k = 0; k < c.materials.size(); ++k)
    if (const AntiLocking a = anti_locking_of(c, k); a != c.solver.anti_locking)
      say("           material \"{}\": anti-locking {}{}\n", c.materials[k].name, to_string(a),
                 k < c.material_anti_locking.size() && c.material_anti_locking[k] ? "" : " (dilatant: the default)");
  say("time step  {:.4g} s ({}; stable limit {:.4g} s)\n", dt,
             c.time.courant ? fmt::format("Courant {}", *c.time.courant) : std::string("fixed"), dt_crit);
  if (c.staged()) {
    print_stages(c);
    if (c.fos.given) print_fos(c);
    say("output     {} (a frame at the end of each stage{}; stages.csv)\n", output_dir,
               c.output.interval > 0 ? fmt::format(" and every {} s", c.output.interval) : std::string{});
  } else {
    if (c.fos.given) print_fos(c);
    double frame_bytes = c.output.write_frames ? vtu_size<D>(m, c.output.fields) : 0.0;
    if (!c.output.grid_fields.empty()) {
      // The grid frame of the start (output.grid_fields); it grows where the material spreads.
      const GridFrameSize g = grid_vtu_size<D>(m, c.output.grid_fields);
      say("grid frame {} nodes with mass, {} cells, about {} at the start (grid_NNNNNN.vtu)\n", g.points,
          g.cells, app::byte_size(g.bytes));
      frame_bytes += g.bytes;
    }
    print_length(c, dt, output_dir, frame_bytes);
  }
  say("memory     about {:.1f} MB\n", static_cast<double>(m.bytes()) / 1e6);
  say("threads    {}\n", omp_get_max_threads());
}

// A staged run: each stage, what it changes and how it ends.
void print_stages(const Config& c) {
  const auto names = [&](const std::vector<int>& bodies) {
    std::string r;
    for (const int b : bodies) r += fmt::format("{}\"{}\"", r.empty() ? "" : ", ", c.bodies[static_cast<std::size_t>(b)].name);
    return r;
  };
  for (std::size_t k = 0; k < c.stages.size(); ++k) {
    const StageConfig& st = c.stages[k];
    const StageEnd& e = st.end;
    std::vector<std::string> ends;
    if (e.duration) ends.push_back(fmt::format("after {:g} s", *e.duration));
    if (e.steps > 0) ends.push_back(fmt::format("after {} steps", e.steps));
    if (e.unbalanced_force_ratio) ends.push_back(fmt::format("unbalanced-force ratio < {:g}", *e.unbalanced_force_ratio));
    if (e.kinetic_energy_ratio) ends.push_back(fmt::format("kinetic-energy ratio < {:g}", *e.kinetic_energy_ratio));
    if (e.recorder >= 0)
      ends.push_back(fmt::format("{} {}", c.recorders[static_cast<std::size_t>(e.recorder)].name,
                                 e.above ? fmt::format(">= {:g}", *e.above) : fmt::format("<= {:g}", *e.below)));
    if (e.max_steps > 0) ends.push_back(fmt::format("at most {} steps", e.max_steps));
    std::string ends_text;
    for (const auto& x : ends) ends_text += (ends_text.empty() ? "" : ", ") + x;
    std::vector<std::string> changes;
    if (!st.remove.empty()) changes.push_back("removes " + names(st.remove));
    if (!st.add.empty()) changes.push_back("adds " + names(st.add));
    if (st.reset_displacements) changes.push_back("resets displacements");
    if (st.changes_gravity) changes.push_back("gravity");
    if (st.changes_boundary) changes.push_back("boundary");
    if (st.changes_loads) changes.push_back("loads");
    if (st.changes_materials) changes.push_back("materials");
    if (st.changes_solver) changes.push_back(fmt::format("solver (damping {})", st.config->solver.damping));
    if (!st.changes_motion.empty()) changes.push_back("motion of " + names(st.changes_motion));
    std::string change_text;
    for (const auto& x : changes) change_text += (change_text.empty() ? "" : ", ") + x;
    say("stage {:<4} \"{}\": ends {}{}\n", k + 1, st.name, ends_text,
               change_text.empty() ? std::string{} : fmt::format("; changes {}", change_text));
  }
}

void print_length(const Config& c, double dt, const std::string& output_dir, double frame_bytes) {
  // To the time a recorder will stop the run when that can be foreseen, else to time.end.
  const auto stop = forecast_stop(c);
  Config to_stop = c;
  if (stop) to_stop.time.end = stop->time;
  const RunLength length = estimate_run_length(to_stop, dt);
  say("steps      about {:.0f} to t = {:.6g} s{}\n", length.steps, to_stop.time.end,
             c.time.max_steps > 0 && length.steps >= static_cast<double>(c.time.max_steps)
                 ? fmt::format(" (stopped by time.max_steps = {})", c.time.max_steps)
             : stop ? fmt::format(", where {} reaches {:g} and stops the run (time.end = {} s)", stop->recorder,
                                  stop->bound, c.time.end)
                    : std::string{});
  for (const auto& r : c.recorders) {
    const char* note = stop ? "" : " (maybe before time.end: then fewer steps and frames than estimated here)";
    if (r.stop_above) say("stop       when {} >= {:g}{}\n", r.name, *r.stop_above, note);
    if (r.stop_below) say("stop       when {} <= {:g}{}\n", r.name, *r.stop_below, note);
  }
  // The frames' size against the space free where they go: a model of 4e6 particles with 99,801
  // frames (~100 TB) passed `check` (issue 41, defect 10). Said, not refused: a recorder may stop
  // the run early, and space may be freed meanwhile. global.csv, a few hundred bytes a row, is left out.
  const double bytes = length.frames * frame_bytes;
  say("output     {} ({:.0f} frames{}{})\n", output_dir, length.frames,
      frame_bytes > 0.0 ? fmt::format(" of about {}, {} in all", app::byte_size(frame_bytes), app::byte_size(bytes))
                        : std::string{},
      c.output.global_interval > 0 ? fmt::format(", global.csv every {} s", c.output.global_interval)
                                   : ", global.csv every step");
  if (const double free = app::free_space(output_dir); free >= 0.0 && bytes > free)
    say(stderr,
        "warning: the frames would take about {}, more than the {} free on the file system of {}; choose a larger "
        "output.interval or fewer output.fields\n",
        app::byte_size(bytes), app::byte_size(free), output_dir);
}

template <int D>
int check(const Config& c) {
  check_output_paths(c, c.output.directory, checkpoint_path(c, c.output.directory));
  const Model<D> m = build_model<D>(c);
  make_recorders<D>(c, m);  // an empty particle set is an input error
  check_stages<D>(m, c);    // what a later stage would meet at its start
  warn_at_start<D>(c, m);
  const double dt_crit = critical_time_step<D>(m.particles, c.materials, m.grid.h);
  if (!c.staged()) check_run_length(c, next_time_step(c.time, dt_crit, 0, c.source));
  print_summary<D>(c, m, c.output.directory);
  say("input is valid\n");
  return exit_code::ok;
}

// "tsuchi run FILE -o DIR --set ...": how to continue this run, less "--restart CHECKPOINT".
std::string resume_command(const Options& o) {
  std::string r = "tsuchi run " + shell_word(o.file);
  if (!o.output.empty()) r += " -o " + shell_word(o.output);
  for (const auto& s : o.overrides) r += " --set " + shell_word(s);
  return r;
}

template <int D>
int run(const Config& c, const Options& o) {
  Model<D> m = build_model<D>(c);
  make_recorders<D>(c, m);  // an empty particle set is an input error, found before the summary
  check_stages<D>(m, c);    // and what a later stage would meet at its start, not hours into the run
  if (o.restart.empty()) warn_at_start<D>(c, m);
  if (!o.quiet) print_summary<D>(c, m, o.output.empty() ? c.output.directory : o.output);
  RunOptions ro;
  ro.resume_command = resume_command(o);
  if (!o.output.empty()) ro.output_directory = o.output;
  if (!o.restart.empty()) {
    ro.restart = o.restart;
    if (!o.quiet) say("restart    from {}\n", o.restart);
  }
  app::ProgressReporter reporter(stderr);
  Progress last;
  app::BusyMachineMonitor busy(omp_get_max_threads());
  ro.on_progress = [&](const Progress& p) {
    last = p;
    if (!o.quiet) reporter.update(p);
    if (const auto w = busy.sample()) reporter.note("warning: " + *w);
  };
  ro.on_warning = [&](const std::string& w) { reporter.note("warning: " + app::shown(w)); };
  ro.on_stage_end = [&](const StageReport& r) {
    if (r.equilibrium_asked && !r.reached_equilibrium())
      say(stderr, "warning: stage \"{}\" reached {} before equilibrium; {}\n", r.name, r.end,
                 r.stage < r.stages ? "the next stage starts from a state that is not at rest"
                                    : "the analysis ends in a state that is not at rest");
    if (o.quiet) return;
    reporter.finish(last);
    say("stage {}/{} \"{}\": {} at step {} (t = {:.6g} s), {} steps, unbalanced-force ratio {:.3g}\n", r.stage,
               r.stages, r.name, r.end, r.end_step, r.end_time, r.end_step - r.start_step, r.unbalanced_force_ratio);
  };
  const RunSummary s = run_simulation<D>(m, c, ro);
  if (!o.quiet && !c.staged()) reporter.finish(last);
  // The steps of this process: a restart's earlier steps took no time here.
  const double rate =
      s.wall_seconds > 0 ? static_cast<double>(s.steps_taken) * static_cast<double>(m.particles.size()) / s.wall_seconds : 0.0;
  if (!s.stopped_by.empty()) say("stopped: {}\n", s.stopped_by);
  // A single-stage run cut short by its step limit: say so, as a staged run does (not an error:
  // the limit is the input's own).
  if (s.stopped_by.empty() && !c.staged() && c.time.max_steps > 0 && s.steps >= c.time.max_steps &&
      s.time < c.time.end * (1.0 - 1e-12))
    say("stopped: time.max_steps = {} reached at t = {:.6g} s, before time.end = {:.6g} s\n", c.time.max_steps,
               s.time, c.time.end);
  if (!s.checkpoint.empty()) say("checkpoint: {}\n", s.checkpoint);
  say("done: {} steps to t = {:.6g} s in {:.2f} s ({:.3g} particle-steps/s); {} frames in {}\n", s.steps,
             s.time, s.wall_seconds, rate, s.frames, s.directory);
  return exit_code::ok;
}

// `tsuchi fos FILE`: the analysis, then the factor of safety by strength reduction.
template <int D>
int fos(const Config& c, const Options& o) {
  FosOptions fo;
  fo.output_directory = o.output.empty() ? c.output.directory : o.output;
  fo.quiet = o.quiet;
  fo.on_note = [&](const std::string& note) { say("{}\n", note); };
  app::BusyMachineMonitor busy(omp_get_max_threads());
  fo.on_trial = [&](const FosTrial& t) {
    say("trial {:>3}  F = {:<10.6g} {:<6} ({}) after {} steps, largest displacement {:.4g} m, ratio {:.3g}, {:.1f} s\n",
               t.index, t.factor, t.failed ? "fails" : "stands", t.reason, t.steps, t.max_displacement,
               t.unbalanced_force_ratio, t.wall_seconds);
    if (const auto w = busy.sample()) say(stderr, "warning: {}\n", *w);
  };
  Model<D> m = build_model<D>(c);
  make_recorders<D>(c, m);  // input errors before the summary, as for `run`
  check_stages<D>(m, c);
  warn_at_start<D>(c, m);
  if (!o.quiet) print_summary<D>(c, m, fo.output_directory);
  const FosResult r = factor_of_safety<D>(c, std::move(m), fo);
  say("bracket: stands at F = {:.6g}, fails at F = {:.6g} ({} trials); trials, stable.vtu and mechanism.vtu in {}\n",
             r.lower, r.upper, r.trials.size(), r.directory);
  if (r.bound.empty())
    say("factor of safety: {:.4g}\n", r.factor);
  else
    say("factor of safety: at least {:.4g} (a bound, not the factor): {}\n", r.lower, r.bound);
  return exit_code::ok;
}

// The most threads --threads takes (a larger number is a usage error); any request is then held to
// the CPUs the process may use (cpus.hpp).
constexpr int max_threads = 1024;

// The thread count: --threads, else OMP_NUM_THREADS (its first level: "8,4" gives 8), else every
// usable CPU; at most the usable CPUs, with a warning when a request asked for more (OMP_NUM_THREADS
// = 100000 crashed libgomp; 1024 on 2 cores failed to create its threads under a memory limit, or
// ran 1000x slower). Set before the first parallel region, so libgomp never starts more.
void choose_threads(int requested_option) {
  const app::UsableCpus cpus = app::usable_cpus();
  long requested = requested_option;
  std::string source = fmt::format("--threads {}", requested_option);
  if (requested <= 0) {
    if (const char* env = std::getenv("OMP_NUM_THREADS")) {
      char* end = nullptr;
      errno = 0;
      requested = std::strtol(env, &end, 10);
      if (end == env || requested <= 0) requested = 0;  // libgomp's own reading then stands
      if (errno == ERANGE) requested = std::numeric_limits<long>::max();
      source = fmt::format("OMP_NUM_THREADS={}", app::shown(env));
    }
  }
  if (requested <= 0) {
    if (omp_get_max_threads() > cpus.count) omp_set_num_threads(cpus.count);
    return;
  }
  if (requested > cpus.count) {
    say(stderr,
        "warning: {} asks for more threads than the {} {}; using {}: more threads than CPUs only wait on each "
        "other (results do not depend on the count)\n",
        source, cpus.count, cpus.what, cpus.count);
    requested = cpus.count;
  }
  omp_set_num_threads(static_cast<int>(requested));
}

int dispatch(bool run_it, const Options& o, bool fos_it = false) {
  choose_threads(o.threads);
  const Config c = read_config_file(o.file, o.overrides);
  for (const auto& w : c.warnings) say(stderr, "warning: {}\n", tsuchi::app::shown(w));
  // A busy output directory stops a run before it builds its model (which may take long).
  if (run_it || fos_it) DirectoryLock::refuse_if_held(o.output.empty() ? c.output.directory : o.output);
  if (fos_it) return c.dimension == 2 ? fos<2>(c, o) : fos<3>(c, o);
  if (c.dimension == 2) return run_it ? run<2>(c, o) : check<2>(c);
  return run_it ? run<3>(c, o) : check<3>(c);
}

}  // namespace

int main(int argc, char** argv) {
  // MPI when a launcher (mpirun) started the process: before the command line, which MPI may edit.
  const tsuchi::comm::Session mpi(argc, argv);
  CLI::App app{"tsuchi: GIMP / MPM solver for large-deformation geomechanics"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("tsuchi ") + version);
  app.footer(
      "Every input key, its unit and default: docs/input.md (in the source tree).\n"
      "Exit codes: 0 done (also when a recorder stops the run), 1 command line, 2 input, 3 run fault,\n"
      "  4 output (also: another run holds the output directory), 5 internal error, 6 non-finite state,\n"
      "  7 particle left the grid, 8 volume collapse, 9 time step above the stable limit,\n"
      "  130 / 143 / 129 interrupted by SIGINT / SIGTERM / SIGHUP after the state was saved.");
  Options o;
  // `-o "$OUT"` with OUT unset is `-o ''`: taken as "not given", the run would go to the input's
  // output.directory and remove an earlier run's frames there. Refused, as --set output.directory="" is.
  const CLI::Validator a_path(
      [](std::string& v) {
        return v.empty() ? std::string("expected a path, got an empty one (an unset shell variable?)") : std::string();
      },
      "PATH");
  auto* run_cmd = app.add_subcommand("run", "Run the model in an input file");
  run_cmd->add_option("file", o.file, "Input file (TOML)")->required();
  run_cmd->add_option("-o,--output", o.output, "Output directory (overrides output.directory)")->check(a_path);
  run_cmd->add_option("-s,--set", o.overrides, "Override an input key, e.g. --set time.end=0.5")
      ->allow_extra_args(false);
  run_cmd->add_flag("-q,--quiet", o.quiet, "No summary or progress");
  run_cmd->add_option("-r,--restart", o.restart, "Continue from a checkpoint written by a run of the same input")
      ->check(a_path);
  run_cmd->add_option("-j,--threads", o.threads, "Threads (default: OMP_NUM_THREADS, else every core); results do not depend on it")
      ->check(CLI::Range(1, max_threads));
  auto* check_cmd = app.add_subcommand("check", "Validate an input file and print the model summary");
  check_cmd->add_option("file", o.file, "Input file (TOML)")->required();
  check_cmd->add_option("-s,--set", o.overrides, "Override an input key")
      ->allow_extra_args(false);
  auto* fos_cmd = app.add_subcommand(
      "fos", "Run the analysis, then find its factor of safety by strength reduction ([fos] in the input)");
  fos_cmd->add_option("file", o.file, "Input file (TOML) with a [fos] table")->required();
  fos_cmd->add_option("-o,--output", o.output, "Output directory (overrides output.directory); the search writes to its fos/")
      ->check(a_path);
  fos_cmd->add_option("-s,--set", o.overrides, "Override an input key, e.g. --set fos.tolerance=0.005")->allow_extra_args(false);
  fos_cmd->add_flag("-q,--quiet", o.quiet, "No summary");
  fos_cmd->add_option("-j,--threads", o.threads, "Threads (default: OMP_NUM_THREADS, else every core); results do not depend on it")
      ->check(CLI::Range(1, max_threads));
  tsuchi::app::ElementOptions eo;
  auto* element_cmd =
      app.add_subcommand("element", "Drive one material point along a stress/strain path (a lab test) to CSV");
  element_cmd->add_option("file", eo.file, "Element-test input file (TOML)")->required();
  element_cmd->add_option("-o,--output", eo.output, "CSV file to write (default: FILE's name with .csv, here)")
      ->check(a_path);
  element_cmd->add_option("-s,--set", eo.overrides, "Override an input key, e.g. --set test.confining_pressure=1e5")
      ->allow_extra_args(false);
  element_cmd->add_flag("-q,--quiet", eo.quiet, "No summary, only the final lines");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 says "A subcommand is required" for `tsuchi`, `tsuchi frobnicate` and `tsuchi --bogus`
    // alike: name what was given and the commands there are.
    if (dynamic_cast<const CLI::RequiredError*>(&e) && !run_cmd->parsed() && !check_cmd->parsed() &&
        !fos_cmd->parsed() && !element_cmd->parsed()) {
      std::string names;
      for (const auto* sub : app.get_subcommands([](const CLI::App*) { return true; }))
        names += (names.empty() ? "" : ", ") + sub->get_name();
      if (argc < 2)
        say(stderr, "expected a command: one of {} (tsuchi --help)\n", names);
      else
        say(stderr, "unknown {} '{}': expected a command first, one of {} (tsuchi --help)\n",
            argv[1][0] == '-' ? "option" : "command", app::shown(argv[1]), names);
      return exit_code::usage;
    }
    return app.exit(e) == 0 ? exit_code::ok : exit_code::usage;
  }
  // Several processes: the step does not yet divide the model between them (issue 42,
  // docs/issue42-design.md), and N copies of one run would race for one output directory. Said
  // once, by the first process; every process exits with the same code.
  if (const tsuchi::comm::Communicator world = tsuchi::comm::Communicator::world(); world.size() > 1) {
    if (world.rank() == 0)
      say(stderr,
          "tsuchi on {} processes: distributed runs (mpirun -np N) are not built yet; start it as one process "
          "(tsuchi {} ...), with --threads for this machine's cores\n",
          world.size(), argc > 1 ? app::shown(argv[1]) : std::string("run"));
    return exit_code::usage;
  }
  // Line by line: piped into one log, the summary (stdout) comes before the progress (stderr).
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  // A full disk or a file-size limit should be an error message, not a silent kill.
  std::signal(SIGXFSZ, SIG_IGN);
  // A closed pipe (`tsuchi run ... | head -1`) must not kill a run: its writes to the terminal
  // fail and are dropped (console.hpp), and its files and checkpoint are written on.
  std::signal(SIGPIPE, SIG_IGN);
  try {
    if (element_cmd->parsed()) return tsuchi::app::run_element_command(eo);
    if (run_cmd->parsed()) install_interrupt_handlers();
    return dispatch(run_cmd->parsed(), o, fos_cmd->parsed());
  } catch (const InputError& e) {
    say(stderr, "\nerror in input: {}\n", tsuchi::app::shown(e.what()));
    return exit_code::input;
  } catch (const RunError& e) {
    say(stderr, "\nrun stopped: {}\n", tsuchi::app::shown(e.what()));
    return exit_code::of(e.fault);
  } catch (const Interrupted& e) {
    say(stderr, "\ninterrupted: {}\n", tsuchi::app::shown(e.what()));
    return 128 + e.signal;
  } catch (const OutputError& e) {
    say(stderr, "\noutput failed: {}\n", tsuchi::app::shown(e.what()));
    return exit_code::output;
  } catch (const std::bad_alloc&) {
    // The model's estimate passed the pre-check (model.cpp, check_memory) but the allocation did
    // not: other processes took memory since, or the estimate missed a part (recorders, contact).
    const tsuchi::MemoryLimit limit = tsuchi::memory_limit();
    say(stderr,
        "\nout of memory: an allocation failed{}; the summary's `memory` line is the model's estimate: choose a "
        "larger grid.cell_size or fewer particles_per_cell, or raise the limit\n",
        limit.bytes > 0.0 ? fmt::format(" with {:.3g} GB {}", limit.bytes / 1e9, limit.what) : std::string{});
    return exit_code::internal;
  } catch (const std::exception& e) {
    say(stderr, "\ninternal error: {}\n", tsuchi::app::shown(e.what()));
    return exit_code::internal;
  }
}
