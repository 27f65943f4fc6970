#pragma once
// Lock-free, deterministic particle-to-grid scatter on several threads.
//
// The grid is cut into blocks of B x B (x B) cells and each particle belongs to the block of the
// cell it sits in. The shape kernel declares its reach: how many nodes beyond the two of a
// particle's cell its stencil may write, below and above along an axis (Reach; 1 and 1 for the
// three GIMP nodes per axis with l_p <= L/2, 0 and 0 for the linear hat). Block b along an axis
// then writes nodes b B - below .. b B + B + above. Blocks get P colours per axis, cyclically
// (P^D in all), with P the least that keeps blocks P apart from writing a common node,
// (P - 1) B > below + above: P = 2 (4 colours in 2D, 8 in 3D) for every kernel reaching fewer than
// B nodes in all. The scatter runs colour by colour; inside a colour, blocks go to threads in any
// order, and inside a block particles go in increasing index. Every node therefore sums its
// contributions in one fixed order, whatever the number of threads: results are bitwise the same
// on 1 or N threads, with no lock or atomic.
//
// Brought up to date every step from the start-of-step positions: a pass that files each particle
// under its block, then, only if some particle changed block, a counting sort of the particle
// indices (8 bytes per particle in all).
#include "tsuchi/grid/grid.hpp"
#include "tsuchi/grid/thread_shares.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

namespace tsuchi {

template <int D>
class BlockSchedule {
 public:
  static constexpr int B = Grid<D>::T;         // cells per block per axis: a block is a tile

  // Nodes a stencil may reach beyond the two of the particle's cell, along an axis.
  struct Reach {
    int below = 0, above = 0;
    bool operator==(const Reach&) const = default;
  };
  template <class Kernel>
  static constexpr Reach reach_of() {
    static_assert(Kernel::reach_below >= 0 && Kernel::reach_above >= 0, "a kernel's reach counts nodes, >= 0");
    return {Kernel::reach_below, Kernel::reach_above};
  }
  // The three GIMP nodes per axis (l_p <= L/2).
  static constexpr Reach kGimpReach{1, 1};

  // Colours per axis: blocks P apart write disjoint nodes when (P - 1) B > below + above.
  static constexpr int colours_per_axis(Reach r) { return (r.below + r.above) / B + 2; }
  // Tiles on either side of a block that hold nodes its particles reach: the lowest node,
  // b B - below, lies ceil(below / B) tiles below; the highest, b B + B + above, 1 + above / B
  // tiles above. The larger of the two on both sides.
  static constexpr int tile_reach(Reach r) { return std::max((r.below + B - 1) / B, 1 + r.above / B); }
  // Today's kernels (GIMP, linear) keep the 2^D colours and the 3^D tiles around a block.
  static_assert(colours_per_axis(kGimpReach) == 2 && tile_reach(kGimpReach) == 1);
  static_assert(colours_per_axis(Reach{0, 0}) == 2 && tile_reach(Reach{0, 0}) == 1);

  // Files the particles at x by block and colours the blocks for a kernel of the given reach. The
  // particle order (order()) does not depend on the reach.
  void build(const Grid<D>& grid, const std::vector<Vec<D>>& x, Reach reach = kGimpReach);

  // The particles were reordered: the next build starts afresh.
  void invalidate() { valid_ = false; }

  // Calls f(i) for every particle, colour by colour, blocks of one colour in parallel.
  // Each thread takes the blocks of its own part of the grid (below) in every colour, and the
  // same part in every pass of a step, so a particle's data and most of its nodes stay in one
  // core's cache from pass to pass: on a host whose cores are far apart (a cache line took
  // 200 ns to cross between the two vCPUs of the team's machine) that matters more than handing
  // out blocks on demand. The parts follow the threads' measured speeds (thread_shares.hpp), so
  // that a slower core does not keep the others waiting at every colour.
  template <class F>
  void scatter(F&& f) const {
#pragma omp parallel
    {
      const Part part = my_part();
      for (std::size_t c = 0; c < colour_blocks_.size(); ++c) {
        if (c > 0) {
#pragma omp barrier
        }
        timed_blocks(c, c + 1, part, f);
      }
    }
  }

