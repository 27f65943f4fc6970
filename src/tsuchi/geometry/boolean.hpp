#pragma once
// A shape built from others: ((base u add_1 u ...) n intersect_1 n ...) \ subtract_1 \ ...
// Membership is the same formula on booleans; a chord is the same formula on the operands'
// chords (intervals.hpp), so it is as exact as theirs.
#include "tsuchi/geometry/intervals.hpp"
#include "tsuchi/geometry/shape.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace tsuchi::geometry {

class Boolean final : public Shape {
 public:
  Boolean(ShapePtr base, std::vector<ShapePtr> add, std::vector<ShapePtr> intersect, std::vector<ShapePtr> subtract)
      : base_(std::move(base)),
        add_(std::move(add)),
        intersect_(std::move(intersect)),
        subtract_(std::move(subtract)) {}

  bool contains(const Point& x) const override {
    bool in = base_->contains(x);
    for (const auto& s : add_) in = in || s->contains(x);
    for (const auto& s : intersect_) in = in && s->contains(x);
    for (const auto& s : subtract_) in = in && !s->contains(x);
    return in;
  }

  Intervals chord(const Point& x, int axis) const override {
    Intervals c = base_->chord(x, axis);
    for (const auto& s : add_) c = unite(c, s->chord(x, axis));
    for (const auto& s : intersect_) {
      if (c.empty()) return c;
      c = geometry::intersect(c, s->chord(x, axis));
    }
    for (const auto& s : subtract_) {
      if (c.empty()) return c;
      c = geometry::subtract(c, s->chord(x, axis));
    }
    return c;
  }

  double precision() const override {
    double p = base_->precision();
    for (const auto* parts : {&add_, &intersect_, &subtract_})
      for (const auto& s : *parts) p = std::max(p, s->precision());
    return p;
  }

  // The union's box, cut down by each intersected shape's box; a subtraction does not shrink it.
  Bounds bounds() const override {
    Bounds b = base_->bounds();
    for (const auto& s : add_) {
      const Bounds o = s->bounds();
      b.min = b.min.cwiseMin(o.min), b.max = b.max.cwiseMax(o.max);
    }
    for (const auto& s : intersect_) {
      const Bounds o = s->bounds();
      b.min = b.min.cwiseMax(o.min), b.max = b.max.cwiseMin(o.max);
    }
    return b;
  }

  // Known only for a difference whose removed parts lie inside the base and apart from each
  // other (a tunnel through a box): the base less each part. Whether a part lies inside is
  // judged from its box, so the base must fill its own box (`base_fills_bounds`).
  double measure() const override {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (!add_.empty() || !intersect_.empty() || !base_fills_bounds_) return nan;
    const Bounds b = base_->bounds();
    double m = base_->measure();
    for (std::size_t i = 0; i < subtract_.size(); ++i) {
      const Bounds o = subtract_[i]->bounds();
      if (!((o.min.array() >= b.min.array()).all() && (o.max.array() <= b.max.array()).all())) return nan;
      for (std::size_t j = 0; j < i; ++j) {
        const Bounds p = subtract_[j]->bounds();
        // Boxes overlap when they overlap along every axis; a flat axis (z in 2D) always does.
        bool overlap = true;
        for (int d = 0; d < 3; ++d)
          overlap = overlap &&
                    ((o.min[d] < p.max[d] && p.min[d] < o.max[d]) || (o.min[d] == o.max[d] && p.min[d] == p.max[d]));
        if (overlap) return nan;
      }
      m -= subtract_[i]->measure();
    }
    return m;
  }

  // Set by the reader when the base is a box (which fills its bounds).
  void set_base_fills_bounds(bool v) { base_fills_bounds_ = v; }

 private:
  ShapePtr base_;
  std::vector<ShapePtr> add_, intersect_, subtract_;
  bool base_fills_bounds_ = false;
};

}  // namespace tsuchi::geometry
