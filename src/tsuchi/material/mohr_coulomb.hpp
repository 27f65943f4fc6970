#pragma once
// Mohr-Coulomb, elastic-perfectly plastic, with a tension cut-off: the FLAC formulation of
// METHOD.md section 5 (eqs 24-29). Tension positive; principal stresses s1 <= s2 <= s3 (s1 the
// most compressive). Non-associated flow through the dilatancy angle psi.
//
//   shear yield    f_s = s1 - s3 N_phi + 2 c sqrt(N_phi)  < 0      (24)
//   tension yield  f_t = sigma_t - s3                      < 0
//   which one      FLAC: h = s3 - sigma_t + a_P (s1 - sigma_P), shear if h <= 0;
//                  the paper: tension whenever s3 > sigma_t ("exceeds the tension strength")
//
// The return keeps the principal directions and corrects the principal values only.
//
// Plastic strain booked: the inelastic part of the step, C (sigma_trial - sigma), C the elastic
// compliance. For a shear return that is lambda g (eq 26); for a tension release it is the opening
// of the released directions. A release lowers principal values only, never raises one, so its
// volumetric part tr(sigma_trial - sigma) / 3K is >= 0: releasing tension cannot compact.
#include "tsuchi/core/principal.hpp"
#include "tsuchi/core/principal_frame.hpp"
#include "tsuchi/material/angle_scaling.hpp"
#include "tsuchi/material/strength_reduction.hpp"
#include "tsuchi/material/linear_elastic.hpp"
#include "tsuchi/material/mohr_coulomb_return.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>

namespace tsuchi {

enum class YieldMode : std::uint8_t { Elastic = 0, Shear = 1, Tension = 2 };

// How a point that fails in tension is returned.
enum class TensionRule : std::uint8_t {
  Flac,   // s3 = sigma_t, s1 and s2 follow elastically (FLAC's correction, associated flow)
  Paper,  // eq (28) per direction: every principal stress above sigma_t released to it, others kept
};

// Which points that exceed both the shear and the tension surface fail in tension. The paper's
// release goes with the paper's selection only: on FLAC's h = 0 the release and the shear return
// meet at different stresses (the input reader refuses that pairing).
enum class TensionSelection : std::uint8_t {
  Flac,   // FLAC's h-function (the bisector of the shear-tension corner)
  Paper,  // the paper's "particles that exceed the tension strength": s3 > sigma_t
};

// Per-point plastic history (output fields).
struct PlasticPoint {
  YieldMode mode = YieldMode::Elastic;
  double plastic_shear = 0.0;   // accumulated eps1_p - eps3_p of the plastic strain increments
  double plastic_volume = 0.0;  // accumulated plastic volumetric strain (dilation positive)
};

struct MohrCoulomb {
  static constexpr std::string_view name = "mohr_coulomb";
  // The state of a point (material/state_field.hpp), in this order.
  enum StateIndex : std::size_t { kMode, kPlasticShear, kPlasticVolume, kCohesionFactor, kFrictionFactor };
  static constexpr std::array<StateField, 5> state_fields{{
      {field_name::yield_mode, "", 0.0, true, "yielded", "surface the stress ended on in the last step: 0 elastic, 1 shear, 2 tension"},
      {field_name::plastic_shear_strain, "", 0.0, false, "", "accumulated eps1_p - eps3_p of the plastic strain increments"},
      {field_name::plastic_volumetric_strain, "", 0.0, false, "", "accumulated plastic volumetric strain, dilation positive"},
      {field_name::cohesion_factor, "", 1.0, false, "", "c of the point / c of the material: 1 + d of the imperfection"},
      {field_name::friction_factor, "", 1.0, false, "", "phi of the point / phi of the material: 1 + d of the imperfection"},
  }};

  LinearElastic elastic;
  double cohesion = 0.0;  // c (Pa)
  double phi = 0.0;       // friction angle (rad)
  double psi = 0.0;       // dilatancy angle (rad)
  double dilatancy_angle() const { return psi; }
  double tension = 0.0;   // sigma_t (Pa), at most c / tan(phi), eq (29)
  TensionRule tension_rule = TensionRule::Flac;
  TensionSelection tension_selection = TensionSelection::Flac;

  // Strength of one point; c and phi may carry the point's imperfection factors.
  struct Strength {
    double c, N_phi, sqrt_N_phi, N_psi, sigma_t;
  };

