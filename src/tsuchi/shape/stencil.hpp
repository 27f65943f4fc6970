#pragma once
// Multi-dimensional weights as tensor products of the 1D ones, eqs (18)-(19):
//   S = S_x S_y S_z,   G_x = S_x' S_y S_z, ...
// Nodes of the stencil that fall outside the grid get weight 0 and a clamped (valid) index, so
// scatter and gather loops run without a branch; the dropped weight is the grid edge, where a
// boundary condition holds anyway.
#include "tsuchi/core/tensor.hpp"
#include "tsuchi/grid/grid.hpp"

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
    const double inv_h = 1.0 / grid.h;
    for (int d = 0; d < D; ++d) {
      const double s = (x[d] - grid.origin[d]) * inv_h;
      const int i0 = Kernel::weights(s, inv_h, lp[d], w[d].data(), dw[d].data());
      const int last = grid.n_nodes[d] - 1;
      for (int k = 0; k < K; ++k) {
        const int i = i0 + k;
        const bool inside = i >= 0 && i <= last;
        off[d][k] = grid.axis_offset(d, inside ? i : (i < 0 ? 0 : last));
        if (!inside) w[d][k] = dw[d][k] = 0.0;
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
