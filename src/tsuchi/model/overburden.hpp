#pragma once
// The weight of the material above a point, for the geostatic (K0) initial stress
// (model/initial_stress.hpp): along the vertical line through x,
//
//   sigma_v(x) = q(x) - |g| * integral_{z above x} rho(z) dz,
//
// where rho(z) is the density of whatever fills the point at height z: the body of highest
// priority whose shape holds it (model.cpp: overlaps of equal priority are refused), and within
// it the last of its regions holding it. Each shape answers where the line lies inside it
// (Shape::chord), so the integral is exact for any surface and layering: the sum over the pieces
// between consecutive chord ends of rho times the piece's length. Bodies read from files are not
// part of any column (they have no shape). q is the surcharge on top of the column.
//
// Only what is in the model when the point enters it is weighed (present_after, entry_stage): a
// fill that a later stage adds does not load the ground before it is placed, a body or a part an
// earlier stage removed does not load a fill placed after it, and a lift of a fill built in lifts
// weighs only itself and the lifts below.
#include "tsuchi/geometry/boolean.hpp"
#include "tsuchi/geometry/shape.hpp"
#include "tsuchi/model/config.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace tsuchi {

// The vertical stress on top of the column through x (Pa, tension positive): the surface_stress of
// the particle's body, the same on every column. A surcharge on part of the surface (a traction
// load on a footing's area) belongs here: add its vertical stress at the point where the column
// through x leaves the top of the material.
inline double column_surcharge(const Config& c, int body, const geometry::Point& /*x*/) {
  return c.bodies[static_cast<std::size_t>(body)].initial_stress.surface_stress;
}

// The part of each body in the model once stage k has made its removals and additions (k < 0: at
// the start): the body's shape; for a body built or cut by regions (StageRegionConfig), the
// boolean of its shape with them, (body n (added_1 u ...)) \ removed_1 \ ...; null where the body is
// absent. A body added whole after parts of it is whole again, less what regions have cut.
inline std::vector<geometry::ShapePtr> present_after(const Config& c, int k) {
  const std::size_t n = c.bodies.size();
  const auto dormant = [&](std::size_t b) { return b < c.body_starts_dormant.size() && c.body_starts_dormant[b]; };
  struct Part {
    bool whole = false, there = false;
    std::vector<geometry::ShapePtr> added, removed;
  };
  std::vector<Part> part(n);
  for (std::size_t b = 0; b < n; ++b) part[b].whole = part[b].there = !dormant(b);
  for (int j = 0; j <= k && j < static_cast<int>(c.stages.size()); ++j) {
    const StageConfig& st = c.stages[static_cast<std::size_t>(j)];
    for (const auto& r : st.remove_regions)
      for (std::size_t b = 0; b < n; ++b)
        if (part[b].there && (r.bodies.empty() || std::find(r.bodies.begin(), r.bodies.end(), static_cast<int>(b)) != r.bodies.end()))
          part[b].removed.push_back(r.shape);
    for (const int b : st.remove) part[static_cast<std::size_t>(b)] = Part{};
    for (const int b : st.add) part[static_cast<std::size_t>(b)].whole = part[static_cast<std::size_t>(b)].there = true;
    for (const auto& r : st.add_regions)
      for (const int b : r.bodies) {
        part[static_cast<std::size_t>(b)].there = true;
        part[static_cast<std::size_t>(b)].added.push_back(r.shape);
      }
  }
  std::vector<geometry::ShapePtr> shapes(n);
  for (std::size_t b = 0; b < n; ++b) {
    const Part& p = part[b];
    const geometry::ShapePtr& body = c.bodies[b].shape;
    if (!p.there || !body) continue;
    if (p.whole && p.removed.empty()) shapes[b] = body;
    else if (p.whole) shapes[b] = std::make_shared<geometry::Boolean>(body, std::vector<geometry::ShapePtr>{},
                                                                      std::vector<geometry::ShapePtr>{}, p.removed);
    else
      shapes[b] = std::make_shared<geometry::Boolean>(
          p.added.front(), std::vector<geometry::ShapePtr>(p.added.begin() + 1, p.added.end()),
          std::vector<geometry::ShapePtr>{body}, p.removed);
  }
  return shapes;
}

