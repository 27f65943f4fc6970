#pragma once
// The CPUs a run may use, and whether it gets them. More threads than CPUs only wait on each other
// at every barrier of the step (issue 41: --threads 1024 on 2 cores ran 1000x slower, or libgomp
// failed to create them and exited with no word from tsuchi); and a machine busy with other work
// slows every thread of a step to the pace of the most delayed one (a piece that takes 4.4 s alone
// took 15.7 s beside one busy core). Results do not depend on the thread count, so the count is
// bounded by the CPUs, and a run whose threads wait for a CPU says so once.
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

namespace tsuchi::app {

// The CPUs this process may run on: its affinity mask (taskset, a batch scheduler's cpuset), and a
// cgroup CPU quota (cpu.max in v2, cpu.cfs_quota_us / cpu.cfs_period_us in v1; a container's
// --cpus) rounded up. With what bounds it, as a phrase.
struct UsableCpus {
  int count = 1;
  std::string what;
};
UsableCpus usable_cpus();

// The share of the time this process's threads spent waiting for a CPU while runnable
// (/proc/self/task/*/schedstat), judged over windows of `window` once a run has gone on that long.
class BusyMachineMonitor {
 public:
  explicit BusyMachineMonitor(int threads, std::chrono::duration<double> window = std::chrono::seconds(3));
  // Called after every step (cheap between windows). Returns, once, the warning of a window in
  // which the threads waited for a CPU more than a fifth of the time they were runnable.
  std::optional<std::string> sample();

 private:
  int threads_;
  std::chrono::duration<double> window_;
  std::chrono::steady_clock::time_point last_;
  double run_ns_ = 0.0, wait_ns_ = 0.0;
  bool first_ = true, said_ = false;
};

}  // namespace tsuchi::app
