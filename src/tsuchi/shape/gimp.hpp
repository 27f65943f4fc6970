#pragma once
// GIMP shape function (Bardenhagen & Kober 2004): the linear hat integrated against the particle's
// characteristic function of half-width l_p, eq (16)-(17), as corrected in METHOD.md section 2.
// The table there is valid for l_p <= L/2, which the domain update keeps (see particle_domain.hpp).
#include <algorithm>
#include <cmath>
#include <cstdint>

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
  static constexpr const char* name = "gimp";

  // s = (x_p - origin) / L in cell units (s >= 0 inside the grid), inv_L = 1 / L (a product is
  // cheaper than a division in the hottest function of the step); fills the first node index and
  // K weights/derivatives.
  static inline int weights(double s, double inv_L, double lp, double* w, double* dw) {
    // floor(s - 1/2) by truncation, exact for s >= -1/2: std::floor is a branchy sequence or a
    // library call on baseline x86-64. Further outside, the particle has left the grid and the
    // step is reported, whatever these weights are.
    const auto c = static_cast<std::int64_t>(s + 0.5) - 1;  // node left of the nearest one
    const double r = s - static_cast<double>(c + 1);
    // max and min written as the comparisons SSE's maxsd and minsd perform: std::max and
    // std::clamp compile to branches here.
    const auto max0 = [](double a) { return a > 0.0 ? a : 0.0; };
    const auto min_ = [](double a, double b) { return a < b ? a : b; };
    const double lq = lp * inv_L;
    const double q = lq > 1e-12 ? lq : 1e-12;  // a zero width is the linear hat, reached continuously
    const double tl = q - r, tr = q + r, q2 = 2.0 * q;
    const double cl = min_(max0(tl), q2), cr = min_(max0(tr), q2);
    const double inv4q = 0.25 / q;
    w[0] = cl * cl * inv4q + max0(tl - q2);
    w[2] = cr * cr * inv4q + max0(tr - q2);
    w[1] = 1.0 - w[0] - w[2];
    // dt/dx_p is -1/L on the left, +1/L on the right; g'(t) = clamp(t / 2q, 0, 1).
    dw[0] = -2.0 * cl * inv4q * inv_L;
    dw[2] = 2.0 * cr * inv4q * inv_L;
    dw[1] = -dw[0] - dw[2];
    return static_cast<int>(c);
  }
};

}  // namespace tsuchi::shape
