#pragma once
// Lock-free, deterministic particle-to-grid scatter on several threads.
//
// The grid is cut into blocks of B x B (x B) cells and each particle belongs to the block of the
// cell it sits in. A particle writes to nodes at most one node outside its cell's block (three
// GIMP nodes per axis with l_p <= L/2), so two blocks of the same colour - colours alternate along
// every axis, 4 in 2D and 8 in 3D - never write the same node when B >= 3. The scatter runs colour
// by colour; inside a colour, blocks go to threads in any order, and inside a block particles go in
// increasing index. Every node therefore sums its contributions in one fixed order, whatever the
// number of threads: results are bitwise the same on 1 or N threads, with no lock or atomic.
//
// Brought up to date every step from the start-of-step positions: a pass that files each particle
// under its block, then, only if some particle changed block, a counting sort of the particle
// indices (8 bytes per particle in all).
#include "tsuchi/grid/grid.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace tsuchi {

template <int D>
class BlockSchedule {
 public:
  static constexpr int B = Grid<D>::T;         // cells per block per axis: a block is a tile
  static constexpr int kColours = 1 << D;

  void build(const Grid<D>& grid, const std::vector<Vec<D>>& x);

  // The particles were reordered: the next build starts afresh.
  void invalidate() { valid_ = false; }

  // Calls f(i) for every particle, colour by colour, blocks of one colour in parallel.
  template <class F>
  void scatter(F&& f) const {
    for (int c = 0; c < kColours; ++c) {
      const auto& blocks = colour_blocks_[c];
      const auto nb = static_cast<std::int64_t>(blocks.size());
      // Runs of blocks per grab: two same-colour blocks two apart both write the tile between
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

  // Particle indices in block order: the order a locality-improving reordering would follow.
  const std::vector<std::int32_t>& order() const { return order_; }

  // Calls f(k) for every node slot of the active tiles, in parallel: the tiles of the non-empty
  // blocks and their neighbours, which hold every node a particle's stencil reaches (a block is a
  // tile, and a stencil reaches at most one node beyond its block, see above). Nodes elsewhere
  // carry nothing, so the grid loops skip them; a tile is cleared by p2g when it becomes active.
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

 private:
  bool valid_ = false;                          // built, and the particles not reordered since
  std::array<int, D> blocks_{};
  std::vector<std::int32_t> block_of_;          // per particle
  std::vector<std::int64_t> start_;             // per block: first entry in order_, plus a sentinel
  std::vector<std::int32_t> order_;             // particle indices grouped by block, increasing within
  std::vector<std::int64_t> fill_;              // counting-sort cursors
  std::array<std::vector<std::int32_t>, kColours> colour_blocks_;  // non-empty blocks of each colour
  std::vector<std::int32_t> active_tiles_;      // increasing
  std::vector<unsigned char> tile_mark_;        // per tile, while active_tiles_ is built
};

extern template class BlockSchedule<2>;
extern template class BlockSchedule<3>;

}  // namespace tsuchi
