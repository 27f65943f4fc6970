#pragma once
// The fixed Cartesian background grid: geometry, the boundary conditions, and one or more nodal
// fields, each a set of flat arrays (one per quantity).
#include "tsuchi/core/tensor.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace tsuchi {

// The quantities the step scatters to and solves on the nodes: one velocity field. Today's step
// uses one (Grid::fields[0]); contact between bodies will hold one per body and a centre-of-mass
// one, each filled and solved by the same stages.
template <int D>
struct NodalField {
  std::vector<double> m;   // mass
  std::vector<Vec<D>> p;   // momentum
  std::vector<Vec<D>> f;   // internal + external force
  std::vector<Vec<D>> v;   // velocity p / m (before the step, or remapped)
  // Acceleration: kept only for FLIP's g2p (and its blends with PIC), its one reader
  // (Grid::keep_acceleration); empty otherwise. APIC's g2p reads v^L alone, and the solve then
  // forms a node's acceleration and uses it in the same pass.
  std::vector<Vec<D>> a;
  std::vector<Vec<D>> vL;  // updated velocity v^L = v + dt a

  void allocate(std::size_t slots, bool with_acceleration) {
    m.assign(slots, 0.0);
    p.assign(slots, Vec<D>::Zero());
    f.assign(slots, Vec<D>::Zero());
    if (with_acceleration) a.assign(slots, Vec<D>::Zero());
    else a.clear(), a.shrink_to_fit();
    v.assign(slots, Vec<D>::Zero());
    vL.assign(slots, Vec<D>::Zero());
  }

  static constexpr std::size_t bytes_per_slot(bool with_acceleration) {
    return sizeof(double) + (with_acceleration ? 5 : 4) * sizeof(Vec<D>);
  }
};

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

  // The nodal fields: allocate() makes field 0, the only one the step uses today; add_field()
  // makes another, of the same size and zeroed, and returns its number. Only the fields asked for
  // take memory. The boundary conditions (fixed_g) hold for every field.
  std::vector<NodalField<D>> fields;
  // Bit d set: velocity component d held, at zero (a fixed or roller face, `fix`) or at a driven
  // base motion (model/node_sets.hpp), which the solver sets after its passes over the nodes.
  std::vector<std::uint8_t> fixed_g;

  // Per axis, for i = -kEdge .. n_nodes - 1 + kEdge (entry i + kEdge): axis_offset(d, i) clamped
  // into the grid, and 1 for a node of the grid, 0 for the kEdge nodes beyond each edge, which a
  // stencil may reach and drops. Two loads per stencil node instead of a clamp, a division and a
  // select. Built by index_axes(). A kernel reaching further than kEdge nodes beyond the cell of
  // a particle does not compile (shape/stencil.hpp).
  static constexpr int kEdge = 1;
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
      axis_term[d].resize(static_cast<std::size_t>(n) + 2 * kEdge);
      axis_inside[d].resize(static_cast<std::size_t>(n) + 2 * kEdge);
      for (int i = -kEdge; i < n + kEdge; ++i) {
        axis_term[d][i + kEdge] = axis_offset(d, std::clamp(i, 0, n - 1));
        axis_inside[d][i + kEdge] = i >= 0 && i < n ? 1.0 : 0.0;
      }
    }
  }

  // Whether the nodal fields keep the acceleration (NodalField::a): only FLIP's g2p reads it. Set
  // before allocate() (model/model.cpp, from solver.velocity_transfer; a stage cannot change it).
  bool keep_acceleration = true;

  // index_axes(), the boundary conditions (none held) and one nodal field.
  void allocate() {
    index_axes();
    const std::size_t n = size();
    fields.assign(1, NodalField<D>{});
    fields[0].allocate(n, keep_acceleration);
    fixed_g.assign(n, 0);
  }

  // A further nodal field, after allocate(); returns its number.
  int add_field() {
    fields.emplace_back().allocate(size(), keep_acceleration);
    return static_cast<int>(fields.size()) - 1;
  }

  NodalField<D>& field(int k = 0) { return fields[static_cast<std::size_t>(k)]; }
  const NodalField<D>& field(int k = 0) const { return fields[static_cast<std::size_t>(k)]; }

  // Bytes per storage slot with one nodal field (what allocate() takes); each add_field() adds
  // NodalField<D>::bytes_per_slot(keep_acceleration).
  static constexpr std::size_t bytes_per_slot(bool with_acceleration) {
    return NodalField<D>::bytes_per_slot(with_acceleration) + sizeof(std::uint8_t);
  }
  std::size_t bytes() const {
    return size() * (fields.size() * NodalField<D>::bytes_per_slot(keep_acceleration) + sizeof(std::uint8_t));
  }
};

}  // namespace tsuchi
