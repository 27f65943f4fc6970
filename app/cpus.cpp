#include "cpus.hpp"

#include "tsuchi/core/cgroup.hpp"

#include <fmt/format.h>

#include <sched.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace tsuchi::app {

namespace {

// The tightest CPU quota of the process's cgroup and its parents, in CPUs, or 0 when none sets
// one (v2 cpu.max "max 100000" or "200000 100000"; v1 cpu.cfs_quota_us over cpu.cfs_period_us,
// -1 for none).
double cgroup_quota() {
  double least = 0.0;
  auto take = [&](double cpus) {
    if (cpus > 0.0 && (least == 0.0 || cpus < least)) least = cpus;
  };
  for (const std::string& dir : cgroup_v2_dirs()) {
    std::ifstream f(dir + "/cpu.max");
    std::string quota;
    double period = 0.0;
    if (f >> quota >> period && quota != "max" && period > 0.0) take(std::strtod(quota.c_str(), nullptr) / period);
  }
  for (const std::string& dir : cgroup_v1_dirs("cpu")) {
    double quota = 0.0, period = 0.0;
    if (read_cgroup_number(dir + "/cpu.cfs_quota_us", quota) && read_cgroup_number(dir + "/cpu.cfs_period_us", period) &&
        period > 0.0)
      take(quota / period);
  }
  return least;
}

// Run and wait times (ns) of every thread of this process, summed.
bool schedule_times(double& run, double& wait) {
  run = wait = 0.0;
  std::error_code ec;
  bool any = false;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task", ec)) {
    std::ifstream f(task.path() / "schedstat");
    double r = 0.0, w = 0.0;
    if (f >> r >> w) run += r, wait += w, any = true;
  }
  return any;
}

}  // namespace

UsableCpus usable_cpus() {
  UsableCpus u;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) {
    u.count = CPU_COUNT(&set);
    u.what = "CPUs this process may run on (its affinity mask)";
  }
  if (const double quota = cgroup_quota(); quota > 0.0 && std::ceil(quota) < u.count) {
    u.count = static_cast<int>(std::ceil(quota));
    u.what = fmt::format("CPUs of its cgroup's quota ({:.3g})", quota);
  }
  if (u.count < 1) u.count = 1;
  return u;
}

BusyMachineMonitor::BusyMachineMonitor(int threads, std::chrono::duration<double> window)
    : threads_(threads), window_(window), last_(std::chrono::steady_clock::now()) {}

std::optional<std::string> BusyMachineMonitor::sample() {
  if (said_) return std::nullopt;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_ < window_) return std::nullopt;
  last_ = now;
  double run = 0.0, wait = 0.0;
  if (!schedule_times(run, wait)) return said_ = true, std::nullopt;  // no schedstat: nothing to judge
  const double d_run = run - run_ns_, d_wait = wait - wait_ns_;
  run_ns_ = run, wait_ns_ = wait;
  // The first window starts at the run's start, when the threads of the set-up and the first
  // frame's writing were not yet all at work: it only sets the base.
  if (first_) return first_ = false, std::nullopt;
  if (!(d_run + d_wait > 0.0) || d_wait <= 0.2 * (d_run + d_wait)) return std::nullopt;
  said_ = true;
  return fmt::format(
      "this run's {} thread{} waited for a CPU {:.0f} % of the time they were ready to run in the last {:.0f} s: "
      "the machine is busy with other work{}",
      threads_, threads_ == 1 ? "" : "s", 100.0 * d_wait / (d_run + d_wait), window_.count(),
      threads_ > 1 ? fmt::format(", and each step waits for its most delayed thread; fewer threads (--threads {}) "
                                 "may be faster, and results do not depend on the count",
                                 std::max(1, threads_ / 2))
                   : std::string{});
}

}  // namespace tsuchi::app
