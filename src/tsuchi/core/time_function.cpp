#include "tsuchi/core/time_function.hpp"

#include "tsuchi/core/errors.hpp"

#include <fmt/format.h>

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

TimeFunction TimeFunction::formula(std::shared_ptr<const Expression> of_time, std::string name, std::string text) {
  TimeFunction f;
  f.kind_ = Kind::Formula;
  f.f_ = std::move(of_time);
  f.name_ = std::move(name);
  f.text_ = std::move(text);
  return f;
}

double TimeFunction::finite(double value, double t) const {
  if (std::isfinite(value)) return value;
  // t is on the function's own clock; a stage that set it started it at start_ on the run's clock.
  const std::string when = start_ != 0.0 ? fmt::format("t = {:.6g} s (its clock started at {:.6g} s, so {:.6g} s on it)",
                                                       t + start_, start_, t)
                                         : fmt::format("t = {:.6g} s", t);
  throw RunError(fmt::format("function \"{}\" (formula \"{}\") is {} at {}: the load, gravity or motion it scales "
                             "would be too; give a formula finite at every time of the run (e.g. log(t + 1e-3) "
                             "rather than log(t))",
                             name_, text_, std::isnan(value) ? "NaN" : value > 0.0 ? "inf" : "-inf", when),
                 Fault::NonFinite);
}

double TimeFunction::operator()(double t) const {
  t -= start_;
  switch (kind_) {
    case Kind::One: return 1.0;
    case Kind::Formula: return finite(f_->at_time(t), t);
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
      if (!std::isfinite(sum))  // name the first time where it fails
        for (int k = 0; k < pieces; ++k)
          for (const std::size_t q : {3u, 1u, 0u, 2u, 4u}) {  // the points in time order
            const double tq = a + (k + 0.5) * h + 0.5 * h * x[q];
            finite(f_->at_time(tq), tq);
          }
      return 0.5 * h * finite(sum, a);
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
