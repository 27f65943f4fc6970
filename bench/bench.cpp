// tsuchi-bench: particle-steps per second, wall time per step and memory per particle of the
// explicit step, on 1 thread and on every core:
//   - the paper's triaxial test 3 with the cap fixed (5500 particles, Mohr-Coulomb), timed after
//     loading to 2 % axial strain so that particles are yielding; and the same with the cap a rigid
//     platen in frictional contact with the specimen ([[contact]], mu = 0.3: two velocity fields);
//   - an elastic block under gravity on a fixed floor (GIMP, MUSL) at 1e4, 1e5 and 1e6 particles
//     in 2D, and 1e6 in 3D: the cost per particle-step should not grow with the size;
//   - whole runs: bench/cases/triaxial_2d.toml (5,500 particles) and slab_3d.toml (the same
//     geometry as a 3D slab one cell thick, 6,000 particles), the cases the team times beside
//     CB-Geo and MPM-Geomechanics, each read, built and run for its 2,000 steps as `tsuchi run`
//     does with output off; the figure counts every second from reading the input to the end,
//     and the share of it spent outside the steps (start-up) is reported beside it. And
//     examples/triaxial_3d/test2_cylinder.toml's first 500 steps (13,904 particles, to 0.24 %
//     axial strain): a confined 3D specimen every point of which is still inside the yield
//     surface (its yielded_fraction recorder reads 0), as most points of most 3D models are;
//     slab_3d's points sit on their 1 Pa tension cut-off. What an elastic 3D point costs.
//   - the host's price of a parallel stage (--sync, and at the end of a full run): an empty
//     parallel region (fork and join) and a barrier, on every core. Each step pays a fixed number
//     of both (scripts/count-omp-regions.sh counts them), whatever the particle loops cost.
// Usage: tsuchi-bench [--quick | --triaxial | --whole | --sync]   (quick: small cases, a smoke run
// of a few seconds; triaxial: only the triaxial case, for profiling; whole: only the whole runs;
// sync: only the region and barrier costs)
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/run/simulation.hpp"
#include "tsuchi/solver/explicit_step.hpp"
#include "tsuchi/solver/time_step.hpp"

#include <fmt/format.h>

#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using namespace tsuchi;

std::string block_input(int dim, int cells_per_side) {
  const double h = 1.0 / cells_per_side;
  const std::string three = dim == 3 ? ", 0.0" : "";
  const std::string ext = dim == 3 ? ", 1.5" : "";
  return fmt::format(R"(
[model]
dimension = {0}
gravity = [0.0, -9.81{1}]
[grid]
origin = [0.0, 0.0{1}]
extent = [1.5, 1.5{2}]
cell_size = {3}
[[materials]]
name = "elastic"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[[bodies]]
material = "elastic"
min = [0.25, 0.0{1}]
max = [1.25, 1.0{4}]
particles_per_cell = 2
[boundary]
y_min = "fixed"{5}
[solver]
scheme = "musl"
shape_function = "gimp"
[time]
end = 1.0
courant = 0.5
[output]
frames = false
)",
                     dim, three, ext, h, dim == 3 ? ", 1.0" : "",
                     // The 3D block lies on the grid's z_min face, which holds nothing when free
                     // (issue 41, defect 1): on rollers there, as the free face held it before.
                     dim == 3 ? "\nz_min = \"roller\"" : "");
}

struct Figures {
  double rate = 0.0, best_rate = 0.0, wall_per_step = 0.0, bytes_per_particle = 0.0;
  std::vector<double> shares;  // each thread's fraction of the particles at the end (thread_shares.hpp)
};

// Times `steps` steps after one warm-up step on `threads` threads, in five batches: the figures
// are the median batch's (a shared host slows some batches down) and the best batch's rate.
template <int D>
Figures time_steps(Model<D>& m, int steps, int threads) {
  omp_set_num_threads(threads);
  ExplicitSolver<D> solver(m);
  const double dt = 0.5 * critical_time_step<D>(m.particles, m.materials, m.grid.h);
  solver.step(dt);  // warm-up: first touch of every array
  constexpr int kBatches = 5;
  const int per_batch = std::max(1, steps / kBatches);
  std::vector<double> walls;
  for (int b = 0; b < kBatches; ++b) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int s = 0; s < per_batch; ++s) solver.step(dt);
    walls.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(walls.begin(), walls.end());
  const double n = static_cast<double>(m.particles.size());
  const double median = walls[kBatches / 2] / per_batch;
  return {n / median, n / (walls.front() / per_batch), median, static_cast<double>(m.bytes()) / n,
          solver.schedule().thread_shares()};
}

