#pragma once
// A disk (2D) or a ball (3D: the sphere): all points within `radius` of `centre`. The chord of a
// line along an axis is the one interval centre_a -/+ sqrt(R^2 - d^2), d the line's distance
// from the centre (Pythagoras), so it is exact.
#include "tsuchi/geometry/shape.hpp"

#include <cmath>
#include <numbers>

namespace tsuchi::geometry {

class Ball final : public Shape {
 public:
  Ball(const Point& centre, double radius, int dimension) : c_(centre), r_(radius), dim_(dimension) {}

  bool contains(const Point& x) const override { return squared_distance(x, -1) <= r_ * r_; }

  Intervals chord(const Point& x, int axis) const override {
    const double d2 = squared_distance(x, axis);
    if (d2 >= r_ * r_) return {};
    const double half = std::sqrt(r_ * r_ - d2);
    return {{c_[axis] - half, c_[axis] + half}};
  }

  Bounds bounds() const override {
    Point lo = c_, hi = c_;
    for (int d = 0; d < dim_; ++d) lo[d] -= r_, hi[d] += r_;
    return {lo, hi};
  }

  double measure() const override {
    return dim_ == 2 ? std::numbers::pi * r_ * r_ : 4.0 / 3.0 * std::numbers::pi * r_ * r_ * r_;
  }

 private:
  // Squared distance from the centre over the dimensions other than `skip`.
  double squared_distance(const Point& x, int skip) const {
    double s = 0.0;
    for (int d = 0; d < dim_; ++d)
      if (d != skip) s += (x[d] - c_[d]) * (x[d] - c_[d]);
    return s;
  }

  Point c_;
  double r_;
  int dim_;
};

}  // namespace tsuchi::geometry
