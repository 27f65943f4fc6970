#pragma once
// Multi-dimensional weights as tensor products of the 1D ones, eqs (18)-(19):
//   S = S_x S_y S_z,   G_x = S_x' S_y S_z, ...
// Nodes of the stencil that fall outside the grid get weight 0 and a clamped (valid) index, so
// scatter and gather loops run without a branch; the dropped weight is the grid edge, where a
// boundary condition holds anyway.
#include "tsuchi/core/tensor.hpp"
#include "tsuchi/grid/grid.hpp"

#include <algorithm>
#include <cstdint>

namespace tsuchi {

template <int D, class Kernel>
struct Stencil {
  static constexpr int K = Kernel::K;
  static constexpr int N = D == 2 ? K * K : K * K * K;
  std::array<std::int64_t, N> node;
  std::array<double, N> S;
  std::array<Vec<D>, N> G;

  [[gnu::always_inline]] inline void compute(const Grid<D>& grid, const Vec<D>& x, const Vec<D>& lp) {
    std::array<std::array<double, K>, D> w, dw;
    std::array<std::array<std::int64_t, K>, D> off;  // per-axis terms of the node index
    const double inv_h = grid.inv_h;
    for (int d = 0; d < D; ++d) {
      const double s = (x[d] - grid.origin[d]) * inv_h;
      const int i0 = Kernel::weights(s, inv_h, lp[d], w[d].data(), dw[d].data());
      // Only a particle outside the grid, about to be reported, needs the clamp: it keeps the
      // table reads inside the tables.
      const auto first = static_cast<std::size_t>(std::clamp(i0, -1, grid.n_nodes[d] + 1 - K) + 1);
      const std::int64_t* term = grid.axis_term[d].data() + first;
      const double* inside = grid.axis_inside[d].data() + first;
      for (int k = 0; k < K; ++k) {
        off[d][k] = term[k];
        w[d][k] *= inside[k];
        dw[d][k] *= inside[k];
      }
    }
    int n = 0;
    if constexpr (D == 2) {
      for (int b = 0; b < K; ++b)
        for (int a = 0; a < K; ++a, ++n) {
          node[n] = off[0][a] + off[1][b];
          S[n] = w[0][a] * w[1][b];
          G[n] = Vec<D>(dw[0][a] * w[1][b], w[0][a] * dw[1][b]);
        }
    } else {
      for (int c = 0; c < K; ++c)
        for (int b = 0; b < K; ++b)
          for (int a = 0; a < K; ++a, ++n) {
            node[n] = off[0][a] + off[1][b] + off[2][c];
            S[n] = w[0][a] * w[1][b] * w[2][c];
            G[n] = Vec<D>(dw[0][a] * w[1][b] * w[2][c], w[0][a] * dw[1][b] * w[2][c],
                          w[0][a] * w[1][b] * dw[2][c]);
          }
    }
  }
};

}  // namespace tsuchi
