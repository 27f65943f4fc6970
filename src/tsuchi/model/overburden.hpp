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
// Only the bodies in the model when the point's body enters it are weighed (present_with): a
// fill that a later stage adds does not load the ground before it is placed, and a body an
// earlier stage removed does not load a fill placed after it.
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

// The bodies in the model when `body` enters it: those present from the start, or, for a body a
// stage adds, those present once that stage has made its removals and additions.
inline std::vector<bool> present_with(const Config& c, int body) {
  const std::size_t n = c.bodies.size();
  const auto dormant = [&](std::size_t b) { return b < c.body_starts_dormant.size() && c.body_starts_dormant[b]; };
  std::vector<bool> present(n);
  for (std::size_t b = 0; b < n; ++b) present[b] = !dormant(b);
  if (!dormant(static_cast<std::size_t>(body))) return present;
  for (const StageConfig& st : c.stages) {
    for (const int b : st.remove) present[static_cast<std::size_t>(b)] = false;
    for (const int b : st.add) present[static_cast<std::size_t>(b)] = true;
    if (std::find(st.add.begin(), st.add.end(), body) != st.add.end()) break;
  }
  return present;
}

class Overburden {
 public:
  // up_axis: the axis opposite gravity; up_sign +1 when up is its positive direction; weighs the
  // bodies `counts` marks.
  Overburden(const Config& c, int up_axis, double up_sign, std::vector<bool> counts)
      : c_(c), axis_(up_axis), sign_(up_sign), counts_(std::move(counts)) {}

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
      if (!bc.shape || !counts_[b]) continue;
      body[b] = take(bc.shape->chord(x, axis_));
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
  std::vector<bool> counts_;
};

}  // namespace tsuchi