double peak_rss_mb() {
  rusage r{};
  getrusage(RUSAGE_SELF, &r);
  return static_cast<double>(r.ru_maxrss) / 1024.0;
}

void report(const std::string& name, std::size_t particles, int threads, const Figures& f) {
  fmt::print("{:<34} {:>9} particles  {} thread{}  {:.3e} particle-steps/s (best batch {:.3e})  {:8.3f} ms/step"
             "  {:5.0f} bytes/particle  peak RSS {:.0f} MB\n",
             name, particles, threads, threads > 1 ? "s" : " ", f.rate, f.best_rate, 1e3 * f.wall_per_step,
             f.bytes_per_particle, peak_rss_mb());
  // How the threads' parts ended: far from even, one core ran slower than the others (another
  // process, a busy host, an efficiency core), and the multi-thread figure says as much about it.
  if (threads > 1 && f.shares.size() == static_cast<std::size_t>(threads))
    fmt::print("{:<34} thread parts at the end: {:.2f}\n", "", fmt::join(f.shares, " / "));
}

template <int D>
void block(int cells_per_side, int steps, const std::vector<int>& threads) {
  for (int t : threads) {
    Model<D> m = build_model<D>(read_config_string(block_input(D, cells_per_side), "bench"));
    report(fmt::format("{}D elastic block, GIMP, MUSL", D), m.particles.size(), t, time_steps<D>(m, steps, t));
  }
}

std::string read_text(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw std::runtime_error("cannot open " + path);
  std::string text;
  char buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) text.append(buf, n);
  std::fclose(f);
  return text;
}

// The paper's triaxial test 3, cap fixed: 5500 particles, Mohr-Coulomb, GIMP, MUSL, damping; with
// `contact`, the cap (prescribed in x and y: rigid) meets the specimen through [[contact]], mu 0.3.
void triaxial(int steps, const std::vector<int>& threads, bool contact = false) {
  const std::string file = std::string(TSUCHI_SOURCE_DIR) + "/examples/triaxial/test3_fixed.toml";
  std::string text = read_text(file);
  if (contact) text += "\n[[contact]]\nbodies = [\"cap\", \"specimen\"]\nfriction = 0.3\n";
  for (int t : threads) {
    Model<2> m = build_model<2>(read_config_string(text, file, {"output.frames=false"}));
    // Load it to 2 % axial strain first, so that the timed steps include plastic returns.
    omp_set_num_threads(t);
    ExplicitSolver<2> pre(m);
    const double dt = 0.5 * critical_time_step<2>(m.particles, m.materials, m.grid.h);
    while (pre.time() < 0.1) pre.step(dt);
    report(contact ? "triaxial test 3, cap in contact" : "triaxial test 3, cap fixed (MC)", m.particles.size(), t,
           time_steps<2>(m, steps, t));
  }
}

// A whole run of `file` on `threads` threads, as `tsuchi run FILE -q --threads N` with output off:
// wall time from reading the input to the end of the last step, in five rounds (median round
// reported). Start-up is the time before the first step began: from reading the input to the end
// of the first step, less the median of the run's step intervals.
template <int D>
void whole_run(const std::string& file, const std::string& name, int threads,
               const std::vector<std::string>& overrides = {}) {
  using Clock = std::chrono::steady_clock;
  omp_set_num_threads(threads);
  struct Round {
    double wall = 0.0, startup = 0.0;
  };
  std::vector<Round> rounds;
  std::int64_t steps = 0;
  std::size_t particles = 0;
  for (int r = 0; r < 5; ++r) {
    const auto t0 = Clock::now();
    const Config c = read_config_file(file, overrides);
    Model<D> m = build_model<D>(c);
    RunOptions options;
    options.write_output = false;
    std::vector<Clock::time_point> ends;
    ends.reserve(4096);
    const RunSummary s = run_simulation<D>(m, c, options, [&](const ExplicitSolver<D>&) { ends.push_back(Clock::now()); });
    const auto t1 = Clock::now();
    std::vector<double> intervals;
    for (std::size_t k = 1; k < ends.size(); ++k) intervals.push_back(std::chrono::duration<double>(ends[k] - ends[k - 1]).count());
    std::sort(intervals.begin(), intervals.end());
    const double step = intervals.empty() ? 0.0 : intervals[intervals.size() / 2];
    const double first_end = ends.empty() ? 0.0 : std::chrono::duration<double>(ends.front() - t0).count();
    rounds.push_back({std::chrono::duration<double>(t1 - t0).count(), std::max(0.0, first_end - step)});
    steps = s.steps;
    particles = m.particles.size();
  }
  std::sort(rounds.begin(), rounds.end(), [](const Round& a, const Round& b) { return a.wall < b.wall; });
  const Round& med = rounds[rounds.size() / 2];
  const double n = static_cast<double>(particles) * static_cast<double>(steps);
  fmt::print("{:<34} {:>9} particles  {} thread{}  {:.3e} particle-steps/s whole run (best round {:.3e})  {} steps "
             "in {:.3f} s, start-up {:.3f} s ({:.1f} %)  peak RSS {:.0f} MB\n",
             name, particles, threads, threads > 1 ? "s" : " ", n / med.wall, n / rounds.front().wall, steps, med.wall,
             med.startup, 100.0 * med.startup / med.wall, peak_rss_mb());
}

