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

#include <algorithm>
#include <array>
#include <cstdint>
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
  template <class F>
  void scatter(F&& f) const {
    for (const auto& blocks : colour_blocks_) {
      const auto nb = static_cast<std::int64_t>(blocks.size());
      // Runs of blocks per grab: neighbouring blocks of one colour both write the tiles between
      // them, and threads taking alternate blocks would write the same cache lines at once. Runs
      // of 2 when a colour has few blocks, so that the threads still end close together.
      const std::int64_t run = nb >= 64 ? 4 : 2;
#pragma omp parallel for schedule(dynamic, run)
      for (std::int64_t k = 0; k < nb; ++k) {
        const std::int32_t b = blocks[static_cast<std::size_t>(k)];
        for (std::int64_t j = start_[b]; j < start_[b + 1]; ++j) f(static_cast<std::size_t>(order_[j]));
      }
    }
  }

  // The non-empty blocks of each colour, in the order scatter() takes them (for checks).
  const std::vector<std::vector<std::int32_t>>& colour_blocks() const { return colour_blocks_; }

  // Particle indices in block order: the order a locality-improving reordering would follow.
  const std::vector<std::int32_t>& order() const { return order_; }

  // Calls f(k) for every node slot of the active tiles, in parallel: the tiles of the non-empty
  // blocks and the tiles within tile_reach() of them, which hold every node a particle's stencil
  // reaches (a block is a tile). Nodes elsewhere carry nothing, so the grid loops skip them; a
  // tile is cleared by p2g when it becomes active.
  template <class F>
  void for_active_nodes(F&& f) const {
    constexpr std::int64_t nodes = Grid<D>::kTileNodes;
    const auto nt = static_cast<std::int64_t>(active_tiles_.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t t = 0; t < nt; ++t) {
      const std::int64_t first = active_tiles_[static_cast<std::size_t>(t)] * nodes;
      for (std::int64_t k = first; k < first + nodes; ++k) f(k);
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

 private:
  bool valid_ = false;                          // built, and the particles not reordered since
  std::array<int, D> blocks_{};
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
