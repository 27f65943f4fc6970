#pragma once
// GIMP shape function (Bardenhagen & Kober 2004): the linear hat integrated against the particle's
// characteristic function of half-width l_p, eq (16)-(17), as corrected in METHOD.md section 2.
// The table there is valid for l_p <= L/2, which the domain update keeps (see particle_domain.hpp).
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
struct GimpKernel {
  static constexpr int K = 3;
  static constexpr const char* name = "gimp";

  static inline int weights(double s, double L, double lp, double* w, double* dw) {
    const double c = std::floor(s - 0.5);  // node left of the nearest one
    for (int k = 0; k < K; ++k) {
      const double xi = (s - (c + k)) * L;
      w[k] = gimp_S(xi, L, lp);
      dw[k] = gimp_dS(xi, L, lp);
    }
    return static_cast<int>(c);
  }
};

}  // namespace tsuchi::shape