  // Calls f(i) for every particle on the threads of an enclosing parallel region, each thread
  // taking the blocks scatter() gives it, with no barrier between colours: for passes in which a
  // particle writes only its own data. Must be reached by every thread of the region.
  template <class F>
  void for_each_particle_in_region(F&& f) const {
    timed_blocks(0, colour_blocks_.size(), my_part(), f);
  }

  // For a pass of uneven cost per particle (the stress update: a yielding point costs several
  // times an elastic one, and they gather in shear bands): each thread takes its own part's blocks
  // first, one at a time and in order, then helps the others with what is left of theirs, so
  // that only the particles it takes over change cores. begin_balanced(passes) resets the
  // counters of that many passes before the enclosing parallel region; every thread of the region
  // then calls this with the same pass numbers. Each particle's update is its own, so which
  // thread takes it changes no result.
  void begin_balanced(std::size_t passes) const;
  template <class F>
  void for_each_particle_balanced(std::size_t pass, F&& f) const {
    const Part part = my_part();
    if (!part.cut) {
      for_each_particle_in_region(f);
      return;
    }
    Counter* next = next_.get() + pass * part.threads;
    for (std::size_t o = 0; o < part.threads; ++o) {
      const std::size_t t = (part.thread + o) % part.threads;
      const std::size_t first = block_cut_[t], last = block_cut_[t + 1];
      for (;;) {
        const std::size_t k = first + next[t].taken.fetch_add(1, std::memory_order_relaxed);
        if (k >= last) break;
        const std::int32_t b = blocks_in_order_[k];
        for (std::int64_t j = start_[b]; j < start_[b + 1]; ++j) f(static_cast<std::size_t>(order_[j]));
      }
    }
  }

  // The same in a parallel region of its own.
  template <class F>
  void for_each_particle(F&& f) const {
#pragma omp parallel
    for_each_particle_in_region(f);
  }

  // The non-empty blocks of each colour, in increasing index (a thread takes a run of each; for checks).
  const std::vector<std::vector<std::int32_t>>& colour_blocks() const { return colour_blocks_; }

  // Particle indices in block order: the order a locality-improving reordering would follow.
  const std::vector<std::int32_t>& order() const { return order_; }

  // Calls f(k) for every node slot of the active tiles, in parallel: the tiles of the non-empty
  // blocks and the tiles within tile_reach() of them, which hold every node a particle's stencil
  // reaches (a block is a tile). Nodes elsewhere carry nothing, so the grid loops skip them; a
  // tile is cleared by p2g when it becomes active. Each thread takes the tiles of its part of the
  // grid, where its particles scattered.
  template <class F>
  void for_active_nodes(F&& f) const {
    constexpr std::int64_t nodes = Grid<D>::kTileNodes;
#pragma omp parallel
    {
      const Part part = my_part();
      for (std::size_t t = part.first_tile; t < part.last_tile; ++t) {
        const std::int64_t first = active_tiles_[t] * nodes;
        for (std::int64_t k = first; k < first + nodes; ++k) f(k);
      }
    }
  }

  // The active tiles, increasing: for reductions that combine per-tile partial results in tile
  // order, the same for every thread count.
  const std::vector<std::int32_t>& active_tiles() const { return active_tiles_; }
  // Whether grid slot k lies on an active tile: one the latest p2g cleared and filled (the slots of
  // the other tiles hold stale values). A binary search, for the few listed nodes (held, loaded,
  // wall) that passes visit outside for_active_nodes.
  bool on_active_tile(std::int64_t k) const {
    return std::binary_search(active_tiles_.begin(), active_tiles_.end(), static_cast<std::int32_t>(k / Grid<D>::kTileNodes));
  }

  // Each thread's fraction of the particles in the parts now cut (sums to 1).
  const std::vector<double>& thread_shares() const { return shares_.shares(); }
  // Cuts the parts at the given fractions (one per thread of the team the schedule was built
  // for, summing to 1) until the measured speeds move them: for tests, which check that any cut
  // gives the same results.
  void cut_parts(const std::vector<double>& shares) {
    if (shares.size() != static_cast<std::size_t>(threads_))
      throw std::invalid_argument("BlockSchedule::cut_parts: one share per thread of the team it was built for");
    shares_.set(shares);
    partition(threads_, tiles_);
  }

