#pragma once
// Linear (standard MPM) shape function, eq (15): the hat of half-width L around each node.
#include <cmath>
#include <cstdint>

namespace tsuchi::shape {

// S and dS/dxi for xi = x_p - x_v.
inline double linear_S(double xi, double L) {
  const double a = std::abs(xi);
  return a < L ? 1.0 - a / L : 0.0;
}

inline double linear_dS(double xi, double L) {
  if (std::abs(xi) >= L) return 0.0;
  return xi > 0.0 ? -1.0 / L : 1.0 / L;
}

// Two nodes per axis: the ends of the cell holding the particle. The particle half-width is unused.
struct LinearKernel {
  static constexpr int K = 2;
  static constexpr const char* name = "linear";

  // s = (x_p - origin) / L in cell units, inv_L = 1 / L; fills the first node index and K
  // weights/derivatives.
  static inline int weights(double s, double inv_L, double /*l_p*/, double* w, double* dw) {
    // floor(s) by truncation, exact for s >= 0, that is inside the grid (see GimpKernel).
    const auto c = static_cast<std::int64_t>(s);
    const double f = s - static_cast<double>(c);  // position within the cell, in [0, 1)
    w[0] = 1.0 - f;
    w[1] = f;
    dw[0] = -inv_L;
    dw[1] = inv_L;
    return static_cast<int>(c);
  }
};

}  // namespace tsuchi::shape
