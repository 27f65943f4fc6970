#pragma once
// sin and cos of a point's friction angle phi (1 + d), d the point's imperfection, from those of
// the material's phi: every point of a material shares sin(phi) and cos(phi), computed once per
// step, and a point's own angle then costs no call to sin or cos.
#include <cmath>

namespace tsuchi {

struct SinCos {
  double sin, cos;
};

// phi in radians, scale = 1 + d; sin_phi and cos_phi those of phi.
inline SinCos scaled_sin_cos(double phi, double scale, double sin_phi, double cos_phi) {
  // phi (1 + d) = phi + b with b = phi d: the angle-sum formulas with a few terms of the series of
  // sin b and cos b, exact to rounding for the small d of an imperfection.
  const double b = phi * (scale - 1.0);
  if (std::abs(b) >= 0.03) return {std::sin(phi + b), std::cos(phi + b)};  // below, the first omitted terms are < 1e-19
  const double b2 = b * b;
  const double sin_b = b * (1.0 - b2 / 6.0 * (1.0 - b2 / 20.0 * (1.0 - b2 / 42.0)));
  const double cos_b = 1.0 - b2 / 2.0 * (1.0 - b2 / 12.0 * (1.0 - b2 / 30.0 * (1.0 - b2 / 56.0)));
  return {sin_phi * cos_b + cos_phi * sin_b, cos_phi * cos_b - sin_phi * sin_b};
}

}  // namespace tsuchi
