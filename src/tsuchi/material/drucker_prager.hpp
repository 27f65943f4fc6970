#pragma once
// Drucker-Prager, elastic-perfectly plastic, with a tension cut-off: FLAC's formulation (Itasca,
// FLAC3D "Constitutive Models", Drucker-Prager model; docs/materials.md eqs DP1-DP8). Tension
// positive. A smooth cone in principal stress space, fitted to Mohr-Coulomb's c and phi by one of
// three matchings (the input's `match`), with non-associated flow through the dilatancy angle psi.
//
//   f_s = tau + q_phi sigma_m - k_phi <= 0,  f_t = sigma_m - sigma_t <= 0         (DP1, DP2)
//   tau = sqrt(J2), sigma_m = tr(sigma) / 3;  g_s = tau + q_psi sigma_m           (DP3)
//
//   match           q_phi                        k_phi                        q_psi
//   compression     6 sin phi / (sqrt3 (3 - sin phi))   6 c cos phi / (same)   phi -> psi    (DP4)
//   extension       6 sin phi / (sqrt3 (3 + sin phi))   6 c cos phi / (same)   phi -> psi    (DP5)
//   plane_strain    sin phi / beta               c cos phi / beta         sqrt3 sin psi / sqrt(3 + sin^2 psi)  (DP6)
//                   beta = sqrt(1 - q_psi^2 / 3) + q_psi sin phi / 3
//
// Compression: the cone through Mohr-Coulomb's triaxial-compression corners (the outer cone);
// extension: through its extension corners (the inner cone); plane strain: the cone whose limit
// load under plane strain is Mohr-Coulomb's (with the flow of g_s, eps_zz = 0 at plastic flow
// gives s_zz = -(2/3) q_psi tau, so R + s_c sin phi = c cos phi in the plane for any psi; q_psi
// gives Mohr-Coulomb's plane-strain dilation rate sin psi). Every matching has its apex at
// k_phi / q_phi = c / tan phi, Mohr-Coulomb's.
//
// The return (drucker_prager_return.hpp) scales the deviator and shifts the mean stress, so it
// keeps the principal directions and needs no eigen-decomposition. Plastic strain booked: the
// flow lambda_s dg_s/dsigma + lambda_t dg_t/dsigma, which is C (sigma_trial - sigma).
#include "tsuchi/core/tensor.hpp"
#include "tsuchi/material/angle_scaling.hpp"
#include "tsuchi/material/strength_reduction.hpp"
#include "tsuchi/material/drucker_prager_return.hpp"
#include "tsuchi/material/linear_elastic.hpp"
#include "tsuchi/material/mohr_coulomb.hpp"  // YieldMode, PlasticPoint
#include "tsuchi/material/state_field.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>

namespace tsuchi {

// Which Mohr-Coulomb strength the cone reproduces exactly.
enum class ConeMatch : std::uint8_t { Compression, Extension, PlaneStrain };
inline constexpr std::array<const char*, 3> cone_match_names{"compression", "extension", "plane_strain"};

struct DruckerPrager {
  static constexpr std::string_view name = "drucker_prager";
  // The state of a point: Mohr-Coulomb's fields, with the same meaning and order (so an
  // imperfection scales c and phi of a point, and the element CSV shows the plastic strains).
  static constexpr std::size_t kMode = MohrCoulomb::kMode, kPlasticShear = MohrCoulomb::kPlasticShear,
                               kPlasticVolume = MohrCoulomb::kPlasticVolume,
                               kCohesionFactor = MohrCoulomb::kCohesionFactor,
                               kFrictionFactor = MohrCoulomb::kFrictionFactor;
  static constexpr auto state_fields = MohrCoulomb::state_fields;

  LinearElastic elastic;
  double cohesion = 0.0;  // c (Pa)
  double phi = 0.0;       // friction angle (rad)
  double psi = 0.0;       // dilatancy angle (rad)
  double dilatancy_angle() const { return psi; }
  double tension = 0.0;   // sigma_t (Pa), at most the apex c / tan(phi)
  ConeMatch match = ConeMatch::Compression;

  // What every point of a material shares. Each matching is q_phi = sin phi / D and
  // k_phi = c cos phi / D with D = d0 + d1 sin phi (DP4-DP6), so a point's own phi (1 + d) costs
  // one division (angle_scaling.hpp for its sine and cosine).
  // A point without an imperfection takes the material's own strength, `plain` (the same bits).
  struct Shared {
    double sin_phi, cos_phi, d0, d1, q_psi;
    DruckerPragerStrength plain;
  };
  Shared shared() const {
    Shared m = cone();
    m.plain = scaled_strength(1.0, 1.0, m);
    return m;
  }

