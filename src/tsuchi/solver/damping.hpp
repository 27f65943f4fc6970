#pragma once
// Cundall's (1987) local non-viscous damping, eqs (20)-(21) with METHOD.md's fix: the force opposes
// the nodal velocity and is proportional to the magnitude of the unbalanced force, so it always
// dissipates and vanishes at equilibrium (no viscosity to tune against a frequency).
#include <cmath>

namespace tsuchi {

inline double local_damping_force(double f_drive, double v, double alpha) {
  const double sign_v = (v > 0.0) - (v < 0.0);
  return -alpha * std::abs(f_drive) * sign_v;
}

}  // namespace tsuchi
