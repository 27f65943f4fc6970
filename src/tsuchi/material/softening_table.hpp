#pragma once
// A strength parameter as a piecewise-linear function of the softening parameter k (FLAC's
// strain-softening tables): points (k_i, v_i) with k_0 = 0 < k_1 < ... < k_n, linear between
// them, v_n (the residual value) beyond the last one. A constant is the table of one point.
#include <algorithm>
#include <cstddef>
#include <vector>

namespace tsuchi {

struct SofteningTable {
  std::vector<double> strain{0.0};  // k_i, from 0, strictly increasing
  std::vector<double> value{0.0};   // v_i

  static SofteningTable constant(double v) { return {{0.0}, {v}}; }

  bool varies() const { return strain.size() > 1; }

  double at(double k) const {
    if (k >= strain.back()) return value.back();  // the residual (and the constant)
    if (k <= 0.0) return value.front();
    // Tables are a few points long: a linear search beats a bisection.
    std::size_t i = 1;
    while (strain[i] < k) ++i;
    const double t = (k - strain[i - 1]) / (strain[i] - strain[i - 1]);
    return value[i - 1] + t * (value[i] - value[i - 1]);
  }

  // The same values at abscissae times f (the regularisation's L / h).
  SofteningTable scaled(double f) const {
    SofteningTable t = *this;
    for (double& k : t.strain) k *= f;
    return t;
  }

  double max_value() const { return *std::max_element(value.begin(), value.end()); }
};

}  // namespace tsuchi