  DruckerPragerStrength strength(double c_scale, double phi_scale, const Shared& m) const {
    if (c_scale == 1.0 && phi_scale == 1.0) return m.plain;
    return scaled_strength(c_scale, phi_scale, m);
  }

 private:
  Shared cone() const {
    constexpr double r3 = std::numbers::sqrt3;
    const double sp = std::sin(psi);
    switch (match) {
      case ConeMatch::Compression: return {std::sin(phi), std::cos(phi), r3 / 2.0, -r3 / 6.0, 6.0 * sp / (r3 * (3.0 - sp)), {}};
      case ConeMatch::Extension: return {std::sin(phi), std::cos(phi), r3 / 2.0, r3 / 6.0, 6.0 * sp / (r3 * (3.0 + sp)), {}};
      case ConeMatch::PlaneStrain: break;
    }
    const double q_psi = r3 * sp / std::sqrt(3.0 + sp * sp);
    return {std::sin(phi), std::cos(phi), std::sqrt(1.0 - q_psi * q_psi / 3.0), q_psi / 3.0, q_psi, {}};
  }

  DruckerPragerStrength scaled_strength(double c_scale, double phi_scale, const Shared& m) const {
    const SinCos a = scaled_sin_cos(phi, phi_scale, m.sin_phi, m.cos_phi);
    const double c = cohesion * c_scale, D = m.d0 + m.d1 * a.sin;
    DruckerPragerStrength s;
    s.q_phi = a.sin / D;
    s.k_phi = c * a.cos / D;
    s.q_psi = m.q_psi;
    // The apex k_phi / q_phi = c / tan(phi) of the point caps sigma_t (compared without a division).
    s.sigma_t = tension * a.sin <= c * a.cos ? tension : c * a.cos / a.sin;
    return s;
  }

 public:
  // The `tsuchi fos` hook (material.hpp): c, phi, psi and the tension reduced by F (strength_reduction.hpp),
  // the cone then matched to the reduced Mohr-Coulomb parameters as the input's `match` says.
  DruckerPrager reduced(double F, bool reduce_dilatancy) const {
    DruckerPrager m = *this;
    const ReducedStrength r = reduce_strength(cohesion, phi, psi, tension, F, reduce_dilatancy);
    m.cohesion = r.cohesion, m.phi = r.phi, m.psi = r.psi, m.tension = r.tension;
    return m;
  }

  DruckerPragerStrength strength(double c_scale = 1.0, double phi_scale = 1.0) const {
    return strength(c_scale, phi_scale, shared());
  }

  // (s_max - s_min) / (2 tau) of a deviator s, from its Lode angle: the principal spread of the
  // flow dtau/dsigma = s / (2 tau), which turns lambda_s into eps1_p - eps3_p. In [sqrt3/2, 1].
  template <int D>
  static double principal_spread(const Voigt<D>& s, double tau) {
    double J3;
    if constexpr (D == 2) J3 = s[2] * (s[0] * s[1] - s[3] * s[3]);
    else J3 = s[0] * (s[1] * s[2] - s[4] * s[4]) - s[3] * (s[3] * s[2] - s[4] * s[5]) + s[5] * (s[3] * s[4] - s[1] * s[5]);
    const double cos3 = std::clamp(1.5 * std::numbers::sqrt3 * J3 / (tau * tau * tau), -1.0, 1.0);
    return std::sin(std::acos(cos3) / 3.0 + std::numbers::pi / 3.0);
  }

  // Plastic correction of a trial stress in place; returns the mode of this step.
  template <int D>
  YieldMode correct(Voigt<D>& sigma, const DruckerPragerStrength& s, PlasticPoint& state) const {
    const double sigma_m = trace<D>(sigma) / 3.0;
    const Voigt<D> dev = deviator<D>(sigma);
    const double tau = std::sqrt(0.5 * contract<D>(dev, dev));
    if (s.shear_yield(sigma_m, tau) <= 0.0 && sigma_m <= s.sigma_t) return YieldMode::Elastic;
    const InvariantReturn r = return_to_cone(sigma_m, tau, s, elastic.K, elastic.G);
    if (r.lambda_s > 0.0) state.plastic_shear += r.lambda_s * principal_spread<D>(dev, tau);
    state.plastic_volume += s.q_psi * r.lambda_s + r.lambda_t;
    sigma = tau > 0.0 ? Voigt<D>(dev * (r.tau / tau)) : Voigt<D>(dev);
    for (int i = 0; i < 3; ++i) sigma[i] += r.sigma_m;
    return state.mode = r.mode;
  }

