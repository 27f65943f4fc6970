#pragma once
// Modified Cam-Clay (Roscoe and Burland 1968) in the critical-state form of Borja and Lee (1990),
// docs/materials.md "Modified Cam-Clay". Inside the model p = -tr(sigma)/3 and volumetric strains
// are compression positive; q = sqrt(3 J2). The solver's stress is tension positive.
//
//   yield        f = q^2 / M^2 + p (p - p_c)                       ellipse through 0 and p_c
//   elasticity   K = v max(p, p_min) / kappa, integrated exactly over a step ("hypoelastic with
//                exact integration of the ln p law"); G constant or 3K(1 - 2nu) / (2(1 + nu))
//   hardening    p_c,n+1 = p_c,n exp(v d_eps_v^p / (lambda - kappa))
//   volume       v_n+1 = v_n exp(-d_eps_v)  (the total volumetric strain of the step)
//
// The moduli take v, and G its K, at the step's start: explicit in v and G, implicit in p, q, p_c
// (the return: modified_cam_clay_return.hpp). The deviatoric stress is scaled along its trial
// direction (associated flow on a surface of q alone), so the return is objective.
//
// No tensile strength: a trial with p <= 0 (an opening) goes to the origin, sigma = 0, keeping
// p_c; that opening is a separation of grains, booked as no plastic strain (yield mode 2, the
// solver's `released`). A step whose return does not converge is split into up to 64 substeps;
// if that fails too the point goes to the origin the same way: never a NaN.
#include "tsuchi/core/principal.hpp"
#include "tsuchi/material/linear_elastic.hpp"
#include "tsuchi/material/modified_cam_clay_return.hpp"
#include "tsuchi/material/state_field.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace tsuchi {

struct ModifiedCamClay {
  static constexpr std::string_view name = "modified_cam_clay";
  // Its moduli follow from kappa and the stress: the material reader reads no youngs_modulus.
  static constexpr bool reads_own_elasticity = true;

  enum StateIndex : std::size_t { kMode, kPlasticShear, kPlasticVolume, kPreconsolidation, kSpecificVolume, kBulkModulus };
  // p_c, v and K start at 0, meaning "not set yet": start() (or the first update) sets them from
  // the starting stress; a particle file may give p_c or v, which start() then keeps.
  static constexpr std::array<StateField, 6> state_fields{{
      {field_name::yield_mode, "", 0.0, true, "yielded", "surface the stress ended on in the last step: 0 elastic, 1 yielding, 2 released to zero stress"},
      {field_name::plastic_shear_strain, "", 0.0, false, "", "accumulated eps1_p - eps3_p of the plastic strain increments"},
      {field_name::plastic_volumetric_strain, "", 0.0, false, "", "accumulated plastic volumetric strain, dilation positive"},
      {"preconsolidation_pressure", "Pa", 0.0, false, "", "p_c, the size of the Cam-Clay ellipse (0 until the point starts)"},
      {"specific_volume", "", 0.0, false, "", "v = 1 + e of the soil (0 until the point starts)"},
      {"bulk_modulus", "Pa", 0.0, false, "", "tangent bulk modulus v max(p, p_min) / kappa after the last update: the time step's stiffness"},
  }};

  double lambda = 0.0;         // slope of the NCL in v - ln p
  double kappa = 0.0;          // slope of the unloading lines in v - ln p
  double M = 0.0;              // critical state slope q / p
  double v0 = 0.0;             // initial specific volume 1 + e0
  double pc0 = 0.0;            // given preconsolidation pressure (Pa), or 0 when ocr is given
  double ocr = 0.0;            // over-consolidation ratio p_c / p_y, or 0 when pc0 is given
  double poisson = 0.0;        // nu of the pressure-dependent shear modulus, when shear_modulus is 0
  double shear_modulus = 0.0;  // constant G (Pa), or 0 when poisson is given
  double p_min = 1e3;          // floor of the pressure in K (Pa)

  // Compression-positive p and q of a tension-positive tensor or principal values.
  template <int D>
  static double pressure_of(const Voigt<D>& s) {
    return 0.0 - trace<D>(s) / 3.0;
  }
  static double q_of(const Eigen::Vector3d& v) {
    return std::sqrt(0.5 * ((v[0] - v[1]) * (v[0] - v[1]) + (v[1] - v[2]) * (v[1] - v[2]) + (v[2] - v[0]) * (v[2] - v[0])));
  }

  double bulk(double v, double p) const { return v * std::max(p, p_min) / kappa; }
  double shear(double K) const {
    return shear_modulus > 0.0 ? shear_modulus : 3.0 * K * (1.0 - 2.0 * poisson) / (2.0 * (1.0 + poisson));
  }

  // p_c of a point starting at (p, q): the given one, or OCR times the isotropic pressure p_y of
  // the ellipse through (p, q), at least p_min (a point at zero stress still has an ellipse).
  double starting_pc(double p, double q) const {
    if (pc0 > 0.0) return pc0;
    const double p_y = p > 0.0 ? p + q * q / (M * M * p) : 0.0;
    return ocr * std::max(p_y, p_min);
  }

  // The optional hook (material/material.hpp): the state of a point from its starting stress.
  // A p_c or v already set (a particle file's column) is kept.
  void start(const Eigen::Vector3d& principal, StateRef s) const { start_pq(-principal.mean(), q_of(principal), s); }
  void start_pq(double p, double q, StateRef s) const {
    if (s[kPreconsolidation] == 0.0) s[kPreconsolidation] = starting_pc(p, q);
    if (s[kSpecificVolume] == 0.0) s[kSpecificVolume] = v0;
    s[kBulkModulus] = bulk(s[kSpecificVolume], p);
  }

