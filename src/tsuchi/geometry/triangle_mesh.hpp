#pragma once
// A solid bounded by a closed triangulated surface (read from an STL file by io/stl_reader.cpp).
//
// A chord along axis a is found by projecting the surface on the plane of the other two axes:
// the triangles whose projection holds the line's foot are the ones the line crosses, each at
// the depth where the line meets its plane; the crossings sorted and paired up (even-odd, as for
// polygons) give the chord, and contains(x) is whether x_z lies in the chord along z.
//
// A line through an edge or a vertex must be counted once, not twice or never. Each edge's
// side test (the 2D orientation of the edge and the foot) is computed from the edge's two
// vertices in one fixed order (lower vertex index first) and negated for the triangle that runs
// the other way, so the two triangles sharing an edge see exactly opposite signs, bit for bit.
// A foot lying exactly on an edge (a zero sign) is decided as if it were moved by an
// infinitesimal (eps, eps^2) in the plane (simulation of simplicity, Edelsbrunner & Muecke,
// ACM Trans. Graphics 9, 1990): the sign then comes from the edge's direction alone and is never
// zero, so every foot is inside exactly the triangles a slightly moved line would cross.
// Triangles seen edge-on (zero projected area) are crossed by no moved line and are skipped.
//
// Acceleration: for each axis, the projected triangles are binned in a grid of about one bin per
// triangle, built in the constructor (so queries from many threads are safe: nothing changes
// after construction). A query visits the triangles of one bin.
#include "tsuchi/geometry/shape.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace tsuchi::geometry {

using Triangle = std::array<Point, 3>;

class TriangleMesh final : public Shape {
 public:
  // What is wrong with the surface, or nothing: a coordinate that is not finite, a triangle of
  // zero area, an edge not shared by exactly two triangles (an open surface or one with more than
  // two faces on an edge), an edge run twice in the same direction (neighbours of opposite
  // orientation). Vertices are the same when their coordinates are equal bit for bit, as an STL
  // file writes them. `name` words triangle k (from 0) for the message ("triangle 3 (line 20)").
  static std::optional<std::string> problem(const std::vector<Triangle>& triangles,
                                            const std::function<std::string(std::size_t)>& name);

  // The triangles must have passed problem().
  // `precision`: Shape::precision(), the rounding of the file's coordinates in m.
  explicit TriangleMesh(const std::vector<Triangle>& triangles, double precision = 0.0);

  bool contains(const Point& x) const override;
  Intervals chord(const Point& x, int axis) const override;
  Bounds bounds() const override { return {min_, max_}; }
  // The volume by the divergence theorem: the sum of the signed volumes of the tetrahedra from
  // a point to each triangle, (v0 - o) . ((v1 - o) x (v2 - o)) / 6 (its absolute value: either
  // orientation of the surface).
  double measure() const override;
  double precision() const override { return precision_; }

  std::size_t triangle_count() const { return tri_.size(); }

  // The volume the even-odd rule fills (what contains() and chord() give) and the volume inside
  // any of the surfaces (the nonzero winding rule), sampled on the same samples x samples columns.
  // They differ where closed surfaces overlap or nest with the same orientation: the even-odd
  // rule then leaves the overlap out, which a user meaning one solid of two shells did not want.
  struct Fill {
    double even_odd = 0.0, nonzero = 0.0;
  };
  Fill fill_volumes(int samples) const;

 private:
  // The crossings of the line through x along `axis` with the surface, by depth, each with the
  // side its triangle faces along the axis (+1 or -1).
  void crossings(const Point& x, int axis, std::vector<std::pair<double, int>>& out) const;

  struct Bins {
    int u = 0, v = 0;            // the projection's axes
    Eigen::Vector2d lo, inv_h;   // the grid's corner and 1 / bin size
    int nu = 1, nv = 1;
    std::vector<std::uint32_t> start;  // bin b's triangles: index[start[b] .. start[b + 1])
    std::vector<std::uint32_t> index;
    int bin(double x, double lo_, double inv, int n) const;
  };

  std::vector<Point> vert_;
  std::vector<std::array<std::uint32_t, 3>> tri_;
  Point min_, max_;
  double precision_ = 0.0;
  std::array<Bins, 3> bins_;
};

}  // namespace tsuchi::geometry
