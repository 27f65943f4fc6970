#include "tsuchi/core/time_function.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace tsuchi {

TimeFunction TimeFunction::table(std::vector<double> times, std::vector<double> values) {
  TimeFunction f;
  f.kind_ = Kind::Table;
  f.t_ = std::move(times);
  f.v_ = std::move(values);
  return f;
}

TimeFunction TimeFunction::formula(std::shared_ptr<const Expression> of_time) {
  TimeFunction f;
  f.kind_ = Kind::Formula;
  f.f_ = std::move(of_time);
  return f;
}

double TimeFunction::operator()(double t) const {
  t -= start_;
  switch (kind_) {
    case Kind::One: return 1.0;
    case Kind::Formula: return f_->at_time(t);
    case Kind::Table: break;
  }
  if (t <= t_.front()) return v_.front();
  if (t >= t_.back()) return v_.back();
  const auto k = static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin());  // t_[k-1] <= t < t_[k]
  const double s = (t - t_[k - 1]) / (t_[k] - t_[k - 1]);
  return v_[k - 1] + s * (v_[k] - v_[k - 1]);
}

double TimeFunction::integral(double a, double b) const {
  if (b == a) return 0.0;
  if (b < a) return -integral(b, a);
  if (start_ != 0.0) {
    a = std::max(a, start_) - start_, b = std::max(b, start_) - start_;
    if (b == a) return 0.0;
  }
  switch (kind_) {
    case Kind::One: return b - a;
    case Kind::Formula: {
      // Gauss-Legendre, 5 points on [-1, 1].
      static constexpr std::array<double, 5> x{0.0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640,
                                               0.9061798459386640};
      static constexpr std::array<double, 5> w{0.5688888888888889, 0.4786286704993665, 0.4786286704993665,
                                               0.2369268850561891, 0.2369268850561891};
      constexpr int pieces = 50;
      const double h = (b - a) / pieces;
      double sum = 0.0;
      for (int k = 0; k < pieces; ++k) {
        const double mid = a + (k + 0.5) * h;
        for (std::size_t q = 0; q < x.size(); ++q) sum += w[q] * f_->at_time(mid + 0.5 * h * x[q]);
      }
      return 0.5 * h * sum;
    }
    case Kind::Table: break;
  }
  // f is piecewise linear with breaks at the table's times (constant outside): integrate each piece
  // of [a, b] between consecutive breaks by the trapezoid rule, which is exact there.
  double sum = 0.0, lo = a;
  auto k = static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), a) - t_.begin());
  while (lo < b) {
    const double hi = k < t_.size() ? std::min(b, t_[k]) : b;
    sum += 0.5 * (hi - lo) * ((*this)(lo + start_) + (*this)(hi + start_));  // a and b are on f's own clock here
    lo = hi;
    ++k;
  }
  return sum;
}

}  // namespace tsuchi