  // What the strength of every point of a material shares: computed once per material group, so
  // that a point's own friction angle phi (1 + d) costs no call to sin (see strength()), and a point
  // without an imperfection (both factors exactly 1, most points of most models) takes the
  // material's own strength, `plain`, instead of the ten divisions of strength(): the same bits,
  // as scaled_sin_cos gives sin_phi and cos_phi themselves at a factor of 1.
  struct Shared {
    double sin_phi, cos_phi, N_psi;
    Strength plain;
  };
  Shared shared() const {
    Shared m = angles();
    m.plain = scaled_strength(1.0, 1.0, m);
    return m;
  }
  // The angles alone, `plain` left empty: for a caller that makes a Shared per point and then
  // takes scaled_strength() (mohr_coulomb_softening.hpp), which would compute `plain` for nothing.
  Shared angles() const {
    const double ss = std::sin(psi);
    return {std::sin(phi), std::cos(phi), (1.0 + ss) / (1.0 - ss), {}};
  }

  // The `tsuchi fos` hook (material.hpp): c, phi, psi and sigma_t reduced by F (strength_reduction.hpp).
  MohrCoulomb reduced(double F, bool reduce_dilatancy) const {
    MohrCoulomb m = *this;
    const ReducedStrength r = reduce_strength(cohesion, phi, psi, tension, F, reduce_dilatancy);
    m.cohesion = r.cohesion, m.phi = r.phi, m.psi = r.psi, m.tension = r.tension;
    return m;
  }

  Strength strength(double c_scale = 1.0, double phi_scale = 1.0) const {
    return strength(c_scale, phi_scale, shared());
  }

  Strength strength(double c_scale, double phi_scale, const Shared& m) const {
    if (c_scale == 1.0 && phi_scale == 1.0) return m.plain;
    return scaled_strength(c_scale, phi_scale, m);
  }

  Strength scaled_strength(double c_scale, double phi_scale, const Shared& m) const {
    // sin and cos of the point's phi (1 + d) without a call to sin (angle_scaling.hpp).
    const SinCos a = scaled_sin_cos(phi, phi_scale, m.sin_phi, m.cos_phi);
    const double sp = a.sin, cp = a.cos;
    Strength s;
    s.c = cohesion * c_scale;
    s.N_phi = (1.0 + sp) / (1.0 - sp);
    s.sqrt_N_phi = std::sqrt(s.N_phi);
    s.N_psi = m.N_psi;
    // A scaled phi or c must not leave sigma_t above the apex c / tan(phi); compared without the
    // division, which the usual sigma_t = 0 never needs.
    s.sigma_t = tension * sp <= s.c * cp ? tension : s.c * cp / sp;
    return s;
  }

  static double shear_yield(const Eigen::Vector3d& p, const Strength& s) {
    return p[0] - p[2] * s.N_phi + 2.0 * s.c * s.sqrt_N_phi;
  }

  // Which surface a stress with principal values p (ascending) lies beyond by more than 1e-9 of
  // its scale, if any: the check that a starting stress is admissible.
  enum class Beyond { Nothing, Shear, Tension };
  static Beyond beyond(const Eigen::Vector3d& p, const Strength& s) {
    const double tol = 1e-9 * (std::max(p.cwiseAbs().maxCoeff(), s.c) + 1e-300);
    if (shear_yield(p, s) < -tol) return Beyond::Shear;
    if (p[2] - s.sigma_t > tol) return Beyond::Tension;
    return Beyond::Nothing;
  }

  // Whether a 3D stress is inside both surfaces by more than any principal-value computation's
  // round-off, decided from its invariants alone (no eigen-solver). With the mean stress m and the
  // deviator's J2, every principal deviator lies within +-(2/sqrt 3) sqrt J2 and the largest minus
  // the smallest is at most 2 sqrt J2, so with N_phi >= 1
  //   f_s = m (1 - N_phi) + (s_min - s_max) - (N_phi - 1) s_max + 2 c sqrt N_phi
  //       >= m (1 - N_phi) - 2 sqrt J2 - (N_phi - 1) (2/sqrt 3) sqrt J2 + 2 c sqrt N_phi,
  //   s3 <= m + (2/sqrt 3) sqrt J2.
  // Each bound is attained at some Lode angle (pure shear, triaxial extension) and both are exact
  // for an isotropic stress, so a point well inside passes. The margin (1e-12 of the terms' scale,
  // thousands of times the eigen-solver's round-off) makes "inside" here imply that the frame's
  // values say so too: the same bits, the frame skipped. In a confined 3D specimen most points are
  // inside most of the time, and the frame (Eigen's iterative eigen-solver) was a fifth of the step.
  static bool surely_elastic(const Voigt<3>& t, const Strength& s) {
    const double m = trace<3>(t) / 3.0;
    const Voigt<3> dev = deviator<3>(t);
    const double r = std::sqrt(0.5 * contract<3>(dev, dev));  // sqrt J2
    constexpr double k = 2.0 / std::numbers::sqrt3;
    const double N = s.N_phi, shear_room = 2.0 * s.c * s.sqrt_N_phi;
    const double tol = 1e-12 * (std::abs(m) * (1.0 + N) + r * (2.0 + k * N) + shear_room + std::abs(s.sigma_t));
    return N >= 1.0 && m * (1.0 - N) - 2.0 * r - (N - 1.0) * k * r + shear_room > tol &&
           s.sigma_t - (m + k * r) > tol;
  }

