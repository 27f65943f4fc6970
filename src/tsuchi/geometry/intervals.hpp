#pragma once
// Set operations on chords: sorted, disjoint lists of intervals (shape.hpp). The booleans of
// shapes (boolean.hpp) combine their operands' chords with these, so a chord of a slope or a
// tunnel stays exact. Each operation is one merge-like sweep, linear in the lengths.
#include "tsuchi/geometry/shape.hpp"

#include <algorithm>
#include <cstddef>

namespace tsuchi::geometry {

// Sorts by lo, merges intervals that overlap or touch, drops empty ones (lo >= hi): turns any
// list (crossings paired up, a union's concatenation) into a chord.
inline Intervals normalized(Intervals v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](const Interval& i) { return !(i.lo < i.hi); }), v.end());
  std::sort(v.begin(), v.end(), [](const Interval& a, const Interval& b) { return a.lo < b.lo; });
  Intervals r;
  for (const Interval& i : v) {
    if (!r.empty() && i.lo <= r.back().hi) r.back().hi = std::max(r.back().hi, i.hi);
    else r.push_back(i);
  }
  return r;
}

inline Intervals unite(const Intervals& a, const Intervals& b) {
  Intervals all(a);
  all.insert(all.end(), b.begin(), b.end());
  return normalized(std::move(all));
}

inline Intervals intersect(const Intervals& a, const Intervals& b) {
  Intervals r;
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const double lo = std::max(a[i].lo, b[j].lo), hi = std::min(a[i].hi, b[j].hi);
    if (lo < hi) r.push_back({lo, hi});
    // The interval that ends first cannot meet anything further along the other list.
    if (a[i].hi < b[j].hi) ++i;
    else ++j;
  }
  return r;
}

// a minus b. The pieces of a that are left keep the end points of b, so a tunnel's chord ends
// exactly on the tunnel's wall.
inline Intervals subtract(const Intervals& a, const Intervals& b) {
  Intervals r;
  std::size_t j = 0;
  for (const Interval& i : a) {
    double lo = i.lo;
    while (j < b.size() && b[j].hi <= lo) ++j;  // b's intervals wholly before what is left of i
    std::size_t k = j;
    for (; k < b.size() && b[k].lo < i.hi; ++k) {
      if (b[k].lo > lo) r.push_back({lo, b[k].lo});
      lo = std::max(lo, b[k].hi);
    }
    if (lo < i.hi) r.push_back({lo, i.hi});
    // b[k-1] may reach into the next interval of a: do not skip it.
    if (k > j) j = k - 1;
  }
  return r;
}

inline bool covers(const Intervals& v, double s) {
  for (const Interval& i : v)
    if (i.lo <= s && s <= i.hi) return true;
  return false;
}

}  // namespace tsuchi::geometry