void whole_runs(const std::vector<int>& threads) {
  const std::string dir = std::string(TSUCHI_SOURCE_DIR) + "/bench/cases/";
  for (int t : threads) whole_run<2>(dir + "triaxial_2d.toml", "whole run: triaxial geometry, 2D", t);
  for (int t : threads) whole_run<3>(dir + "slab_3d.toml", "whole run: triaxial geometry, 3D slab", t);
  const std::string cylinder = std::string(TSUCHI_SOURCE_DIR) + "/examples/triaxial_3d/test2_cylinder.toml";
  for (int t : threads) whole_run<3>(cylinder, "whole run: 3D cylinder, 50 kPa", t, {"time.max_steps=500"});
}

// Microseconds per empty parallel region and per barrier on `threads` threads: the median of
// seven batches of 20,000 (the first batch also wakes the thread team).
void sync_costs(int threads) {
  using Clock = std::chrono::steady_clock;
  constexpr int kBatch = 20000;
  omp_set_num_threads(threads);
  std::vector<double> region, barrier;
  for (int r = 0; r < 7; ++r) {
    const auto t0 = Clock::now();
    for (int k = 0; k < kBatch; ++k) {
#pragma omp parallel
      {
        // Nothing to do: the region's fork and join is what is timed.
        asm volatile("" ::: "memory");
      }
    }
    const auto t1 = Clock::now();
#pragma omp parallel
    for (int k = 0; k < kBatch; ++k) {
#pragma omp barrier
    }
    const auto t2 = Clock::now();
    region.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count() / kBatch);
    barrier.push_back(std::chrono::duration<double, std::micro>(t2 - t1).count() / kBatch);
  }
  std::sort(region.begin(), region.end());
  std::sort(barrier.begin(), barrier.end());
  fmt::print("{:<34} {} threads  empty parallel region {:.2f} us, barrier {:.2f} us (median of 7 x {})\n",
             "OpenMP synchronisation", threads, region[3], barrier[3], kBatch);
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const bool only_triaxial = argc > 1 && std::strcmp(argv[1], "--triaxial") == 0;
  const bool only_whole = argc > 1 && std::strcmp(argv[1], "--whole") == 0;
  const bool only_sync = argc > 1 && std::strcmp(argv[1], "--sync") == 0;
  if (argc > 2 || (argc == 2 && !quick && !only_triaxial && !only_whole && !only_sync)) {
    std::fprintf(stderr, "usage: tsuchi-bench [--quick | --triaxial | --whole | --sync]\n");
    return 2;
  }
  // Line by line: a fault in a later case (an exception ends the program) keeps the figures so far.
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  const int cores = omp_get_num_procs();
  std::vector<int> threads{1};
  if (cores > 1) threads.push_back(cores);
  fmt::print("tsuchi-bench: {} cores\n", cores);
  if (only_sync) {
    sync_costs(cores);
    return 0;
  }
  if (quick) {
    triaxial(100, threads);
    triaxial(100, threads, true);
    block<2>(50, 20, threads);   // 10,000 particles
    block<3>(10, 10, threads);   // 8,000 particles
    return 0;
  }
  if (only_whole) {
    whole_runs(threads);
    return 0;
  }
  triaxial(2000, threads);
  triaxial(2000, threads, true);
  if (only_triaxial) return 0;
  whole_runs(threads);
  block<2>(50, 400, threads);    // 10,000 particles
  block<2>(158, 40, threads);    // 99,856 particles
  block<2>(500, 10, threads);    // 1,000,000 particles
  block<3>(50, 4, threads);      // 1,000,000 particles
  sync_costs(cores);
  return 0;
}
