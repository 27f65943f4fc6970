#pragma once
// An axis-aligned box [min, max] (a rectangle in 2D): the shape every body had before shapes.
#include "tsuchi/geometry/shape.hpp"

namespace tsuchi::geometry {

class Box final : public Shape {
 public:
  Box(const Point& min, const Point& max, int dimension) : min_(min), max_(max), dim_(dimension) {}

  bool contains(const Point& x) const override {
    for (int d = 0; d < dim_; ++d)
      if (x[d] < min_[d] || x[d] > max_[d]) return false;
    return true;
  }

  Intervals chord(const Point& x, int axis) const override {
    for (int d = 0; d < dim_; ++d)
      if (d != axis && (x[d] < min_[d] || x[d] > max_[d])) return {};
    return {{min_[axis], max_[axis]}};
  }

  Bounds bounds() const override { return {min_, max_}; }

  double measure() const override {
    double v = 1.0;
    for (int d = 0; d < dim_; ++d) v *= max_[d] - min_[d];
    return v;
  }

 private:
  Point min_, max_;
  int dim_;
};

}  // namespace tsuchi::geometry