 private:
  // A thread's part of the grid: a run of blocks in index order, cut where the particle count
  // reaches the thread's share (thread_shares.hpp; block indices run along x, then y, then z, so a
  // part is a slab; partition()); kept as positions in each colour's list (colour_cut_), in
  // blocks_in_order_ (block_cut_) and in active_tiles_ (tile_cut_).
  // A region of another thread count than the parts were cut for (a nested one) splits each
  // list evenly instead: blocks of one colour write disjoint nodes, so any split gives the same sums.
  struct Part {
    std::size_t thread = 0, threads = 1;
    bool cut = false;  // threads == threads_: the cut parts
    std::size_t first_tile = 0, last_tile = 0;
  };
  Part my_part() const;
  // The part's blocks of one colour; returns how many particles they hold.
  template <class F>
  std::int64_t run_blocks(std::size_t colour, const Part& part, F& f) const {
    const auto& blocks = colour_blocks_[colour];
    std::size_t lo = blocks.size() * part.thread / part.threads, hi = blocks.size() * (part.thread + 1) / part.threads;
    if (part.cut) {
      const std::size_t* cut = colour_cut_.data() + colour * (part.threads + 1);
      lo = cut[part.thread], hi = cut[part.thread + 1];
    }
    std::int64_t n = 0;
    for (std::size_t k = lo; k < hi; ++k) {
      const std::int32_t b = blocks[k];
      n += start_[b + 1] - start_[b];
      for (std::int64_t j = start_[b]; j < start_[b + 1]; ++j) f(static_cast<std::size_t>(order_[j]));
    }
    return n;
  }
  // Colours [first, last) of the part, timed for the shares when the parts were cut for a team of
  // several (two clock reads, about 30 ns each, per call).
  template <class F>
  void timed_blocks(std::size_t first, std::size_t last, const Part& part, F& f) const {
    using clock = std::chrono::steady_clock;
    const bool timed = part.cut && part.threads > 1;
    const clock::time_point start = timed ? clock::now() : clock::time_point{};
    std::int64_t n = 0;
    for (std::size_t c = first; c < last; ++c) n += run_blocks(c, part, f);
    if (timed) shares_.add(part.thread, std::chrono::duration<double>(clock::now() - start).count(), n);
  }
  void partition(int threads, const std::array<int, D>& tiles);

  int threads_ = 0;                             // the thread count the parts were cut for
  std::vector<std::size_t> colour_cut_;         // per colour, per thread + 1: positions in its list
  std::vector<std::size_t> tile_cut_;           // per thread + 1: positions in active_tiles_
  std::vector<std::int32_t> blocks_in_order_;   // the non-empty blocks, increasing
  std::vector<std::size_t> block_cut_;          // per thread + 1: positions in blocks_in_order_
  // Blocks taken from one part in a balanced pass; a cache line each, as every thread takes from
  // its own counter at once.
  struct alignas(64) Counter {
    std::atomic<std::size_t> taken{0};
  };
  mutable std::unique_ptr<Counter[]> next_;     // per balanced pass and part
  mutable std::size_t next_size_ = 0;
  bool valid_ = false;                          // built, and the particles not reordered since
  std::array<int, D> blocks_{};
  std::array<int, D> tiles_{};                  // the grid's tiles per axis
  ThreadShares shares_;                         // each thread's fraction of the particles
  Reach reach_{};
  std::vector<std::int32_t> block_of_;          // per particle
  std::vector<std::int64_t> start_;             // per block: first entry in order_, plus a sentinel
  std::vector<std::int32_t> order_;             // particle indices grouped by block, increasing within
  std::vector<std::int64_t> fill_;              // counting-sort cursors
  std::vector<std::vector<std::int32_t>> colour_blocks_;  // non-empty blocks of each colour
  std::vector<std::int32_t> active_tiles_;      // increasing
  std::vector<unsigned char> tile_mark_;        // per tile, while active_tiles_ is built
};

extern template class BlockSchedule<2>;
extern template class BlockSchedule<3>;

}  // namespace tsuchi
