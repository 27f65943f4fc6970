#pragma once
// A polygon with holes: the region of a plane inside an outline and outside its holes. It is the
// 2D `polygon` shape and the cross-section of the 3D `extrusion` (extrusion.hpp).
//
// Inside is decided by the crossing (even-odd) rule: a line crosses the boundary of the region
// an even number of times, and the chord along it is the crossings paired up in order. An edge
// (p, q) is crossed by the line v = c when exactly one of its ends lies above the line,
// (p_v > c) != (q_v > c), so a vertex lying on the line counts as above it: a line through a
// vertex meets one of the vertex's two edges when it passes through, and none or both when it
// only touches, and an edge along the line is never crossed (the classic half-open rule of
// point-in-polygon tests, e.g. Haines, "Point in polygon strategies", Graphics Gems IV, 1994).
#include "tsuchi/geometry/shape.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace tsuchi::geometry {

using Point2 = Eigen::Vector2d;
using Ring = std::vector<Point2>;

class PolygonRegion {
 public:
  PolygonRegion() = default;
  // The rings must have passed problem(); orientation does not matter.
  PolygonRegion(Ring outline, std::vector<Ring> holes);

  // What is wrong with this outline and these holes, in words naming the ring ("the outline",
  // "hole 2") and the edges (numbered from 1: edge k joins vertex k to vertex k+1), or nothing.
  // Refused: fewer than 3 vertices, a zero-length edge, zero area, two edges that cross or
  // touch (other than neighbours at their shared vertex), a hole outside the outline, a hole
  // inside another.
  // More than max_vertices (over all rings) are refused too.
  static std::optional<std::string> problem(const Ring& outline, const std::vector<Ring>& holes);
  static constexpr std::size_t max_vertices = 100000;

  bool contains(const Point2& p) const;
  // Intervals of coordinate `axis` (0 or 1) along the line through p parallel to that axis.
  Intervals chord(const Point2& p, int axis) const;
  // Area: the shoelace formula of the outline less those of the holes.
  double area() const;
  Point2 min() const { return min_; }
  Point2 max() const { return max_; }

 private:
  // The edges of every ring by bands of one coordinate: a line v = c can only cross the edges
  // listed in the band of c (each edge is listed in every band its v-range meets). A query then
  // visits a few edges, not all of them: a polygon at the allowed 100,000 vertices made `check`
  // run for minutes at particles x vertices (issue 41, defect 11). The same edges give the same
  // crossings, so the chords are bit for bit those of the scan over all edges.
  struct Bands {
    double lo = 0.0, inv_width = 0.0;
    std::vector<std::uint32_t> start;  // band k lists edges[start[k] .. start[k + 1])
    std::vector<std::uint32_t> edges;  // global edge numbers: ring_start_[ring] + index
    std::size_t band(double v) const;
  };
  void index_edges();

  std::vector<Ring> rings_;  // the outline, then the holes: even-odd treats them alike
  std::vector<std::uint32_t> ring_start_;  // global number of each ring's first edge, and the total
  Bands bands_[2];  // by coordinate 0 (lines x = c, chords along y) and 1 (lines y = c)
  Point2 min_, max_;
};

// The 2D shape.
class Polygon final : public Shape {
 public:
  explicit Polygon(PolygonRegion region) : region_(std::move(region)) {}
  bool contains(const Point& x) const override { return region_.contains(x.head<2>()); }
  Intervals chord(const Point& x, int axis) const override { return region_.chord(x.head<2>(), axis); }
  Bounds bounds() const override {
    Point lo = Point::Zero(), hi = Point::Zero();
    lo.head<2>() = region_.min(), hi.head<2>() = region_.max();
    return {lo, hi};
  }
  double measure() const override { return region_.area(); }

 private:
  PolygonRegion region_;
};

}  // namespace tsuchi::geometry