  struct Context {};
  Context context() const { return {}; }

  template <int D>
  void update(Voigt<D>& sigma, const Voigt<D>& d_eps, const Mat<D>& /*d_omega*/, const Context&, StateRef s) const {
    if (s[kPreconsolidation] == 0.0 || s[kSpecificVolume] == 0.0)  // a point the start hook has not seen
      start_pq(pressure_of<D>(sigma), von_mises<D>(sigma), s);
    const double v = s[kSpecificVolume], pn = pressure_of<D>(sigma);
    const double Kn = bulk(v, pn);
    const CamClayReturn ret{M * M, v / kappa, v / (lambda - kappa), shear(Kn), p_min};
    const double d_eps_v = 0.0 - trace<D>(d_eps);  // compression positive
    const Voigt<D> de = deviator<D>(d_eps);
    // Substeps only when the whole step's return fails (not seen at ordinary step sizes).
    int mode = 0;
    bool done = false;
    for (int n = 1; n <= 64 && !done; n *= 2) {
      Voigt<D> sig = sigma;
      double pc = s[kPreconsolidation], shear_p = 0.0, vol_p = 0.0;
      done = true, mode = 0;
      for (int k = 0; k < n && done; ++k) {
        const int m = substep<D>(sig, d_eps_v / n, de / n, ret, pc, shear_p, vol_p);
        if (m < 0) done = false;
        mode = std::max(mode, m);
        if (m == 2) break;  // released: the rest of the step is more opening
      }
      if (done) {
        sigma = sig;
        s[kPreconsolidation] = pc;
        s[kPlasticShear] += shear_p;
        s[kPlasticVolume] += vol_p;
      }
    }
    if (!done) sigma.setZero(), mode = 2;  // the return of last resort: the origin, p_c kept
    s[kMode] = mode;
    s[kSpecificVolume] = v * std::exp(-d_eps_v);
    s[kBulkModulus] = bulk(s[kSpecificVolume], pressure_of<D>(sigma));
  }

  // One (sub)step from sig: 0 elastic, 1 returned onto the ellipse, 2 released to the origin, -1
  // the return did not converge (sig and the increments then unusable).
  template <int D>
  int substep(Voigt<D>& sig, double d_eps_v, const Voigt<D>& de, const CamClayReturn& ret, double& pc, double& shear_p,
              double& vol_p) const {
    const double pn = pressure_of<D>(sig);
    const Voigt<D> s_tr = deviator<D>(sig) + 2.0 * ret.G * de;
    const double q_tr = std::sqrt(1.5 * contract<D>(s_tr, s_tr));
    const double p_tr = ret.pressure(pn, d_eps_v);
    const auto set = [&](double p, const Voigt<D>& dev) {
      sig = dev;
      for (int i = 0; i < 3; ++i) sig[i] -= p;
    };
    if (!(p_tr > 0.0)) {  // no tensile strength
      sig.setZero();
      return 2;
    }
    if (CamClayReturn::yield(p_tr, q_tr, pc, ret.M2) <= 1e-14 * pc * pc) {
      set(p_tr, s_tr);
      return 0;
    }
    CamClayReturn::Result r;
    if (!ret.solve(pn, d_eps_v, q_tr, pc, r)) return -1;
    const Voigt<D> dev = q_tr > 0.0 ? Voigt<D>(s_tr * (r.q / q_tr)) : Voigt<D>::Zero();
    set(r.p, dev);
    pc = r.pc;
    // Plastic strain dg (df/dsigma): volumetric -x (dilation positive), deviatoric dg 3 s / M^2,
    // whose extreme principal values differ by dg 3 (s_max - s_min) / M^2.
    const Eigen::Vector3d sp = principal_values(dev);
    shear_p += r.dg * 3.0 * (sp[2] - sp[0]) / ret.M2;
    vol_p -= r.x;
    return 1;
  }

  // The current moduli: K of the last update (or of the minimum pressure before the point starts).
  LinearElastic stiffness(StateRef s) const {
    const double K = s[kBulkModulus] > 0.0 ? s[kBulkModulus] : bulk(v0, p_min);
    return {K, shear(K)};
  }
  bool released(StateRef s) const { return s[kMode] == 2.0; }

  Inadmissible outside(const Eigen::Vector3d& principal, StateRef s) const {
    const double p = -principal.mean(), q = q_of(principal);
    const double pc = s[kPreconsolidation] > 0.0 ? s[kPreconsolidation] : starting_pc(p, q);
    if (p < -1e-9 * pc || CamClayReturn::yield(p, q, pc, M * M) > 1e-9 * pc * pc)
      return {"Modified Cam-Clay", "Modified Cam-Clay", fmt::format("beyond its yield surface (p_c = {:.6g} Pa)", pc)};
    return {};
  }

  // A K0 profile outside the ellipse of a given p_c: an OCR sets p_c from each point's own stress.
  static constexpr std::string_view k0_hint =
      "a given preconsolidation_pressure must exceed p + q^2 / (M^2 p) at every depth; 'ocr' sets p_c per point";

  std::string describe() const {
    std::string r = fmt::format(", lambda = {:.6g}, kappa = {:.6g}, M = {:.6g}, v0 = {:.6g}, ", lambda, kappa, M, v0);
    r += pc0 > 0.0 ? fmt::format("p_c = {:.6g} Pa", pc0) : fmt::format("OCR = {:.6g}", ocr);
    r += shear_modulus > 0.0 ? fmt::format(", constant G = {:.6g} Pa", shear_modulus)
                             : fmt::format(", nu = {:.6g} (G from K)", poisson);
    return r + fmt::format(", K = v max(p, {:.6g} Pa) / kappa", p_min);
  }
};

}  // namespace tsuchi
