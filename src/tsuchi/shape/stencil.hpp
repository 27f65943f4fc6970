#pragma once
// Multi-dimensional weights as tensor products of the 1D ones, eqs (18)-(19):
//   S = S_x S_y S_z,   G_x = S_x' S_y S_z, ...
//
// The stencil is kept factored: the K nodes along x, and the K^(D-1) rows of nodes along x, each
// row with the product T of its weights on the other axes and, per other axis d, dT_d (T with
// that axis' weight replaced by its derivative). Node (a, r) then has
//   S = wx[a] T[r],   G_x = dwx[a] T[r],   G_d = wx[a] dT_d[r],
// and a sum over the stencil can run along x first and apply the row factors once per row:
// fewer products than with the K^D weights spelt out, and nothing to store per node. scatter()
// and gather() below are that iteration, written once; a stage states only what it spreads to a
// node or sums from one.
//
// A kernel is a type with K (nodes per axis), reach_below and reach_above (nodes its stencil may
// reach beyond the two nodes of the particle's cell, on either side along an axis; the block
// colouring of the scatter derives from them, grid/block_schedule.hpp) and weights() (gimp.hpp).
//
// A stage that needs where the nodes are relative to the particle (APIC's affine transfer) calls
// compute_offsets() with the particle's position and gives its functions one more parameter: the row function
// then also gets the row's offsets along the other axes, ry[r] (x_i - x_p along y, z), and the
// node function the node's offset along x, rx[a]. Stages that do not ask pay nothing.
//
// Nodes of the stencil that fall outside the grid get weight 0 and a clamped (valid) index, so
// scatter and gather loops run without a branch; the dropped weight is the grid edge, where a
// boundary condition holds anyway.
#include "tsuchi/core/tensor.hpp"
#include "tsuchi/grid/grid.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <type_traits>

namespace tsuchi {

template <int D, class Kernel>
struct Stencil {
  static_assert(Kernel::reach_below >= 0 && Kernel::reach_above >= 0, "a kernel's reach counts nodes, >= 0");
  static_assert(Kernel::K <= 2 + Kernel::reach_below + Kernel::reach_above,
                "a kernel's K nodes per axis must lie within its cell's two nodes and its declared reach");
  static_assert(Kernel::reach_below <= Grid<D>::kEdge && Kernel::reach_above <= Grid<D>::kEdge,
                "the kernel reaches further beyond the grid's edge than the edge tables hold: raise Grid::kEdge "
                "(grid/grid.hpp)");
  static constexpr int K = Kernel::K;
  static constexpr int R = D == 2 ? K : K * K;  // rows along x
  static constexpr int N = K * R;               // nodes

  std::array<double, K> wx, dwx;
  std::array<std::int64_t, K> offx;  // index terms along x
  std::array<double, R> T;
  std::array<std::array<double, D - 1>, R> dT;
  std::array<std::int64_t, R> row;  // index term of each row
  // In 3D, the rows scatter() and gather() visit, in increasing r: those with a nonzero weight or
  // derivative. A row whose node on another axis lies beyond the GIMP support or off the grid's
  // edge has T = dT = 0, and every term it would add is a zero: with 2 particles per cell about
  // one row in three (a slab one cell thick: one in two), each three nodes' work.
  std::array<std::uint8_t, R> live;
  int live_rows = 0;
  // compute_offsets(): x_i - x_p along x for node a, and along the other axes for row r (m).
  std::array<double, K> rx;
  std::array<std::array<double, D - 1>, R> ry;
  Eigen::Array<int, D, 1> node0;  // first node index per axis (Axes::node0)

  // The particle's position in cell units, (x_p - origin) / h: the kernel's argument. One formula
  // for every caller, so a stage that needs it again (compute_offsets, the cell-centre remedy) gets
  // the bits the kernel got, from the same, not yet moved, position.
  [[gnu::always_inline]] static inline Eigen::Array<double, D, 1> in_cells(const Grid<D>& grid, const Vec<D>& x) {
    return (x - grid.origin).array() * grid.inv_h;
  }

