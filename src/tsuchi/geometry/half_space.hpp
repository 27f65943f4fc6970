#pragma once
// The half-space {x : (x - point) . normal <= 0}: the normal points out of the kept side, as an
// outward normal of a body's surface does. Unbounded, so it is meant as an operand of a boolean
// (a slope: a box intersected with a half-space); io/shape_reader.cpp refuses it alone as a body.
#include "tsuchi/geometry/shape.hpp"

namespace tsuchi::geometry {

class HalfSpace final : public Shape {
 public:
  // `normal` need not be unit length; it must not be zero.
  HalfSpace(const Point& point, const Point& normal, int dimension) : p_(point), n_(normal), dim_(dimension) {
    for (int d = dimension; d < 3; ++d) n_[d] = 0.0, p_[d] = 0.0;
  }

  bool contains(const Point& x) const override { return level(x) <= 0.0; }

  // Along the line x + s e_a the level (x - p).n + s n_a is linear in s: the kept part is a ray
  // (or all or nothing when the line is parallel to the plane).
  Intervals chord(const Point& x, int axis) const override {
    const double f = level(x), na = n_[axis];
    if (na == 0.0) return f <= 0.0 ? Intervals{{-kUnbounded, kUnbounded}} : Intervals{};
    const double cut = x[axis] - f / na;
    return na > 0.0 ? Intervals{{-kUnbounded, cut}} : Intervals{{cut, kUnbounded}};
  }

  // Unbounded on every axis the plane is not normal to; bounded on one side along an axis it is
  // normal to (a floor at y <= 0 keeps y <= 0 only).
  Bounds bounds() const override {
    Point lo = Point::Zero(), hi = Point::Zero();
    for (int d = 0; d < dim_; ++d) lo[d] = -kUnbounded, hi[d] = kUnbounded;
    int along = -1;
    for (int d = 0; d < dim_; ++d)
      if (n_[d] != 0.0) along = along == -1 ? d : -2;
    if (along >= 0) (n_[along] > 0.0 ? hi : lo)[along] = p_[along];
    return {lo, hi};
  }

 private:
  double level(const Point& x) const { return (x - p_).dot(n_); }

  Point p_, n_;
  int dim_;
};

}  // namespace tsuchi::geometry