// The stage at whose start a particle of `body` at x enters the model: the first that adds the body
// whole or by a region holding x; -1 for a body there from the start (or a part no stage adds).
inline int entry_stage(const Config& c, int body, const geometry::Point& x) {
  const auto ub = static_cast<std::size_t>(body);
  if (ub >= c.body_starts_dormant.size() || !c.body_starts_dormant[ub]) return -1;
  for (std::size_t k = 0; k < c.stages.size(); ++k) {
    const StageConfig& st = c.stages[k];
    if (std::find(st.add.begin(), st.add.end(), body) != st.add.end()) return static_cast<int>(k);
    for (const auto& r : st.add_regions)
      if (std::find(r.bodies.begin(), r.bodies.end(), body) != r.bodies.end() && r.shape->contains(x))
        return static_cast<int>(k);
  }
  return -1;
}

class Overburden {
 public:
  // up_axis: the axis opposite gravity; up_sign +1 when up is its positive direction; weighs what
  // `present` holds of each body (present_after; null: the body is not weighed).
  Overburden(const Config& c, int up_axis, double up_sign, std::vector<geometry::ShapePtr> present)
      : c_(c), axis_(up_axis), sign_(up_sign), present_(std::move(present)) {}

  // The integral of rho over the material above x (kg/m^2; per unit area of the horizontal plane).
  double mass_above(const geometry::Point& x) const {
    // The chords in the coordinate s = sign * z, in which "above" is "larger".
    std::vector<geometry::Intervals> body(c_.bodies.size());
    std::vector<std::vector<geometry::Intervals>> region(c_.bodies.size());
    const double s0 = sign_ * x[axis_];
    std::vector<double> ends{s0};
    auto take = [&](geometry::Intervals in) {
      for (auto& i : in) {
        i = sign_ > 0 ? geometry::Interval{i.lo, i.hi} : geometry::Interval{-i.hi, -i.lo};
        for (const double e : {i.lo, i.hi})
          if (std::isfinite(e) && e > s0) ends.push_back(e);
      }
      return in;
    };
    for (std::size_t b = 0; b < c_.bodies.size(); ++b) {
      const BodyConfig& bc = c_.bodies[b];
      if (!present_[b]) continue;
      body[b] = take(present_[b]->chord(x, axis_));
      if (body[b].empty()) continue;
      for (const auto& r : bc.regions) region[b].push_back(take(r.shape->chord(x, axis_)));
    }
    std::sort(ends.begin(), ends.end());
    ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
    double sum = 0.0;
    for (std::size_t k = 0; k + 1 < ends.size(); ++k) {
      const double mid = 0.5 * (ends[k] + ends[k + 1]);
      const double rho = density_at(body, region, mid);
      if (rho > 0.0) sum += rho * (ends[k + 1] - ends[k]);
    }
    return sum;
  }

 private:
  static bool holds(const geometry::Intervals& in, double s) {
    for (const auto& i : in)
      if (s >= i.lo && s <= i.hi) return true;
    return false;
  }

  // The density at height s of the line (0 where no body is).
  double density_at(const std::vector<geometry::Intervals>& body,
                    const std::vector<std::vector<geometry::Intervals>>& region, double s) const {
    int winner = -1;
    for (std::size_t b = 0; b < body.size(); ++b)
      if (holds(body[b], s) && (winner < 0 || c_.bodies[b].priority > c_.bodies[static_cast<std::size_t>(winner)].priority))
        winner = static_cast<int>(b);
    if (winner < 0) return 0.0;
    const BodyConfig& bc = c_.bodies[static_cast<std::size_t>(winner)];
    int material = bc.material_index;
    for (std::size_t r = 0; r < bc.regions.size(); ++r)
      if (holds(region[static_cast<std::size_t>(winner)][r], s)) material = bc.regions[r].material_index;
    return c_.materials[static_cast<std::size_t>(material)].density;
  }

  const Config& c_;
  int axis_;
  double sign_;
  std::vector<geometry::ShapePtr> present_;
};

}  // namespace tsuchi
