#pragma once
// Return of a trial stress to the Drucker-Prager cone with tension cut-off, in the plane of the two
// invariants of FLAC's formulation (Itasca, FLAC3D "Constitutive Models", Drucker-Prager model);
// tension positive, tau = sqrt(J2), sigma_m = tr(sigma) / 3.
//
//   shear yield     f_s = tau + q_phi sigma_m - k_phi  <= 0
//   tension yield   f_t = sigma_m - sigma_t            <= 0,   sigma_t <= k_phi / q_phi (the apex)
//   potentials      g_s = tau + q_psi sigma_m,  g_t = sigma_m (associated in tension)
//
// Hooke's law in these variables is d tau = G d gamma, d sigma_m = K d eps_v, so a plastic strain
// lambda_s dg_s/dsigma + lambda_t dg_t/dsigma moves the trial by (-K (q_psi lambda_s + lambda_t),
// -G lambda_s) and keeps the direction of the deviator. The surfaces meet at the corner
// (sigma_t, tau_P), tau_P = k_phi - q_phi sigma_t. Of three returns exactly one has lambda_s >= 0,
// lambda_t >= 0 and ends inside both surfaces, whatever q_psi >= 0, K and G:
//   shear    lambda_s = f_s / (G + K q_phi q_psi), lambda_t = 0. It ends at sigma_m <= sigma_t when
//            the trial is below the tension plane or on the shear side of the line through the
//            corner along the shear flow: K q_psi (tau - tau_P) >= G (sigma_m - sigma_t);
//   tension  sigma_m = sigma_t, tau kept, lambda_t = f_t / K: when tau <= tau_P;
//   corner   sigma_m = sigma_t, tau = tau_P between the two: lambda_s = (tau - tau_P) / G,
//            lambda_t = (sigma_m - sigma_t) / K - q_psi lambda_s, both >= 0 exactly there.
// FLAC chooses shear or tension by h = tau - tau_P - alpha_P (sigma_m - sigma_t),
// alpha_P = sqrt(1 + q_phi^2) - q_phi (shear where h > 0, the bisector of the corner's outer angle),
// and corrects on that surface alone. Wherever that correction ends inside the other surface it is
// the return below (the admissible return is unique). Elsewhere FLAC's stress would end beyond the
// other surface, or beyond the apex (tau < 0: a non-associated shear return overshooting the tip
// of the cone), and the return below goes to the corner: with sigma_t at the apex, the apex itself.
#include "tsuchi/material/mohr_coulomb.hpp"  // YieldMode

#include <algorithm>

namespace tsuchi {

// The cone of one point and its tension cut-off.
struct DruckerPragerStrength {
  double q_phi, k_phi, q_psi, sigma_t;

  double shear_yield(double sigma_m, double tau) const { return tau + q_phi * sigma_m - k_phi; }
};

struct InvariantReturn {
  double sigma_m = 0.0, tau = 0.0;      // the corrected invariants
  double lambda_s = 0.0, lambda_t = 0.0;  // multipliers of dg_s/dsigma and dg_t/dsigma
  YieldMode mode = YieldMode::Elastic;  // Shear, or Tension (also at the corner: sigma_m = sigma_t)
};

// The return of a trial (sigma_m, tau) beyond the shear or the tension surface; K, G the moduli.
inline InvariantReturn return_to_cone(double sigma_m, double tau, const DruckerPragerStrength& s, double K, double G) {
  InvariantReturn r;
  const double tau_P = s.k_phi - s.q_phi * s.sigma_t;  // >= 0: sigma_t is at most the apex
  const double over = sigma_m - s.sigma_t;             // f_t
  if (over <= 0.0 || K * s.q_psi * (tau - tau_P) >= G * over) {  // shear (the second test implies tau > tau_P)
    r.lambda_s = s.shear_yield(sigma_m, tau) / (G + K * s.q_phi * s.q_psi);
    r.sigma_m = std::min(sigma_m - K * s.q_psi * r.lambda_s, s.sigma_t);
    r.tau = std::max(s.k_phi - s.q_phi * r.sigma_m, 0.0);  // on the cone to rounding
    r.mode = YieldMode::Shear;
    return r;
  }
  r.sigma_m = s.sigma_t;
  r.mode = YieldMode::Tension;
  if (tau <= tau_P) {  // tension
    r.tau = tau;
    r.lambda_t = over / K;
  } else {  // the corner
    r.tau = tau_P;
    r.lambda_s = (tau - tau_P) / G;
    r.lambda_t = std::max(over / K - s.q_psi * r.lambda_s, 0.0);
  }
  return r;
}

}  // namespace tsuchi