  // What the stencil is made of, per axis: the weights and derivatives (zero off the grid's
  // edge) and the first node. A step keeps these per particle (104 bytes in 2D, 160 in 3D;
  // solver/explicit_step.cpp) and every stage assembles its stencil from them, which costs copies
  // and, in 3D, the 27 row products, not the kernel again. Not xi: the few stages that need it
  // compute it from the particle's position (16 or 24 bytes per particle for a few products).
  struct Axes {
    std::array<std::array<double, K>, D> w, dw;
    // First node index per axis, clamped to the range the grid's edge tables hold: the kernel's
    // own for every particle inside the grid; for one outside, about to be reported, it keeps the
    // table reads of the stages inside the tables.
    Eigen::Array<int, D, 1> node0;
  };

  [[gnu::always_inline]] static inline void axes(const Grid<D>& grid, const Vec<D>& x, const Vec<D>& lp, Axes& out) {
    using A = Eigen::Array<double, D, 1>;
    std::array<A, K> wa, dwa;
    const A xi_p = in_cells(grid, x);
    const Eigen::Array<int, D, 1> node0 = Kernel::template weights<D>(xi_p, grid.inv_h, lp.array(), wa, dwa);
    for (int d = 0; d < D; ++d) {
      const std::size_t first = first_entry(grid, d, node0[d]);
      out.node0[d] = static_cast<int>(first) - Grid<D>::kEdge;
      const double* inside = grid.axis_inside[d].data() + first;
      for (int k = 0; k < K; ++k) {
        out.w[d][k] = wa[k][d] * inside[k];
        out.dw[d][k] = dwa[k][d] * inside[k];
      }
    }
  }

  // The row form below from the per-axis factors; the nodes' index terms come from the grid's
  // tables (a few reads of lines every particle shares, cheaper than storing them per particle).
  [[gnu::always_inline]] inline void assemble(const Grid<D>& grid, const Axes& a) {
    node0 = a.node0;
    const auto& w = a.w;
    const auto& dw = a.dw;
    std::array<std::array<std::int64_t, K>, D> off;
    for (int d = 0; d < D; ++d) {
      const std::int64_t* term = grid.axis_term[d].data() + (node0[d] + Grid<D>::kEdge);
      for (int k = 0; k < K; ++k) off[d][k] = term[k];
    }
    wx = w[0], dwx = dw[0], offx = off[0];
    live_rows = 0;
    if constexpr (D == 2) {
      for (int b = 0; b < K; ++b) T[b] = w[1][b], dT[b][0] = dw[1][b], row[b] = off[1][b];
    } else {
      // A node of axis d > 0 counts when its weight or derivative is nonzero; per axis, once.
      std::array<std::array<bool, K>, D> counts;
      for (int d = 1; d < D; ++d)
        for (int k = 0; k < K; ++k) counts[d][k] = w[d][k] != 0.0 || dw[d][k] != 0.0;
      for (int c = 0; c < K; ++c)
        for (int b = 0; b < K; ++b) {
          const int r = b + K * c;
          T[r] = w[1][b] * w[2][c];
          dT[r][0] = dw[1][b] * w[2][c];
          dT[r][1] = w[1][b] * dw[2][c];
          row[r] = off[1][b] + off[2][c];
          if (counts[1][b] && counts[2][c]) live[live_rows++] = static_cast<std::uint8_t>(r);
        }
    }
  }

  [[gnu::always_inline]] inline void compute(const Grid<D>& grid, const Vec<D>& x, const Vec<D>& lp) {
    Axes a;
    axes(grid, x, lp, a);
    assemble(grid, a);
  }

  // The nodes' offsets from the particle at x (the position the stencil was computed at),
  // x_i - x_p = h (i - xi), for the functions that take them. Off the grid's edge the weight is 0,
  // so whatever offset such a node has does not count.
  [[gnu::always_inline]] inline void compute_offsets(const Grid<D>& grid, const Vec<D>& x) {
    const Eigen::Array<double, D, 1> xi = in_cells(grid, x);
    const double h = grid.h;
    std::array<std::array<double, K>, D> o;
    for (int d = 0; d < D; ++d)
      for (int k = 0; k < K; ++k) o[d][k] = h * (static_cast<double>(node0[d] + k) - xi[d]);
    rx = o[0];
    if constexpr (D == 2) {
      for (int b = 0; b < K; ++b) ry[b][0] = o[1][b];
    } else {
      for (int c = 0; c < K; ++c)
        for (int b = 0; b < K; ++b) ry[b + K * c] = {o[1][b], o[2][c]};
    }
  }