  // Plastic correction of a trial stress in place; returns the mode of this step.
  template <int D>
  YieldMode correct(Voigt<D>& sigma, const Strength& s, PlasticPoint& state) const {
    if constexpr (D == 2) {  // the frame is only for points that yield; the values are cheaper
      const Eigen::Vector3d v = principal_values(sigma);
      if (shear_yield(v, s) >= 0.0 && s.sigma_t - v[2] >= 0.0) return YieldMode::Elastic;
    } else {
      if (surely_elastic(sigma, s)) return YieldMode::Elastic;
    }
    const PrincipalFrame<D> frame(sigma);
    const Eigen::Vector3d& p = frame.values;
    if constexpr (D == 3)
      if (shear_yield(p, s) >= 0.0 && s.sigma_t - p[2] >= 0.0) return YieldMode::Elastic;
    const double a1 = elastic.K + 4.0 * elastic.G / 3.0, a2 = elastic.K - 2.0 * elastic.G / 3.0;
    bool shear;
    if (tension_selection == TensionSelection::Paper) {
      shear = !(p[2] > s.sigma_t);
    } else {  // FLAC's h-function; (sigma_P, sigma_t) is the corner of the shear and tension surfaces
      const double a_P = std::sqrt(1.0 + s.N_phi * s.N_phi) + s.N_phi;
      const double sigma_P = s.sigma_t * s.N_phi - 2.0 * s.c * s.sqrt_N_phi;
      shear = p[2] - s.sigma_t + a_P * (p[0] - sigma_P) <= 0.0;
    }
    const MohrCoulombReturn ret(s.N_phi, s.N_psi, 2.0 * s.c * s.sqrt_N_phi, s.sigma_t, a1, a2);
    PrincipalReturn r;
    if (!shear && tension_rule == TensionRule::Paper) {
      r = release(p, s, ret);
    } else if (!ret.solve(p, shear, r)) {
      r = vertex(p, s);
    }
    state.plastic_shear += r.plastic_strain.maxCoeff() - r.plastic_strain.minCoeff();
    state.plastic_volume += r.plastic_strain.sum();
    sigma = frame.rebuild(r.stress);
    return state.mode = (r.shear_active && (shear || !r.tension_active)) ? YieldMode::Shear : YieldMode::Tension;
  }

  // The paper's release (eq 28) applied per principal direction: the principal stresses above
  // sigma_t drop to it and the others are kept, so a point stretched one way and squeezed another
  // still resists the squeeze. Eq (28) itself resets the whole tensor to sigma_t; on a point still
  // compressed on average that erases the compression at every release and lets the soil compact
  // without limit. If the released stress is beyond the shear surface, the shear return follows
  // from there (an operator split, not one return mapping: the release's opening stays booked even
  // when the shear step then takes s3 below sigma_t). The mode reported is the surface the stress
  // ends on: tension while s3 = sigma_t, shear once the shear step has left the tension plane.
  PrincipalReturn release(const Eigen::Vector3d& p, const Strength& s, const MohrCoulombReturn& ret) const {
    PrincipalReturn r;
    r.stress = p.cwiseMin(s.sigma_t);  // keeps the ascending order
    r.plastic_strain = compliance(p - r.stress);
    r.tension_active = true;
    if (shear_yield(r.stress, s) < 0.0) {
      PrincipalReturn sh;
      if (!ret.solve(r.stress, true, sh)) return vertex(p, s);
      r.stress = sh.stress;
      r.plastic_strain += sh.plastic_strain;
      r.shear_active = sh.shear_active;
      r.tension_active = sh.tension_active;
    }
    return r;
  }

