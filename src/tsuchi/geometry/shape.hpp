#pragma once
// A region of space that a body fills with particles (model/model.cpp) and through which the
// geostatic overburden is integrated (model/initial_stress.hpp). Set-up only: no shape is asked
// anything inside a time step, so a virtual call per query costs nothing that matters.
//
// Points have three coordinates in 2D as in 3D (z = 0 and ignored in 2D). A shape answers two
// questions: is a point inside, and where is a straight line along a grid axis inside (its
// "chord": the sorted, disjoint intervals of that coordinate). The second gives the overburden
// above a particle exactly, for any surface and any layering, without sampling.
#include <Eigen/Core>

#include <limits>
#include <memory>
#include <vector>

namespace tsuchi::geometry {

using Point = Eigen::Vector3d;

struct Interval {
  double lo, hi;
};
// Sorted by lo, disjoint, each with lo < hi.
using Intervals = std::vector<Interval>;

struct Bounds {
  Point min, max;  // may be infinite (a half-space)
};

inline constexpr double kUnbounded = std::numeric_limits<double>::infinity();

class Shape {
 public:
  virtual ~Shape() = default;
  // Whether x lies inside (on the boundary: either answer; particle centres of a lattice aligned
  // with a box never lie on its faces).
  virtual bool contains(const Point& x) const = 0;
  // The intervals of coordinate `axis` where the line {x + s e_axis} lies inside.
  virtual Intervals chord(const Point& x, int axis) const = 0;
  // An axis-aligned box holding the shape (infinite where it is unbounded).
  virtual Bounds bounds() const = 0;
  // The area (2D) or volume (3D) where a closed form is known; NaN otherwise.
  virtual double measure() const { return std::numeric_limits<double>::quiet_NaN(); }
  // How far the shape's coordinates may lie from the ones meant, m: the rounding of a file that
  // stores them in single precision (a binary STL file); 0 for shapes given in the input. Bounds
  // checks against the grid allow this much.
  virtual double precision() const { return 0.0; }
};

using ShapePtr = std::shared_ptr<const Shape>;

}  // namespace tsuchi::geometry
