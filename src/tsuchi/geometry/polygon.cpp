#include "tsuchi/geometry/polygon.hpp"

#include "tsuchi/geometry/intervals.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace tsuchi::geometry {

namespace {

// Twice the signed area of the triangle (a, b, c): > 0 when c is left of a->b.
double orient(const Point2& a, const Point2& b, const Point2& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// Whether c, known to lie on the line through a and b, lies within the segment's box.
bool within(const Point2& a, const Point2& b, const Point2& c) {
  return std::min(a[0], b[0]) <= c[0] && c[0] <= std::max(a[0], b[0]) && std::min(a[1], b[1]) <= c[1] &&
         c[1] <= std::max(a[1], b[1]);
}

// Whether the closed segments [a, b] and [c, d] share a point: they cross when each one's ends
// lie on opposite sides of the other's line; they touch when an end lies on the other segment.
bool meet(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return true;
  return (o1 == 0 && within(a, b, c)) || (o2 == 0 && within(a, b, d)) || (o3 == 0 && within(c, d, a)) ||
         (o4 == 0 && within(c, d, b));
}

// Twice the signed area (shoelace formula).
double signed_area2(const Ring& r) {
  double s = 0.0;
  for (std::size_t i = 0, n = r.size(); i < n; ++i) {
    const Point2& p = r[i];
    const Point2& q = r[(i + 1) % n];
    s += p[0] * q[1] - q[0] * p[1];
  }
  return s;
}

std::string point_text(const Point2& p) { return fmt::format("({}, {})", p[0], p[1]); }

std::string edge_text(const Ring& r, std::size_t i) {
  return fmt::format("edge {} from {} to {}", i, point_text(r[i]), point_text(r[(i + 1) % r.size()]));
}

std::string ring_name(std::size_t k) { return k == 0 ? "the outline" : fmt::format("hole {}", k - 1); }

// The crossing of the line {coordinate b = c} with the edge (s, t), by the half-open rule of
// polygon.hpp, as a value of coordinate `axis` = 1 - b; nothing when it does not cross.
void crossing(const Point2& s, const Point2& t, double c, int axis, std::vector<double>& out) {
  const int b = 1 - axis;
  if ((s[b] > c) == (t[b] > c)) return;
  // Interpolate from the lower end so that the two polygons sharing an edge get the same bits.
  const Point2& lo = s[b] < t[b] ? s : t;
  const Point2& hi = s[b] < t[b] ? t : s;
  out.push_back(lo[axis] + (c - lo[b]) / (hi[b] - lo[b]) * (hi[axis] - lo[axis]));
}

// The crossings of the line {coordinate 1-axis = p[1-axis]} with all the ring's edges.
void crossings(const Ring& r, const Point2& p, int axis, std::vector<double>& out) {
  for (std::size_t i = 0, n = r.size(); i < n; ++i) crossing(r[i], r[(i + 1) % n], p[1 - axis], axis, out);
}

bool ring_contains(const Ring& r, const Point2& p) {
  std::vector<double> xs;
  crossings(r, p, 0, xs);
  return std::count_if(xs.begin(), xs.end(), [&](double x) { return x > p[0]; }) % 2 == 1;
}

}  // namespace

std::optional<std::string> PolygonRegion::problem(const Ring& outline, const std::vector<Ring>& holes) {
  std::vector<const Ring*> rings{&outline};
  for (const Ring& h : holes) rings.push_back(&h);
  for (std::size_t k = 0; k < rings.size(); ++k) {
    const Ring& r = *rings[k];
    const std::size_t n = r.size();
    if (n < 3) return fmt::format("{} has {} vertices: a polygon needs at least 3", ring_name(k), n);
    for (std::size_t i = 0; i < n; ++i)
      if (r[i] == r[(i + 1) % n])
        return fmt::format("{} has a zero-length edge: vertex {} repeats vertex {} at {}", ring_name(k),
                           (i + 1) % n, i, point_text(r[i]));
    // All vertices on the line from the first to the farthest one: zero area. (Not the signed
    // area: a figure of eight has zero signed area, and is refused below for its crossing.)
    std::size_t far = 0;
    for (std::size_t i = 1; i < n; ++i)
      if ((r[i] - r[0]).squaredNorm() > (r[far] - r[0]).squaredNorm()) far = i;
    const double len2 = (r[far] - r[0]).squaredNorm();
    if (std::all_of(r.begin(), r.end(),
                    [&](const Point2& p) { return std::abs(orient(r[0], r[far], p)) <= 1e-12 * len2; }))
      return fmt::format("{} has zero area (its vertices lie on one line)", ring_name(k));
  }
  // Pairs of edges whose x-ranges overlap, found by a sweep over the edges sorted by their lowest
  // x: a typical outline of n vertices costs n log n, not n^2 (a comb of long edges all side by
  // side still costs n^2; the cap on vertices bounds it).
  struct Edge {
    std::size_t ring, index;
    double lo, hi;
  };
  std::vector<Edge> edges;
  for (std::size_t k = 0; k < rings.size(); ++k)
    for (std::size_t i = 0, n = rings[k]->size(); i < n; ++i) {
      const double x0 = (*rings[k])[i][0], x1 = (*rings[k])[(i + 1) % n][0];
      edges.push_back({k, i, std::min(x0, x1), std::max(x0, x1)});
    }
  if (edges.size() > max_vertices)
    return fmt::format("{} vertices in all is more than the {} accepted", edges.size(), max_vertices);
  std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) {
    return a.lo != b.lo ? a.lo < b.lo : a.ring != b.ring ? a.ring < b.ring : a.index < b.index;
  });
  for (std::size_t p = 0; p < edges.size(); ++p)
    for (std::size_t q = p + 1; q < edges.size() && edges[q].lo <= edges[p].hi; ++q) {
      // The pair in input order: ring k edge i before ring l edge j.
      const bool in_order =
          edges[p].ring != edges[q].ring ? edges[p].ring < edges[q].ring : edges[p].index < edges[q].index;
      const Edge& e = in_order ? edges[p] : edges[q];
      const Edge& f = in_order ? edges[q] : edges[p];
      const Ring& r = *rings[e.ring];
      const Ring& t = *rings[f.ring];
      const std::size_t i = e.index, j = f.index, n = r.size();
      const Point2 &a = r[i], &b = r[(i + 1) % n], &c = t[j], &d = t[(j + 1) % t.size()];
      if (std::max(a[1], b[1]) < std::min(c[1], d[1]) || std::max(c[1], d[1]) < std::min(a[1], b[1])) continue;
      bool bad;
      if (e.ring == f.ring && j == i + 1) {
        // Neighbours share vertex b: wrong only if d doubles back along b->a.
        bad = orient(a, b, d) == 0 && (d - b).dot(a - b) > 0;
      } else if (e.ring == f.ring && i == 0 && j == n - 1) {
        bad = orient(a, b, c) == 0 && (c - a).dot(b - a) > 0;  // the last edge ends at a
      } else {
        bad = meet(a, b, c, d);
      }
      if (bad)
        return fmt::format("{} of {} crosses or touches {} of {}", edge_text(r, i), ring_name(e.ring), edge_text(t, j),
                           ring_name(f.ring));
    }
  // No edges meet, so a hole lies wholly inside or wholly outside any other ring: one vertex tells.
  for (std::size_t h = 1; h < rings.size(); ++h) {
    if (!ring_contains(outline, (*rings[h])[0])) return fmt::format("{} is not inside the outline", ring_name(h));
    for (std::size_t g = 1; g < rings.size(); ++g)
      if (g != h && ring_contains(*rings[g], (*rings[h])[0]))
        return fmt::format("{} lies inside {}: holes may not overlap", ring_name(h), ring_name(g));
  }
  return std::nullopt;
}