  // The tension vertex, admissible for any trial: the return of last resort (not seen in practice).
  PrincipalReturn vertex(const Eigen::Vector3d& p, const Strength& s) const {
    PrincipalReturn r;
    r.stress.setConstant(s.sigma_t);
    r.plastic_strain = compliance((p.array() - s.sigma_t).matrix());
    r.tension_active = true;
    return r;
  }

  // Principal strain of a principal stress difference: the inverse of Hooke's law.
  Eigen::Vector3d compliance(const Eigen::Vector3d& ds) const {
    const double mean = ds.mean();
    return (ds.array() - mean).matrix() / (2.0 * elastic.G) + Eigen::Vector3d::Constant(mean / (3.0 * elastic.K));
  }

  // Elastic trial (Hooke) then the plastic correction, for one point and one step.
  template <int D>
  YieldMode update(Voigt<D>& sigma, const Voigt<D>& d_eps, PlasticPoint& state, double c_scale = 1.0,
                   double phi_scale = 1.0) const {
    return update<D>(sigma, d_eps, state, c_scale, phi_scale, shared());
  }

  template <int D>
  YieldMode update(Voigt<D>& sigma, const Voigt<D>& d_eps, PlasticPoint& state, double c_scale, double phi_scale,
                   const Shared& m) const {
    elastic.update<D>(sigma, d_eps);
    state.mode = YieldMode::Elastic;
    return correct<D>(sigma, strength(c_scale, phi_scale, m), state);
  }

  // The constitutive model interface (material/material.hpp): one step of a point with state s;
  // the stress has been rotated (Jaumann, eq 22) by the caller. The context is what every point
  // of the material shares, computed once per step.
  using Context = Shared;
  Context context() const { return shared(); }
  template <int D>
  void update(Voigt<D>& sigma, const Voigt<D>& d_eps, const Mat<D>& /*d_omega*/, const Context& m, StateRef s) const {
    PlasticPoint point{YieldMode::Elastic, s[kPlasticShear], s[kPlasticVolume]};
    s[kMode] = static_cast<double>(update<D>(sigma, d_eps, point, s[kCohesionFactor], s[kFrictionFactor], m));
    s[kPlasticShear] = point.plastic_shear;
    s[kPlasticVolume] = point.plastic_volume;
  }
  // The moduli of a point: perfectly plastic, so always the elastic ones.
  const LinearElastic& stiffness(StateRef) const { return elastic; }
  // Whether the last update released the point in tension (a crack opened across it): the solver
  // then keeps its volume rather than let the opening inflate it (solver.hold_released_volume).
  bool released(StateRef s) const { return s[kMode] == static_cast<double>(YieldMode::Tension); }

  Inadmissible outside(const Eigen::Vector3d& principal, StateRef s) const {
    const Strength st = strength(s[kCohesionFactor], s[kFrictionFactor]);
    switch (beyond(principal, st)) {
      case Beyond::Nothing: return {};
      case Beyond::Shear: return {"Mohr-Coulomb shear", "Mohr-Coulomb", "beyond its shear strength"};
      case Beyond::Tension:
        return {"tension cut-off", "Mohr-Coulomb", fmt::format("beyond its tension strength {:g} Pa", st.sigma_t)};
    }
    return {};
  }

  // A K0 profile outside the surface: what k0 must satisfy (with c = 0).
  // With sigma_v > 0 in compression, sigma_h = k0 sigma_v is inside eq (24) while
  // |1 - k0| sigma_v <= 2 c cos(phi) + (1 + k0) sigma_v sin(phi).
  static constexpr std::string_view k0_hint =
      "a K0 state lies inside the surface while |1 - k0| sigma_v <= 2 c cos(phi) + (1 + k0) sigma_v sin(phi), "
      "sigma_v the vertical stress (compression positive): with c = 0 at any depth if 1/N_phi <= k0 <= N_phi, "
      "with c > 0 down to the depth where sigma_v reaches the bound; take k0 nearer 1 or a stronger material";

  // Why an imperfection of this amplitude cannot apply, or "".
  std::string imperfection_limit(double amplitude, bool /*cohesion*/, bool friction) const {
    return friction ? friction_scale_limit(phi, amplitude) : std::string{};
  }

  std::string describe() const {
    constexpr double deg = 180.0 / std::numbers::pi;
    return fmt::format(", c = {:.6g} Pa, phi = {:.6g} deg, psi = {:.6g} deg, tension strength {:.6g} Pa "
                       "({} rule, {} selection)",
                       cohesion, phi * deg, psi * deg, tension, tension_rule == TensionRule::Flac ? "flac" : "paper",
                       tension_selection == TensionSelection::Flac ? "flac" : "paper");
  }
};

}  // namespace tsuchi