  // Elastic trial (Hooke) then the plastic correction, for one point and one step.
  template <int D>
  YieldMode update(Voigt<D>& sigma, const Voigt<D>& d_eps, PlasticPoint& state, double c_scale, double phi_scale,
                   const Shared& m) const {
    elastic.update<D>(sigma, d_eps);
    state.mode = YieldMode::Elastic;
    return correct<D>(sigma, strength(c_scale, phi_scale, m), state);
  }
  template <int D>
  YieldMode update(Voigt<D>& sigma, const Voigt<D>& d_eps, PlasticPoint& state) const {
    return update<D>(sigma, d_eps, state, 1.0, 1.0, shared());
  }

  // The constitutive model interface (material/material.hpp).
  using Context = Shared;
  Context context() const { return shared(); }
  template <int D>
  void update(Voigt<D>& sigma, const Voigt<D>& d_eps, const Mat<D>& /*d_omega*/, const Context& m, StateRef s) const {
    PlasticPoint point{YieldMode::Elastic, s[kPlasticShear], s[kPlasticVolume]};
    s[kMode] = static_cast<double>(update<D>(sigma, d_eps, point, s[kCohesionFactor], s[kFrictionFactor], m));
    s[kPlasticShear] = point.plastic_shear;
    s[kPlasticVolume] = point.plastic_volume;
  }
  // Perfectly plastic: always the elastic moduli.
  const LinearElastic& stiffness(StateRef) const { return elastic; }
  // Ended on the tension cut-off (alone or at its corner with the cone): opened, as Mohr-Coulomb's
  // released points (solver.hold_released_volume).
  bool released(StateRef s) const { return s[kMode] == static_cast<double>(YieldMode::Tension); }

  // A starting stress beyond the cone or the cut-off by more than 1e-9 of its scale.
  Inadmissible outside(const Eigen::Vector3d& p, StateRef st) const {
    const DruckerPragerStrength s = strength(st[kCohesionFactor], st[kFrictionFactor]);
    const double sigma_m = p.mean();
    const Eigen::Vector3d d = p.array() - sigma_m;
    const double tau = std::sqrt(0.5 * d.squaredNorm());
    const double tol = 1e-9 * (std::max(p.cwiseAbs().maxCoeff(), cohesion) + 1e-300);
    if (s.shear_yield(sigma_m, tau) > tol) return {"Drucker-Prager shear", "Drucker-Prager", "beyond its shear strength"};
    if (sigma_m - s.sigma_t > tol)
      return {"tension cut-off", "Drucker-Prager", fmt::format("beyond its tension strength {:g} Pa", s.sigma_t)};
    return {};
  }

  // A K0 profile outside the cone: what k0 must satisfy (with c = 0), from DP1 with
  // tau = |1 - k0| sigma_v / sqrt3 and sigma_m = -(1 + 2 k0) sigma_v / 3.
  static constexpr std::string_view k0_hint =
      "with c = 0 a K0 state needs sqrt(3) |1 - k0| <= q_phi (1 + 2 k0) (q_phi in the material's summary)";

  // Why an imperfection of this amplitude cannot apply, or "".
  std::string imperfection_limit(double amplitude, bool /*cohesion*/, bool friction) const {
    return friction ? friction_scale_limit(phi, amplitude) : std::string{};
  }

  std::string describe() const {
    constexpr double deg = 180.0 / std::numbers::pi;
    const DruckerPragerStrength s = strength();
    return fmt::format(", c = {:.6g} Pa, phi = {:.6g} deg, psi = {:.6g} deg, tension strength {:.6g} Pa, "
                       "{} match: q_phi = {:.6g}, k_phi = {:.6g} Pa, q_psi = {:.6g}",
                       cohesion, phi * deg, psi * deg, s.sigma_t, cone_match_names[static_cast<std::size_t>(match)],
                       s.q_phi, s.k_phi, s.q_psi);
  }
};

}  // namespace tsuchi