PolygonRegion::PolygonRegion(Ring outline, std::vector<Ring> holes) {
  min_ = max_ = outline[0];
  for (const Point2& p : outline) min_ = min_.cwiseMin(p), max_ = max_.cwiseMax(p);
  rings_.push_back(std::move(outline));
  for (Ring& h : holes) rings_.push_back(std::move(h));
  index_edges();
}

std::size_t PolygonRegion::Bands::band(double v) const {
  const double k = std::floor((v - lo) * inv_width);
  const auto last = static_cast<double>(start.size() - 2);
  return static_cast<std::size_t>(std::clamp(k, 0.0, last));  // NaN-free: v and lo are finite
}

void PolygonRegion::index_edges() {
  ring_start_.assign(1, 0);
  for (const Ring& r : rings_) ring_start_.push_back(ring_start_.back() + static_cast<std::uint32_t>(r.size()));
  const std::size_t n = ring_start_.back();
  // f(global edge number, lowest and highest coordinate b of its ends) for every edge of every ring.
  auto each_edge = [&](int b, auto&& f) {
    for (std::size_t k = 0; k < rings_.size(); ++k)
      for (std::size_t i = 0; i < rings_[k].size(); ++i) {
        const Ring& r = rings_[k];
        const auto [a, z] = std::minmax(r[i][b], r[(i + 1) % r.size()][b]);
        f(ring_start_[k] + static_cast<std::uint32_t>(i), a, z);
      }
  };
  for (int b = 0; b < 2; ++b) {
    Bands& bands = bands_[b];
    const double lo = min_[b], span = max_[b] - min_[b];
    // About four edges a band for a round outline; fewer bands while edges spanning many of them
    // (a comb of long teeth) would list more than 16 entries an edge.
    std::size_t count = std::clamp<std::size_t>(n / 4, 1, 4096);
    for (;;) {
      bands.lo = lo, bands.inv_width = span > 0.0 ? static_cast<double>(count) / span : 0.0;
      bands.start.assign(count + 1, 0);
      std::size_t entries = 0;
      each_edge(b, [&](std::uint32_t, double a, double z) { entries += bands.band(z) - bands.band(a) + 1; });
      if (entries <= 16 * n || count == 1) break;
      count /= 2;
    }
    // Two passes: the count of each band, then the edges in place.
    each_edge(b, [&](std::uint32_t, double a, double z) {
      for (std::size_t j = bands.band(a); j <= bands.band(z); ++j) ++bands.start[j + 1];
    });
    for (std::size_t j = 0; j < count; ++j) bands.start[j + 1] += bands.start[j];
    bands.edges.assign(bands.start.back(), 0);
    std::vector<std::uint32_t> fill(bands.start.begin(), bands.start.end() - 1);
    each_edge(b, [&](std::uint32_t e, double a, double z) {
      for (std::size_t j = bands.band(a); j <= bands.band(z); ++j) bands.edges[fill[j]++] = e;
    });
  }
}

