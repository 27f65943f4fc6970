#include "tsuchi/geometry/triangle_mesh.hpp"

#include "tsuchi/geometry/intervals.hpp"

#include <Eigen/Geometry>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

namespace tsuchi::geometry {

namespace {

using Key = std::array<double, 3>;

// Welds the corners of the triangles into shared vertices: equal coordinates, one vertex.
void weld(const std::vector<Triangle>& triangles, std::vector<Point>& vert,
          std::vector<std::array<std::uint32_t, 3>>& tri) {
  std::map<Key, std::uint32_t> id;
  tri.resize(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      const Point& p = triangles[t][c];
      const auto [it, fresh] = id.emplace(Key{p[0], p[1], p[2]}, static_cast<std::uint32_t>(vert.size()));
      if (fresh) vert.push_back(p);
      tri[t][c] = it->second;
    }
}

std::string point_text(const Point& p) { return fmt::format("({}, {}, {})", p[0], p[1], p[2]); }

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) { return (std::uint64_t{a} << 32) | b; }

// The sign of the orientation of the foot p against the edge a->b in the plane (u, v), with the
// tie-break of triangle_mesh.hpp: computed from the lower-numbered vertex, negated otherwise.
int side(const std::vector<Point>& vert, std::uint32_t ia, std::uint32_t ib, int u, int v, double pu, double pv) {
  const bool flip = ia > ib;
  const Point& a = vert[flip ? ib : ia];
  const Point& b = vert[flip ? ia : ib];
  const double du = b[u] - a[u], dv = b[v] - a[v];
  const double e = du * (pv - a[v]) - dv * (pu - a[u]);
  // Moved by (eps, eps^2): e + du eps^2 - dv eps; its sign when e is zero.
  int s = e > 0 ? 1 : e < 0 ? -1 : dv != 0 ? (dv > 0 ? -1 : 1) : (du > 0 ? 1 : -1);
  return flip ? -s : s;
}

// The same orientation, as a number (for barycentric weights).
double orient(const Point& a, const Point& b, int u, int v, double pu, double pv) {
  return (b[u] - a[u]) * (pv - a[v]) - (b[v] - a[v]) * (pu - a[u]);
}

}  // namespace

