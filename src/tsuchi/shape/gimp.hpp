#pragma once
// GIMP shape function (Bardenhagen & Kober 2004): the linear hat integrated against the particle's
// characteristic function of half-width l_p, eq (16)-(17), as corrected in METHOD.md section 2.
// The table there is valid for l_p <= L/2, which the domain update keeps (see particle_domain.hpp).
#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>

namespace tsuchi::shape {

// S(xi) for xi = x_p - x_v, cell size L, particle half-width l_p (0 < l_p <= L/2).
inline double gimp_S(double xi, double L, double lp) {
  const double a = std::abs(xi);  // S is even in xi
  if (a >= L + lp) return 0.0;
  if (a > L - lp) return (L + lp - a) * (L + lp - a) / (4.0 * L * lp);
  if (a > lp) return 1.0 - a / L;
  return 1.0 - (xi * xi + lp * lp) / (2.0 * L * lp);
}

// dS/dxi; odd in xi.
inline double gimp_dS(double xi, double L, double lp) {
  const double a = std::abs(xi);
  const double sgn = xi < 0.0 ? -1.0 : 1.0;
  if (a >= L + lp) return 0.0;
  if (a > L - lp) return -sgn * (L + lp - a) / (2.0 * L * lp);
  if (a > lp) return -sgn / L;
  return -xi / (L * lp);
}

// Three nodes per axis: with l_p <= L/2 the support |xi| < L + l_p covers at most three nodes,
// the nearest node and one on each side of it.
//
// The step evaluates these weights three times per particle, so they are computed without a
// branch. With r = (x_p - x_mid) / L in [-1/2, 1/2) for the middle node and q = l_p / L, the outer
// nodes' weights are g(q - r) (left) and g(q + r) (right), where
//   g(t) = integral from 0 to t of clamp(tau / 2q, 0, 1) dtau
//        = 0 (t <= 0),  t^2 / 4q (0 < t < 2q),  t - q (t >= 2q),
// which is gimp_S above in the variable t = 1 + q - |xi| / L; the middle weight follows from the
// partition of unity, 1 - left - right.
struct GimpKernel {
  static constexpr int K = 3;
  // Nodes reached beyond the two of the particle's cell [i, i+1]: i-1 when the particle sits in
  // the cell's lower half, i+2 in its upper half (stencil.hpp; the block colouring derives from it).
  static constexpr int reach_below = 1, reach_above = 1;
  static constexpr const char* name = "gimp";

  // Every axis at once, one lane per axis (2D: one SSE register). s = (x_p - origin) / L in cell
  // units (s >= 0 inside the grid), inv_L = 1 / L (a product is cheaper than a division in the
  // hottest function of the step); fills w[k], dw[k] per axis and returns the first node indices.
  template <int D>
  [[gnu::always_inline]] static inline Eigen::Array<int, D, 1> weights(const Eigen::Array<double, D, 1>& s, double inv_L,
                                                const Eigen::Array<double, D, 1>& lp,
                                                std::array<Eigen::Array<double, D, 1>, K>& w,
                                                std::array<Eigen::Array<double, D, 1>, K>& dw) {
    using A = Eigen::Array<double, D, 1>;
    // floor(s - 1/2) by truncation, exact for s >= -1/2: std::floor is a branchy sequence or a
    // library call on baseline x86-64. Further outside, the particle has left the grid and the
    // step is reported, whatever these weights are.
    const Eigen::Array<int, D, 1> c = (s + 0.5).template cast<int>() - 1;  // node left of the nearest
    const A r = s - (c + 1).template cast<double>();
    const A q = (lp * inv_L).max(1e-12);  // a zero width is the linear hat, reached continuously
    const A tl = q - r, tr = q + r, q2 = 2.0 * q;
    const A cl = tl.max(0.0).min(q2), cr = tr.max(0.0).min(q2);
    const A inv4q = 0.25 / q;
    w[0] = cl * cl * inv4q + (tl - q2).max(0.0);
    w[2] = cr * cr * inv4q + (tr - q2).max(0.0);
    w[1] = 1.0 - w[0] - w[2];
    // dt/dx_p is -1/L on the left, +1/L on the right; g'(t) = clamp(t / 2q, 0, 1).
    dw[0] = (-2.0 * inv_L) * cl * inv4q;
    dw[2] = (2.0 * inv_L) * cr * inv4q;
    dw[1] = -dw[0] - dw[2];
    return c;
  }
};

}  // namespace tsuchi::shape
