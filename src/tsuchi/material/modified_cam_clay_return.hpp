#pragma once
// Implicit closest-point return of Modified Cam-Clay in the p-q plane (Borja and Lee 1990;
// Borja 1991; de Souza Neto, Peric and Owen 2008, section 10.4), compression positive:
//
//   yield       f = q^2 / M^2 + p (p - p_c) = 0                      (ellipse through 0 and p_c)
//   flow        d_eps_v^p = dg (2p - p_c),  d_eps_s^p = dg 2q / M^2  (associated)
//   elasticity  dp = K d_eps_v^e, K = a max(p, p_min), a = v / kappa  (integrated exactly: P below)
//               q = q_tr - 3 G d_eps_s^p  =>  q = q_tr / (1 + 6 G dg / M^2)
//   hardening   p_c = p_c,n exp(b x), b = v / (lambda - kappa), x = d_eps_v^p
//
// v (so a and b) and G are those of the step's start: explicit in v and G, implicit in p, q, p_c.
// Two unknowns, x and dg, two residuals (the flow rule for x, and f = 0), solved by Newton's
// method with the exact Jacobian and a backtracking line search:
//
//   r1 = x - dg (2p - p_c)                    dr1/dx = 1 + dg (2K + b p_c)   dr1/ddg = -(2p - p_c)
//   r2 = f / p_c,n^2                          dr2/dx = (-(2p - p_c) K - p b p_c) / p_c,n^2
//                                             dr2/ddg = (2q / M^2) dq/ddg / p_c,n^2,
//                                             dq/ddg = -(6G / M^2) q^2 / q_tr
//
// with p = P(p_n, d_eps_v - x) and dp/dx = -K(p). Returns false when Newton does not converge
// (the caller then splits the step).
#include <algorithm>
#include <cmath>

namespace tsuchi {

struct CamClayReturn {
  double M2;     // M^2
  double a;      // v / kappa
  double b;      // v / (lambda - kappa)
  double G;      // shear modulus of the step (Pa)
  double p_min;  // the bulk modulus' floor pressure (Pa)

  // The pressure after an elastic volumetric strain e (compression positive) from p0: the exact
  // solution of dp/de = a max(p, p_min): p0 exp(a e) above p_min, linear below, joined at p_min.
  double pressure(double p0, double e) const {
    if (p0 >= p_min) {
      const double p = p0 * std::exp(a * e);
      if (p >= p_min) return p;
      const double e1 = std::log(p_min / p0) / a;  // the strain that reaches p_min (< 0)
      return p_min + a * p_min * (e - e1);
    }
    const double p = p0 + a * p_min * e;
    if (p <= p_min) return p;
    const double e1 = (p_min - p0) / (a * p_min);  // the strain that reaches p_min (> 0)
    return p_min * std::exp(a * (e - e1));
  }
  double modulus(double p) const { return a * std::max(p, p_min); }

  static double yield(double p, double q, double pc, double M2) { return q * q / M2 + p * (p - pc); }

  struct Result {
    double p, q, pc;  // the returned state
    double x;         // plastic volumetric strain increment, compression positive
    double dg;        // plastic multiplier
  };

  // Returns the trial (p_n, d_eps_v; q_tr) with p_c,n onto the ellipse. The trial must lie outside.
  bool solve(double p_n, double d_eps_v, double q_tr, double pc_n, Result& out) const {
    const double scale2 = pc_n * pc_n;
    double x = 0.0, dg = 0.0;
    const auto residual = [&](double xx, double gg, double r[2], Result& s) {
      s.x = xx, s.dg = gg;
      s.p = pressure(p_n, d_eps_v - xx);
      s.pc = pc_n * std::exp(b * xx);
      s.q = q_tr / (1.0 + 6.0 * G * gg / M2);
      r[0] = xx - gg * (2.0 * s.p - s.pc);
      r[1] = yield(s.p, s.q, s.pc, M2) / scale2;
    };
    // r1 is a strain: weighted by a p_n-scale modulus so that both residuals are stress ratios.
    const double w = modulus(p_n) / std::max(pc_n, p_min);
    const auto norm = [&](const double r[2]) { return std::hypot(w * r[0], r[1]); };
    double r[2];
    Result s;
    residual(x, dg, r, s);
    // Converged when f is at round-off of the current p_c^2 (which may be far from p_c,n^2 after
    // a large step) and r1 at round-off of its terms.
    const auto converged = [&](double tol) {
      return std::abs(r[1]) * scale2 <= tol * s.pc * s.pc &&
             std::abs(r[0]) <= tol * (std::abs(x) + dg * (2.0 * s.p + s.pc)) + 1e-300;
    };
    for (int it = 0; it < 60; ++it) {
      if (converged(1e-14)) break;
      const double K = modulus(s.p);
      const double J11 = 1.0 + dg * (2.0 * K + b * s.pc), J12 = -(2.0 * s.p - s.pc);
      const double dq = q_tr > 0.0 ? -(6.0 * G / M2) * s.q * s.q / q_tr : 0.0;
      const double J21 = (-(2.0 * s.p - s.pc) * K - s.p * b * s.pc) / scale2, J22 = (2.0 * s.q / M2) * dq / scale2;
      const double det = J11 * J22 - J12 * J21;
      if (!(std::abs(det) > 0.0) || !std::isfinite(det)) return false;
      const double step_x = -(r[0] * J22 - J12 * r[1]) / det, step_g = -(J11 * r[1] - r[0] * J21) / det;
      // Backtracking: the exponential laws make full steps overshoot far from the solution.
      const double n0 = norm(r);
      double alpha = 1.0, rt[2];
      Result st;
      bool moved = false;
      for (int ls = 0; ls < 40; ++ls, alpha *= 0.5) {
        const double xt = x + alpha * step_x, gt = std::max(dg + alpha * step_g, 0.0);
        residual(xt, gt, rt, st);
        if (std::isfinite(rt[0]) && std::isfinite(rt[1]) && norm(rt) < (1.0 - 1e-4 * alpha) * n0) {
          x = xt, dg = gt, r[0] = rt[0], r[1] = rt[1], s = st, moved = true;
          break;
        }
      }
      if (!moved) break;  // at round-off: judged below
    }
    if (!converged(1e-12) || dg < 0.0 || s.p < 0.0) return false;
    out = s;
    return true;
  }
};

}  // namespace tsuchi