std::optional<std::string> TriangleMesh::problem(const std::vector<Triangle>& triangles,
                                                 const std::function<std::string(std::size_t)>& name) {
  if (triangles.size() < 4)
    return fmt::format("{} triangles cannot close a surface: at least 4 are needed", triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (const Point& p : triangles[t])
      if (!p.allFinite()) return fmt::format("{} has a coordinate that is not a finite number", name(t));
  std::vector<Point> vert;
  std::vector<std::array<std::uint32_t, 3>> tri;
  weld(triangles, vert, tri);
  Point lo = vert[0], hi = vert[0];
  for (const Point& p : vert) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double size = (hi - lo).maxCoeff();
  for (std::size_t t = 0; t < tri.size(); ++t) {
    const Point &a = vert[tri[t][0]], &b = vert[tri[t][1]], &c = vert[tri[t][2]];
    if ((b - a).cross(c - a).norm() <= 1e-12 * size * size)
      return fmt::format("{} has zero area (corners {}, {}, {})", name(t), point_text(a), point_text(b),
                         point_text(c));
  }
  // Every directed edge once, and its reverse once: a closed, consistently oriented surface.
  std::unordered_map<std::uint64_t, std::size_t> owner;
  owner.reserve(3 * tri.size());
  for (std::size_t t = 0; t < tri.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t a = tri[t][c], b = tri[t][(c + 1) % 3];
      const auto [it, fresh] = owner.emplace(edge_key(a, b), t);
      if (!fresh)
        return fmt::format(
            "the edge from {} to {} is run in the same direction by {} and {}: the triangles around it do "
            "not agree on which side is outside (or more than two triangles share the edge)",
            point_text(vert[a]), point_text(vert[b]), name(it->second), name(t));
    }
  for (std::size_t t = 0; t < tri.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t a = tri[t][c], b = tri[t][(c + 1) % 3];
      if (!owner.count(edge_key(b, a)))
        return fmt::format("the surface is not closed: the edge from {} to {} of {} belongs to no other triangle",
                           point_text(vert[a]), point_text(vert[b]), name(t));
    }
  // Closed and oriented, yet flat (a sheet doubled back on itself): nothing to fill.
  const Point o = vert[0];
  double volume = 0.0;
  for (const auto& t : tri) volume += (vert[t[0]] - o).dot((vert[t[1]] - o).cross(vert[t[2]] - o));
  if (std::abs(volume) / 6.0 <= 1e-12 * size * size * size)
    return fmt::format("the surface encloses no volume (its {} triangles lie flat on each other)", tri.size());
  return std::nullopt;
}

TriangleMesh::TriangleMesh(const std::vector<Triangle>& triangles, double precision) : precision_(precision) {
  weld(triangles, vert_, tri_);
  min_ = max_ = vert_[0];
  for (const Point& p : vert_) min_ = min_.cwiseMin(p), max_ = max_.cwiseMax(p);
  // About one bin per triangle in each projection: a bin then holds a few triangles on average.
  const int n = std::clamp(static_cast<int>(std::sqrt(static_cast<double>(tri_.size()))), 1, 1024);
  for (int a = 0; a < 3; ++a) {
    Bins& g = bins_[a];
    g.u = (a + 1) % 3, g.v = (a + 2) % 3;
    g.lo = {min_[g.u], min_[g.v]};
    const double wu = max_[g.u] - min_[g.u], wv = max_[g.v] - min_[g.v];
    g.nu = g.nv = n;
    g.inv_h = {wu > 0 ? n / wu : 0.0, wv > 0 ? n / wv : 0.0};
    // Two passes (count, fill) into one flat array.
    std::vector<std::array<int, 4>> range(tri_.size());
    std::vector<std::uint32_t> count(static_cast<std::size_t>(n) * n + 1, 0);
    for (std::size_t t = 0; t < tri_.size(); ++t) {
      const Point &p = vert_[tri_[t][0]], &q = vert_[tri_[t][1]], &r = vert_[tri_[t][2]];
      if (orient(p, q, g.u, g.v, r[g.u], r[g.v]) == 0.0) {  // seen edge-on: never crossed
        range[t] = {0, -1, 0, -1};
        continue;
      }
      // Bins are found by the same monotone formula for a triangle's corners and for a query's
      // foot, so a foot inside a triangle always falls in one of the triangle's bins.
      range[t] = {g.bin(std::min({p[g.u], q[g.u], r[g.u]}), g.lo[0], g.inv_h[0], n),
                  g.bin(std::max({p[g.u], q[g.u], r[g.u]}), g.lo[0], g.inv_h[0], n),
                  g.bin(std::min({p[g.v], q[g.v], r[g.v]}), g.lo[1], g.inv_h[1], n),
                  g.bin(std::max({p[g.v], q[g.v], r[g.v]}), g.lo[1], g.inv_h[1], n)};
      for (int i = range[t][0]; i <= range[t][1]; ++i)
        for (int j = range[t][2]; j <= range[t][3]; ++j) ++count[static_cast<std::size_t>(i) * n + j + 1];
    }
    for (std::size_t b = 1; b < count.size(); ++b) count[b] += count[b - 1];
    g.start = count;
    g.index.resize(count.back());
    for (std::size_t t = 0; t < tri_.size(); ++t)
      for (int i = range[t][0]; i <= range[t][1]; ++i)
        for (int j = range[t][2]; j <= range[t][3]; ++j)
          g.index[count[static_cast<std::size_t>(i) * n + j]++] = static_cast<std::uint32_t>(t);
  }
}

int TriangleMesh::Bins::bin(double x, double lo_, double inv, int n) const {
  return std::clamp(static_cast<int>(std::floor((x - lo_) * inv)), 0, n - 1);
}

void TriangleMesh::crossings(const Point& x, int axis, std::vector<std::pair<double, int>>& out) const {
  out.clear();
  const Bins& g = bins_[axis];
  const double pu = x[g.u], pv = x[g.v];
  if (pu < min_[g.u] || pu > max_[g.u] || pv < min_[g.v] || pv > max_[g.v]) return;
  const std::size_t b = static_cast<std::size_t>(g.bin(pu, g.lo[0], g.inv_h[0], g.nu)) * g.nv +
                        static_cast<std::size_t>(g.bin(pv, g.lo[1], g.inv_h[1], g.nv));
  for (std::uint32_t k = g.start[b]; k < g.start[b + 1]; ++k) {
    const auto& t = tri_[g.index[k]];
    const int s0 = side(vert_, t[1], t[2], g.u, g.v, pu, pv);
    const int s1 = side(vert_, t[2], t[0], g.u, g.v, pu, pv);
    const int s2 = side(vert_, t[0], t[1], g.u, g.v, pu, pv);
    if (s0 != s1 || s1 != s2) continue;
    // Barycentric weights: each corner's is the orientation against the opposite edge, so the
    // depth is a convex combination of the corners' depths even for a foot on an edge.
    const Point &p = vert_[t[0]], &q = vert_[t[1]], &r = vert_[t[2]];
    const double w0 = orient(q, r, g.u, g.v, pu, pv), w1 = orient(r, p, g.u, g.v, pu, pv),
                 w2 = orient(p, q, g.u, g.v, pu, pv), sum = w0 + w1 + w2;
    out.emplace_back(sum != 0.0 ? (w0 * p[axis] + w1 * q[axis] + w2 * r[axis]) / sum
                                : (p[axis] + q[axis] + r[axis]) / 3.0,
                     s0);
  }
  std::sort(out.begin(), out.end());
}

Intervals TriangleMesh::chord(const Point& x, int axis) const {
  std::vector<std::pair<double, int>> depth;
  crossings(x, axis, depth);
  // A closed surface gives an even count; should rounding in a sliver triangle ever leave one
  // over, the last crossing is dropped rather than leaving a chord open to infinity.
  Intervals v;
  for (std::size_t i = 0; i + 1 < depth.size(); i += 2) v.push_back({depth[i].first, depth[i + 1].first});
  return normalized(std::move(v));
}

TriangleMesh::Fill TriangleMesh::fill_volumes(int samples) const {
  // Columns along z through the midpoints of a samples x samples grid over the bounds in x, y.
  // Along each, the winding number w steps by the side each crossed triangle faces; the even-odd
  // rule fills where the count of crossings so far is odd, the nonzero rule where w != 0. Both
  // are sampled on the same columns, so their difference is exact column by column.
  Fill f;
  const double wx = (max_[0] - min_[0]) / samples, wy = (max_[1] - min_[1]) / samples;
  std::vector<std::pair<double, int>> cross;
  for (int i = 0; i < samples; ++i)
    for (int j = 0; j < samples; ++j) {
      const Point x(min_[0] + (i + 0.5) * wx, min_[1] + (j + 0.5) * wy, 0.0);
      crossings(x, 2, cross);
      if (cross.size() % 2) continue;  // a sliver's rounding: the column is not judged
      int w = 0;
      for (std::size_t k = 0; k + 1 < cross.size(); ++k) {
        w += cross[k].second;
        const double dz = cross[k + 1].first - cross[k].first;
        if (k % 2 == 0) f.even_odd += dz;
        if (w != 0) f.nonzero += dz;
      }
    }
  f.even_odd *= wx * wy, f.nonzero *= wx * wy;
  return f;
}

bool TriangleMesh::contains(const Point& x) const { return covers(chord(x, 2), x[2]); }

double TriangleMesh::measure() const {
  // From a vertex rather than the origin: a surface far from the origin would lose digits.
  const Point o = vert_[0];
  double v = 0.0;
  for (const auto& t : tri_) v += (vert_[t[0]] - o).dot((vert_[t[1]] - o).cross(vert_[t[2]] - o));
  return std::abs(v) / 6.0;
}

}  // namespace tsuchi::geometry
