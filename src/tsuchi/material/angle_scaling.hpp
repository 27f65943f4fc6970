#pragma once
// sin and cos of a point's friction angle phi (1 + d), d the point's imperfection, from those of
// the material's phi: every point of a material shares sin(phi) and cos(phi), computed once per
// step, and a point's own angle then costs no call to sin or cos.
#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <string>
#include <string_view>

namespace tsuchi {

struct SinCos {
  double sin, cos;
};

// phi in radians, scale = 1 + d; sin_phi and cos_phi those of phi.
inline SinCos scaled_sin_cos(double phi, double scale, double sin_phi, double cos_phi) {
  // phi (1 + d) = phi + b with b = phi d: the angle-sum formulas with a few terms of the series of
  // sin b and cos b, exact to rounding for the small d of an imperfection.
  // No imperfection: sin_phi and cos_phi themselves, the bits the series below gives at b = 0,
  // without its seven divisions.
  if (scale == 1.0) return {sin_phi, cos_phi};
  const double b = phi * (scale - 1.0);
  if (std::abs(b) >= 0.03) return {std::sin(phi + b), std::cos(phi + b)};  // below, the first omitted terms are < 1e-19
  const double b2 = b * b;
  const double sin_b = b * (1.0 - b2 / 6.0 * (1.0 - b2 / 20.0 * (1.0 - b2 / 42.0)));
  const double cos_b = 1.0 - b2 / 2.0 * (1.0 - b2 / 12.0 * (1.0 - b2 / 30.0 * (1.0 - b2 / 56.0)));
  return {sin_phi * cos_b + cos_phi * sin_b, cos_phi * cos_b - sin_phi * sin_b};
}

// Why an imperfection of relative amplitude `amplitude` cannot scale the friction angle phi
// (radians; `what` names it in the message), or "": phi (1 + d) must stay below 90 degrees.
inline std::string friction_scale_limit(double phi, double amplitude, std::string_view what = "friction angle") {
  constexpr double deg = 180.0 / std::numbers::pi;
  if (phi * (1.0 + amplitude) * deg < 90.0) return {};
  return fmt::format("{} {} degrees times (1 + {}) reaches 90 degrees", what, phi * deg, amplitude);
}

}  // namespace tsuchi