  // The rows visited: in 3D the live ones; in 2D all K, a loop of fixed length the compiler
  // unrolls (a row skipped there saves less than the unrolled loop: callgrind, BENCHMARKS.md).
  [[gnu::always_inline]] inline int rows_visited() const { return D == 2 ? R : live_rows; }
  [[gnu::always_inline]] inline int row_visited(int j) const { return D == 2 ? j : live[j]; }

  // Scatter: for each live row r in turn, along = row_fn(T[r], dT[r]) is what the row spreads (formed
  // once per row), then node_fn(k, wx[a], dwx[a], along) for the row's nodes a = 0 .. K-1, k the
  // node's index. Node (a, r) thus gets S = wx[a] T[r], G_x = dwx[a] T[r], G_d = wx[a] dT[r][d-1]
  // from products the row function formed with T and dT.
  template <class RowFn, class NodeFn>
  [[gnu::always_inline]] inline void scatter(RowFn&& row_fn, NodeFn&& node_fn) const {
    for (int j = 0; j < rows_visited(); ++j) {
      const int r = row_visited(j);
      const auto along = [&] {
        if constexpr (std::is_invocable_v<RowFn&, double, const std::array<double, D - 1>&,
                                          const std::array<double, D - 1>&>)
          return row_fn(T[r], dT[r], ry[r]);
        else
          return row_fn(T[r], dT[r]);
      }();
      for (int a = 0; a < K; ++a) {
        if constexpr (std::is_invocable_v<NodeFn&, std::int64_t, double, double, decltype(along), double>)
          node_fn(offx[a] + row[r], wx[a], dwx[a], along, rx[a]);
        else
          node_fn(offx[a] + row[r], wx[a], dwx[a], along);
      }
    }
  }

  // Gather: for each live row r in turn, sums = zero, node_fn(sums, k, wx[a], dwx[a]) for the row's
  // nodes a = 0 .. K-1 (sums along x), then row_fn(sums, T[r], dT[r]) applies the row's factors.
  template <class Sums, class NodeFn, class RowFn>
  [[gnu::always_inline]] inline void gather(const Sums& zero, NodeFn&& node_fn, RowFn&& row_fn) const {
    for (int j = 0; j < rows_visited(); ++j) {
      const int r = row_visited(j);
      Sums sums = zero;
      for (int a = 0; a < K; ++a) {
        if constexpr (std::is_invocable_v<NodeFn&, Sums&, std::int64_t, double, double, double>)
          node_fn(sums, offx[a] + row[r], wx[a], dwx[a], rx[a]);
        else
          node_fn(sums, offx[a] + row[r], wx[a], dwx[a]);
      }
      if constexpr (std::is_invocable_v<RowFn&, const Sums&, double, const std::array<double, D - 1>&,
                                        const std::array<double, D - 1>&>)
        row_fn(static_cast<const Sums&>(sums), T[r], dT[r], ry[r]);
      else
        row_fn(static_cast<const Sums&>(sums), T[r], dT[r]);
    }
  }

  // Node n = a + K r spelt out, for checks and for code off the hot path.
  std::int64_t node(int n) const { return offx[n % K] + row[n / K]; }
  double S(int n) const { return wx[n % K] * T[n / K]; }
  Vec<D> G(int n) const {
    const int a = n % K, r = n / K;
    Vec<D> g;
    g[0] = dwx[a] * T[r];
    for (int d = 1; d < D; ++d) g[d] = wx[a] * dT[r][d - 1];
    return g;
  }

 private:
  // The entry of node i0 in the grid's per-axis tables. Only a particle outside the grid, about
  // to be reported, needs the clamp: it keeps the table reads inside the tables.
  static std::size_t first_entry(const Grid<D>& grid, int d, int i0) {
    constexpr int E = Grid<D>::kEdge;
    return static_cast<std::size_t>(std::clamp(i0, -E, grid.n_nodes[d] + E - K) + E);
  }
};

}  // namespace tsuchi
