#pragma once
// Linear (standard MPM) shape function, eq (15): the hat of half-width L around each node.
#include <Eigen/Core>

#include <array>
#include <cmath>

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
  static constexpr int reach_below = 0, reach_above = 0;  // the cell's own two nodes (see GimpKernel)
  static constexpr const char* name = "linear";

  // Every axis at once (see GimpKernel). s = (x_p - origin) / L in cell units, inv_L = 1 / L.
  template <int D>
  [[gnu::always_inline]] static inline Eigen::Array<int, D, 1> weights(const Eigen::Array<double, D, 1>& s, double inv_L,
                                                const Eigen::Array<double, D, 1>& /*l_p*/,
                                                std::array<Eigen::Array<double, D, 1>, K>& w,
                                                std::array<Eigen::Array<double, D, 1>, K>& dw) {
    // floor(s) by truncation, exact for s >= 0, that is inside the grid (see GimpKernel).
    const Eigen::Array<int, D, 1> c = s.template cast<int>();
    const Eigen::Array<double, D, 1> f = s - c.template cast<double>();  // position in the cell, [0, 1)
    w[0] = 1.0 - f;
    w[1] = f;
    dw[0].setConstant(-inv_L);
    dw[1].setConstant(inv_L);
    return c;
  }
};

}  // namespace tsuchi::shape
