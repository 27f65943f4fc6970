#pragma once
// A solid circular cylinder (3D) between the end centres `base` and `top`, of radius R, in any
// direction. Along a line x + s e_a it is the intersection of the slab 0 <= (p - base).w <= L
// (w the unit axis, L its length: linear in s) and the infinite cylinder |r - (r.w) w|^2 <= R^2
// (r = p - base: quadratic in s), so the chord is exact.
#include "tsuchi/geometry/shape.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tsuchi::geometry {

class Cylinder final : public Shape {
 public:
  Cylinder(const Point& base, const Point& top, double radius)
      : base_(base), w_((top - base).normalized()), len_((top - base).norm()), r_(radius) {}

  bool contains(const Point& x) const override {
    const Point r = x - base_;
    const double t = r.dot(w_);
    return t >= 0.0 && t <= len_ && (r - t * w_).squaredNorm() <= r_ * r_;
  }

  Intervals chord(const Point& x, int axis) const override {
    const Point r0 = x - base_;
    const double wa = w_[axis];
    // Slab: t(s) = r0.w + s w_a in [0, L].
    double lo = -kUnbounded, hi = kUnbounded;
    const double t0 = r0.dot(w_);
    if (wa == 0.0) {
      if (t0 < 0.0 || t0 > len_) return {};
    } else {
      const double s1 = -t0 / wa, s2 = (len_ - t0) / wa;
      lo = std::min(s1, s2), hi = std::max(s1, s2);
    }
    // Tube: the part of r(s) across the axis is q0 + s q, q0 = r0 - (r0.w) w, q = e_a - w_a w;
    // |q0 + s q|^2 <= R^2 is A s^2 + 2 B s + C <= 0.
    const Point q0 = r0 - t0 * w_;
    Point q = -wa * w_;
    q[axis] += 1.0;
    const double A = q.squaredNorm(), B = q0.dot(q), C = q0.squaredNorm() - r_ * r_;
    if (A <= 1e-24) {  // the line is parallel to the axis: inside the tube everywhere or nowhere
      if (C > 0.0) return {};
    } else {
      const double disc = B * B - A * C;
      if (disc <= 0.0) return {};
      const double root = std::sqrt(disc);
      lo = std::max(lo, (-B - root) / A), hi = std::min(hi, (-B + root) / A);
    }
    if (!(lo < hi)) return {};
    return {{x[axis] + lo, x[axis] + hi}};
  }

  // Each end disk reaches R sqrt(1 - w_d^2) from its centre along axis d.
  Bounds bounds() const override {
    const Point top = base_ + len_ * w_;
    Point lo, hi;
    for (int d = 0; d < 3; ++d) {
      const double reach = r_ * std::sqrt(std::max(0.0, 1.0 - w_[d] * w_[d]));
      lo[d] = std::min(base_[d], top[d]) - reach, hi[d] = std::max(base_[d], top[d]) + reach;
    }
    return {lo, hi};
  }

  double measure() const override { return std::numbers::pi * r_ * r_ * len_; }

 private:
  Point base_, w_;
  double len_, r_;
};

}  // namespace tsuchi::geometry
