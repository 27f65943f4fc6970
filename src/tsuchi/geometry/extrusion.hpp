#pragma once
// A prism (3D): a polygon with holes in the plane normal to `axis`, extruded from `from` to `to`
// along it. The polygon's two coordinates are the other two axes in increasing order: (y, z) for
// an extrusion along x, (x, z) along y, (x, y) along z. A chord along the axis is [from, to]
// where the polygon holds the line's foot; across it, the polygon's own chord where from <= x_axis
// <= to.
#include "tsuchi/geometry/polygon.hpp"

namespace tsuchi::geometry {

class Extrusion final : public Shape {
 public:
  Extrusion(PolygonRegion region, int axis, double from, double to)
      : region_(std::move(region)), axis_(axis), u_(axis == 0 ? 1 : 0), v_(axis == 2 ? 1 : 2), from_(from), to_(to) {}

  bool contains(const Point& x) const override {
    return x[axis_] >= from_ && x[axis_] <= to_ && region_.contains(foot(x));
  }

  Intervals chord(const Point& x, int axis) const override {
    if (axis == axis_) return region_.contains(foot(x)) ? Intervals{{from_, to_}} : Intervals{};
    if (x[axis_] < from_ || x[axis_] > to_) return {};
    return region_.chord(foot(x), axis == u_ ? 0 : 1);
  }

  Bounds bounds() const override {
    Point lo, hi;
    lo[axis_] = from_, hi[axis_] = to_;
    lo[u_] = region_.min()[0], lo[v_] = region_.min()[1];
    hi[u_] = region_.max()[0], hi[v_] = region_.max()[1];
    return {lo, hi};
  }

  double measure() const override { return region_.area() * (to_ - from_); }

 private:
  Point2 foot(const Point& x) const { return {x[u_], x[v_]}; }

  PolygonRegion region_;
  int axis_, u_, v_;
  double from_, to_;
};

}  // namespace tsuchi::geometry
