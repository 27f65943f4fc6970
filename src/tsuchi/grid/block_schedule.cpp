#include "tsuchi/grid/block_schedule.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

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
  const int threads = omp_get_max_threads();
  bool same = valid_ && blocks == blocks_ && reach == reach_ && block_of_.size() == x.size() && threads == threads_;
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
  // The speeds the last step measured; a changed thread count starts the shares afresh.
  if (shares_.threads() != threads) shares_.reset(threads);
  const bool recut = shares_.update();
  if (same && moved == 0) {
    if (recut) partition(threads, tiles_);
    return;
  }
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
  std::array<int, D>& tiles = tiles_;
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
  // Each colour's blocks stay in increasing index (the order they were listed in), so that a
  // thread's part of the grid is one run of each list.
  partition(threads, tiles);
}

template <int D>
void BlockSchedule<D>::partition(int threads, const std::array<int, D>& tiles) {
  threads_ = threads;
  const auto T = static_cast<std::size_t>(threads);
  const auto n_blocks = static_cast<std::int64_t>(start_.size()) - 1;
  const std::int64_t n = start_.back();
  // Thread t's blocks start at the first block with (s_0 + ... + s_t-1) n particles before it,
  // s the threads' shares (thread_shares.hpp; t n / T while they are even).
  std::vector<std::int64_t> bound(T + 1, n_blocks);
  bound[0] = 0;
  double before = 0.0;
  for (std::size_t t = 1; t < T; ++t) {
    before += shares_.shares()[t - 1];
    const auto target = static_cast<std::int64_t>(std::llround(before * static_cast<double>(n)));
    bound[t] = std::lower_bound(start_.begin(), start_.end() - 1, target) - start_.begin();
  }
  blocks_in_order_.clear();
  for (std::int64_t b = 0; b < n_blocks; ++b)
    if (start_[b + 1] > start_[b]) blocks_in_order_.push_back(static_cast<std::int32_t>(b));
  block_cut_.resize(T + 1);
  for (std::size_t t = 0; t <= T; ++t)
    block_cut_[t] = static_cast<std::size_t>(
        std::lower_bound(blocks_in_order_.begin(), blocks_in_order_.end(), bound[t]) - blocks_in_order_.begin());
  colour_cut_.assign(colour_blocks_.size() * (T + 1), 0);
  for (std::size_t c = 0; c < colour_blocks_.size(); ++c) {
    const auto& list = colour_blocks_[c];
    for (std::size_t t = 0; t <= T; ++t)
      colour_cut_[c * (T + 1) + t] =
          static_cast<std::size_t>(std::lower_bound(list.begin(), list.end(), bound[t]) - list.begin());
  }
  // The tile of block b has the same coordinates; tiles run in the same axis order, so block
  // order is tile order.
  tile_cut_.assign(T + 1, active_tiles_.size());
  for (std::size_t t = 0; t < T; ++t) {
    std::int64_t tile = std::numeric_limits<std::int64_t>::max();
    if (bound[t] < n_blocks) {
      tile = 0;
      std::int64_t rest = bound[t], stride = 1;
      for (int d = 0; d < D; ++d) {
        tile += rest % blocks_[d] * stride;
        rest /= blocks_[d], stride *= tiles[d];
      }
    }
    tile_cut_[t] = static_cast<std::size_t>(
        std::lower_bound(active_tiles_.begin(), active_tiles_.end(), tile,
                         [](std::int32_t a, std::int64_t b) { return a < b; }) - active_tiles_.begin());
  }
  tile_cut_[0] = 0;
}

template <int D>
void BlockSchedule<D>::begin_balanced(std::size_t passes) const {
  const std::size_t n = passes * static_cast<std::size_t>(std::max(threads_, 1));
  if (n > next_size_) next_ = std::make_unique<Counter[]>(n), next_size_ = n;
  for (std::size_t k = 0; k < n; ++k) next_[k].taken.store(0, std::memory_order_relaxed);
}

template <int D>
typename BlockSchedule<D>::Part BlockSchedule<D>::my_part() const {
  Part part;
  part.thread = static_cast<std::size_t>(omp_get_thread_num());
  part.threads = static_cast<std::size_t>(omp_get_num_threads());
  part.cut = static_cast<int>(part.threads) == threads_;
  if (part.cut) {
    part.first_tile = tile_cut_[part.thread], part.last_tile = tile_cut_[part.thread + 1];
  } else {
    part.first_tile = active_tiles_.size() * part.thread / part.threads;
    part.last_tile = active_tiles_.size() * (part.thread + 1) / part.threads;
  }
  return part;
}

template class BlockSchedule<2>;
template class BlockSchedule<3>;

}  // namespace tsuchi
