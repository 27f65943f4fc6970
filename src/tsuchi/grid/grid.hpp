#pragma once
// The fixed Cartesian background grid: geometry and nodal fields as flat arrays (one per field).
#include "tsuchi/core/tensor.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace tsuchi {

template <int D>
struct Grid {
  Vec<D> origin = Vec<D>::Zero();
  double h = 1.0;                       // cell size, the same on every axis
  double inv_h = 1.0;                   // 1 / h, set by index_axes()
  std::array<int, D> n_nodes{};         // nodes per axis = cells + 1

  // Nodes are stored in tiles of T^D nodes (4 x 4 in 2D, 4 x 4 x 4 in 3D), tile after tile, and
  // lexicographically inside a tile. A tile is the node set of one block of the particle schedule
  // (grid/block_schedule.hpp), so a block's particles scatter mostly into one contiguous piece of
  // memory, and a later split of the grid over processes can hand over whole tiles. The grid is
  // padded to whole tiles; padding nodes never receive mass and are skipped by the solver.
  static constexpr int T = 4;
  static constexpr int kTileNodes = D == 2 ? T * T : T * T * T;

  std::vector<double> m_g;              // mass
  std::vector<Vec<D>> p_g;              // momentum
  std::vector<Vec<D>> f_g;              // internal + external force
  std::vector<Vec<D>> v_g;              // velocity p_g / m_g (before the step, or remapped)
  std::vector<Vec<D>> a_g;              // acceleration
  std::vector<Vec<D>> vL_g;             // updated velocity v^L = v_g + dt a_g
  std::vector<std::uint8_t> fixed_g;    // bit d set: velocity component d held at zero

  // Per axis, for i = -1 .. n_nodes (entry i + 1): axis_offset(d, i) clamped into the grid, and 1
  // for a node of the grid, 0 for the two beyond its edges, which a stencil may reach and drops.
  // Two loads per stencil node instead of a clamp, a division and a select. Built by index_axes().
  std::array<std::vector<std::int64_t>, D> axis_term;
  std::array<std::vector<double>, D> axis_inside;

  int tiles(int d) const { return (n_nodes[d] + T - 1) / T; }

  std::size_t node_count() const {
    std::size_t n = 1;
    for (int d = 0; d < D; ++d) n *= static_cast<std::size_t>(n_nodes[d]);
    return n;
  }

  // Storage slots, padding included.
  std::size_t size() const {
    std::size_t n = kTileNodes;
    for (int d = 0; d < D; ++d) n *= static_cast<std::size_t>(tiles(d));
    return n;
  }

  // The index is a sum of one term per axis, so a stencil computes K terms per axis, not K^D.
  // i >= 0; T is a power of two, so the tile and the place in it are a shift and a mask.
  std::int64_t axis_offset(int d, int i) const {
    std::int64_t tile_stride = kTileNodes, local_stride = 1;
    for (int e = 0; e < d; ++e) tile_stride *= tiles(e), local_stride *= T;
    const auto u = static_cast<unsigned>(i);
    return static_cast<std::int64_t>(u / T) * tile_stride + static_cast<std::int64_t>(u % T) * local_stride;
  }

  std::int64_t index(const std::array<int, D>& ijk) const {
    std::int64_t idx = 0;
    for (int d = 0; d < D; ++d) idx += axis_offset(d, ijk[d]);
    return idx;
  }

  std::array<int, D> ijk(std::int64_t idx) const {
    std::array<int, D> r{};
    std::int64_t local = idx % kTileNodes, tile = idx / kTileNodes;
    for (int d = 0; d < D; ++d) {
      r[d] = static_cast<int>((tile % tiles(d)) * T + local % T);
      tile /= tiles(d), local /= T;
    }
    return r;
  }

  // False for the padding slots of the last tiles.
  bool is_node(std::int64_t idx) const {
    const auto r = ijk(idx);
    for (int d = 0; d < D; ++d)
      if (r[d] >= n_nodes[d]) return false;
    return true;
  }

  Vec<D> position(const std::array<int, D>& ijk_) const {
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = origin[d] + h * ijk_[d];
    return x;
  }

  Vec<D> upper() const {
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = origin[d] + h * (n_nodes[d] - 1);
    return x;
  }

  void index_axes() {
    inv_h = 1.0 / h;
    for (int d = 0; d < D; ++d) {
      const int n = n_nodes[d];
      axis_term[d].resize(static_cast<std::size_t>(n) + 2);
      axis_inside[d].resize(static_cast<std::size_t>(n) + 2);
      for (int i = -1; i <= n; ++i) {
        axis_term[d][i + 1] = axis_offset(d, std::clamp(i, 0, n - 1));
        axis_inside[d][i + 1] = i >= 0 && i < n ? 1.0 : 0.0;
      }
    }
  }

  // The nodal fields, and index_axes().
  void allocate() {
    index_axes();
    const std::size_t n = size();
    m_g.assign(n, 0.0);
    p_g.assign(n, Vec<D>::Zero());
    f_g.assign(n, Vec<D>::Zero());
    a_g.assign(n, Vec<D>::Zero());
    v_g.assign(n, Vec<D>::Zero());
    vL_g.assign(n, Vec<D>::Zero());
    fixed_g.assign(n, 0);
  }

  static constexpr std::size_t bytes_per_slot() { return sizeof(double) + 5 * sizeof(Vec<D>) + sizeof(std::uint8_t); }
  std::size_t bytes() const { return size() * bytes_per_slot(); }
};

}  // namespace tsuchi