bool PolygonRegion::contains(const Point2& p) const { return covers(chord(p, 0), p[0]); }

Intervals PolygonRegion::chord(const Point2& p, int axis) const {
  std::vector<double> xs;
  const int b = 1 - axis;
  const Bands& bands = bands_[b];
  if (bands.start.empty()) return {};  // a default-constructed region: empty
  const std::size_t j = bands.band(p[b]);
  for (std::uint32_t k = bands.start[j]; k < bands.start[j + 1]; ++k) {
    const std::uint32_t e = bands.edges[k];
    const std::size_t ring = static_cast<std::size_t>(
        std::upper_bound(ring_start_.begin(), ring_start_.end(), e) - ring_start_.begin() - 1);
    const Ring& r = rings_[ring];
    const std::size_t i = e - ring_start_[ring];
    crossing(r[i], r[(i + 1) % r.size()], p[b], axis, xs);
  }
  std::sort(xs.begin(), xs.end());
  Intervals v;
  for (std::size_t i = 0; i + 1 < xs.size(); i += 2) v.push_back({xs[i], xs[i + 1]});
  return normalized(std::move(v));
}

double PolygonRegion::area() const {
  double a = std::abs(signed_area2(rings_[0]));
  for (std::size_t k = 1; k < rings_.size(); ++k) a -= std::abs(signed_area2(rings_[k]));
  return 0.5 * a;
}

}  // namespace tsuchi::geometry
