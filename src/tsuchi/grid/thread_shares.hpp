#pragma once
// How many of the particles each thread's part of the grid holds (block_schedule.hpp), from how
// fast each thread has been going.
//
// The parts used to be cut at equal particle counts, which assumes equal cores. They are often not:
// a laptop's efficiency cores run at about half the speed of its performance cores, a core shared
// with another process gives a thread what the kernel leaves it, and on the team's 2-vCPU machine
// one vCPU ran the same one-thread job 25 % slower than the other for hours. With equal parts the
// faster thread waits at the end of every colour of every scatter for the slower one.
//
// So each thread times its own work in the passes that follow the parts (busy time only: from
// entering its blocks of a colour to leaving them, never the wait at a barrier) and counts the
// particles it took. Once per step its speed s_t (particles per second) is smoothed,
//   s_t <- (1 - a) s_t + a n_t / T_t,      a = 0.2 (about five steps of memory),
// and its share of the particles becomes s_t / sum s, raised to at least a quarter of the even
// share before the shares are scaled to sum 1 (a thread that was stopped for a moment keeps some
// work and goes on being measured). The parts
// are cut again only when a share moved by more than `kRecut`, which keeps the cut from following
// the noise of single steps. Which thread takes which block changes no result: blocks of one colour
// write disjoint nodes and every node sums its colours in one order (block_schedule.hpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace tsuchi {

class ThreadShares {
 public:
  static constexpr double kSmoothing = 0.2;   // a, the weight of the latest step
  static constexpr double kRecut = 0.01;      // change of a share that cuts the parts again
  static constexpr double kFloor = 0.25;      // least share, as a fraction of the even one

  // Even shares for `threads`, no history: on the first step, and whenever the thread count changes.
  void reset(int threads) {
    const auto T = static_cast<std::size_t>(std::max(threads, 1));
    slots_.assign(T, Slot{});
    speed_.assign(T, 0.0);
    share_.assign(T, 1.0 / static_cast<double>(T));
  }
  int threads() const { return static_cast<int>(share_.size()); }

  // A thread's busy time and particle count in one timed pass. Each thread writes only its own
  // slot (one cache line each), so this needs no lock.
  void add(std::size_t thread, double seconds, std::int64_t particles) const {
    Slot& s = slots_[thread];
    s.seconds += seconds;
    s.particles += particles;
  }

  // Once per step, outside any parallel region: folds the step's timings into the speeds and
  // returns whether the shares moved by more than kRecut (then the parts are cut again). A step in
  // which some thread timed nothing leaves everything as it was.
  bool update() {
    const std::size_t T = slots_.size();
    bool timed = T > 1;
    for (const Slot& s : slots_) timed = timed && s.seconds > 0.0 && s.particles > 0;
    if (timed)
      for (std::size_t t = 0; t < T; ++t) {
        const double sample = static_cast<double>(slots_[t].particles) / slots_[t].seconds;
        speed_[t] = speed_[t] > 0.0 ? (1.0 - kSmoothing) * speed_[t] + kSmoothing * sample : sample;
      }
    for (Slot& s : slots_) s = Slot{};
    if (!timed) return false;
    double total = 0.0;
    for (const double s : speed_) total += s;
    const double even = 1.0 / static_cast<double>(T), least = kFloor * even;
    std::vector<double> share(T);
    double sum = 0.0;
    for (std::size_t t = 0; t < T; ++t) sum += share[t] = std::max(speed_[t] / total, least);
    double moved = 0.0;
    for (std::size_t t = 0; t < T; ++t) moved = std::max(moved, std::abs(share[t] / sum - share_[t]));
    if (moved <= kRecut) return false;
    for (std::size_t t = 0; t < T; ++t) share_[t] = share[t] / sum;
    return true;
  }

  // Thread t's fraction of the particles; they sum to 1.
  const std::vector<double>& shares() const { return share_; }
  // Fixed shares (tests: any cut must give the same results); kept until the next update that
  // moves them.
  void set(const std::vector<double>& share) { share_ = share; }

 private:
  struct alignas(64) Slot {
    double seconds = 0.0;
    std::int64_t particles = 0;
  };
  mutable std::vector<Slot> slots_;
  std::vector<double> speed_;  // smoothed particles per second, per thread; 0 before the first sample
  std::vector<double> share_;
};

}  // namespace tsuchi
