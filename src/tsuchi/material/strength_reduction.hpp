#pragma once
// Strength reduction for the factor of safety (`tsuchi fos`, run/factor_of_safety.hpp): the
// strength the soil would need to have for the slope to be at the limit, divided by F (Dawson, Roth
// and Drescher 1999; Griffiths and Lane 1999, eqs 2-3):
//   c_F = c / F,   tan(phi_F) = tan(phi) / F,
// and the dilatancy angle either reduced the same way, tan(psi_F) = tan(psi) / F (fos.reduce_dilatancy),
// or kept, but no larger than phi_F: a flow rule dilating faster than the reduced friction angle
// allows would add strength (Dawson et al. 1999). The tension strength goes with c (c_F / c) and
// stays below the reduced apex c_F / tan(phi_F).
#include <algorithm>
#include <cmath>

namespace tsuchi {

struct ReducedStrength {
  double cohesion, phi, psi, tension;
};

inline double reduced_angle(double angle, double F) { return std::atan(std::tan(angle) / F); }

inline ReducedStrength reduce_strength(double cohesion, double phi, double psi, double tension, double F,
                                       bool reduce_dilatancy) {
  ReducedStrength r;
  r.cohesion = cohesion / F;
  r.phi = reduced_angle(phi, F);
  r.psi = reduce_dilatancy ? reduced_angle(psi, F) : std::min(psi, r.phi);
  r.tension = tension / F;
  if (r.phi > 0.0) r.tension = std::min(r.tension, r.cohesion / std::tan(r.phi));
  return r;
}

}  // namespace tsuchi
