#pragma once
// The weights of a single axis. The kernels (gimp.hpp, linear.hpp) compute every axis at once, one
// SIMD lane per axis; checks and code off the hot path use this one-axis form.
#include <Eigen/Core>

#include <array>

namespace tsuchi::shape {

// Fills w[0..K), dw[0..K) for s = (x_p - origin) / L, inv_L = 1 / L and half-width lp; returns the
// first node index.
template <class Kernel>
int axis_weights(double s, double inv_L, double lp, double* w, double* dw) {
  std::array<Eigen::Array<double, 1, 1>, Kernel::K> w1, dw1;
  const int c =
      Kernel::template weights<1>(Eigen::Array<double, 1, 1>(s), inv_L, Eigen::Array<double, 1, 1>(lp), w1, dw1)[0];
  for (int k = 0; k < Kernel::K; ++k) w[k] = w1[k][0], dw[k] = dw1[k][0];
  return c;
}

}  // namespace tsuchi::shape
