#include "tsuchi/grid/block_schedule.hpp"

#include <algorithm>
#include <array>

namespace tsuchi {

template <int D>
void BlockSchedule<D>::build(const Grid<D>& grid, const std::vector<Vec<D>>& x, Reach reach) {
  std::int64_t n_blocks = 1;
  std::array<int, D> blocks{};
  for (int d = 0; d < D; ++d) {
    const int cells = grid.n_nodes[d] - 1;
    blocks[d] = (cells + B - 1) / B;
    n_blocks *= blocks[d];
  }
  const auto n = static_cast<std::int64_t>(x.size());
  // The last schedule still holds if every particle stayed in its block, as nearly all do in a
  // step: the sort below would rebuild it entry for entry. Only the pass over positions runs then.
  bool same = valid_ && blocks == blocks_ && reach == reach_ && block_of_.size() == x.size();
  blocks_ = blocks;
  reach_ = reach;
  block_of_.resize(x.size());
  // (x - origin) / h as the stencils compute it, so a particle on a cell edge is filed in the cell
  // whose nodes its stencil uses.
  const double inv_h = grid.inv_h;
  std::int64_t moved = 0;
#pragma omp parallel for schedule(static) reduction(+ : moved)
  for (std::int64_t i = 0; i < n; ++i) {
    std::int64_t b = 0;
    for (int d = D - 1; d >= 0; --d) {
      // A particle outside the grid (about to be reported) is filed under the nearest block.
      // The comparisons also send a NaN to block 0 rather than into an undefined conversion.
      const double s = (x[i][d] - grid.origin[d]) * inv_h, last = grid.n_nodes[d] - 2.0;
      const double cell = s > 0.0 ? (s < last ? s : last) : 0.0;
      b = b * blocks[d] + static_cast<int>(cell) / B;
    }
    if (block_of_[i] != static_cast<std::int32_t>(b)) block_of_[i] = static_cast<std::int32_t>(b), ++moved;
  }
  if (same && moved == 0) return;
  valid_ = true;
  start_.assign(static_cast<std::size_t>(n_blocks) + 1, 0);
  for (std::int64_t i = 0; i < n; ++i) ++start_[block_of_[i] + 1];
  for (std::int64_t b = 0; b < n_blocks; ++b) start_[b + 1] += start_[b];
  order_.resize(x.size());
  fill_.assign(start_.begin(), start_.end() - 1);  // reuses its storage: no allocation per step
  for (std::int64_t i = 0; i < n; ++i) order_[fill_[block_of_[i]]++] = static_cast<std::int32_t>(i);
  // Each non-empty block joins the list of its colour, sum_d (c_d mod P) P^d for block
  // coordinates c, and marks active the (2 w + 1)^D tiles around it, w = tile_reach().
  const int P = colours_per_axis(reach), w = tile_reach(reach), span = 2 * w + 1;
  int n_colours = 1, around = 1;
  for (int d = 0; d < D; ++d) n_colours *= P, around *= span;
  std::array<int, D> tiles{};
  std::int64_t n_tiles = 1;
  for (int d = 0; d < D; ++d) tiles[d] = grid.tiles(d), n_tiles *= tiles[d];
  tile_mark_.assign(static_cast<std::size_t>(n_tiles), 0);
  colour_blocks_.resize(static_cast<std::size_t>(n_colours));
  for (auto& c : colour_blocks_) c.clear();
  for (std::int64_t b = 0; b < n_blocks; ++b) {
    if (start_[b + 1] == start_[b]) continue;
    std::array<int, D> c{};
    int colour = 0;
    std::int64_t rest = b;
    for (int d = 0, weight = 1; d < D; ++d, weight *= P) {
      c[d] = static_cast<int>(rest % blocks_[d]), rest /= blocks_[d];
      colour += c[d] % P * weight;
    }
    colour_blocks_[static_cast<std::size_t>(colour)].push_back(static_cast<std::int32_t>(b));
    for (int j = 0; j < around; ++j) {
      std::int64_t t = 0, stride = 1;
      bool inside = true;
      for (int d = 0, m = j; d < D; ++d, m /= span) {
        const int q = c[d] + m % span - w;
        inside = inside && q >= 0 && q < tiles[d];
        t += q * stride, stride *= tiles[d];
      }
      if (inside) tile_mark_[static_cast<std::size_t>(t)] = 1;
    }
  }
  active_tiles_.clear();
  for (std::int64_t t = 0; t < n_tiles; ++t)
    if (tile_mark_[static_cast<std::size_t>(t)]) active_tiles_.push_back(static_cast<std::int32_t>(t));
  // Fullest blocks first, so that the threads end a colour on small blocks and wait less for each
  // other. Blocks of one colour write disjoint nodes: their order does not change any result.
  for (auto& c : colour_blocks_)
    std::sort(c.begin(), c.end(), [&](std::int32_t a, std::int32_t b) {
      const auto na = start_[a + 1] - start_[a], nb = start_[b + 1] - start_[b];
      return na != nb ? na > nb : a < b;
    });
}

template class BlockSchedule<2>;
template class BlockSchedule<3>;

}  // namespace tsuchi
