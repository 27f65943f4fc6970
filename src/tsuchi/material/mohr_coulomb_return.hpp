#pragma once
// Return of a trial stress to the Mohr-Coulomb surface with tension cut-off, in principal space
// (tension positive, trial values ascending s1 <= s2 <= s3).
//
// FLAC's single-plane corrections (METHOD.md eqs 26-27 and the tension rule) are right only while
// the corrected values keep their order and the other planes stay satisfied. Near an edge of the
// pyramid (s1 = s2 or s2 = s3) or the shear-tension corner, and with non-associated flow, they
// land outside. So the return is posed as an active set over six planes F = n . s - r <= 0:
//
//   a: N_phi s3 - s1 <= k     b: N_phi s2 - s1 <= k     c: N_phi s3 - s2 <= k      (k = 2c sqrt(N_phi))
//   T3: s3 <= sigma_t         T2: s2 <= sigma_t         T1: s1 <= sigma_t
//
// with plastic flows g (N_psi in place of N_phi, and e_i for tension). For an active set A the
// corrected stress is s = trial - sum_A lambda_m E g_m, with n_l . s = r_l on A; a set is accepted
// when every lambda >= 0 and the result satisfies all planes. Candidate sets are tried in FLAC's
// order (the h-function picks shear or tension first, single planes before edges and corners), so
// the result is FLAC's wherever FLAC's is admissible (Clausen, Damkilde & Andersen 2006 treat
// these multi-plane returns in the associated case).
#include "tsuchi/core/tensor.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

namespace tsuchi {

struct PrincipalReturn {
  Eigen::Vector3d stress;          // corrected principal values (same slots as the trial)
  Eigen::Vector3d plastic_strain;  // principal plastic strain increment, sum lambda g
  bool shear_active = false;
  bool tension_active = false;
};

class MohrCoulombReturn {
 public:
  // N_phi, N_psi, k = 2c sqrt(N_phi), sigma_t; a1 = K + 4G/3, a2 = K - 2G/3.
  MohrCoulombReturn(double N_phi, double N_psi, double k, double sigma_t, double a1, double a2)
      : N_phi_(N_phi), N_psi_(N_psi), k_(k), sigma_t_(sigma_t), a1_(a1), a2_(a2) {}

  // Returns false only if no candidate set is admissible (not seen in practice); the caller then
  // falls back to the isotropic tension vertex, which is always admissible.
  bool solve(const Eigen::Vector3d& trial, bool shear_first, PrincipalReturn& out) const {
    const double scale = std::max(trial.cwiseAbs().maxCoeff(), std::abs(k_)) + 1e-300;
    // FLAC's own single-plane correction settles most yielding points: it is tried before the
    // other five planes are set up.
    const std::uint8_t first = shear_first ? A : T3;
    const Plane one = plane(std::countr_zero(first));
    const Plane* single[1] = {&one};
    if (try_set(first, single, 1, trial, scale, out)) return true;
    const std::array<Plane, 6> all = {plane(0), plane(1), plane(2), plane(3), plane(4), plane(5)};
    const auto try_from_all = [&](std::uint8_t set) {
      const Plane* act[3];
      int m = 0;
      for (int i = 0; i < 6; ++i)
        if (set & (1u << i)) act[m++] = &all[static_cast<std::size_t>(i)];
      return try_set(set, act, m, trial, scale, out);
    };
    for (std::uint8_t set : shear_first ? kShearFirst : kTensionFirst)
      if (set != first && try_from_all(set)) return true;
    for (std::uint8_t set = 1; set < 64; ++set)  // every other set of one to three planes
      if (std::popcount(set) <= 3 && try_from_all(set)) return true;  // rare: popcount's cost is no matter
    return false;
  }

  // Largest violation over all planes, in any order of the values: the test of admissibility.
  double violation(const Eigen::Vector3d& s) const {
    return std::max(N_phi_ * s.maxCoeff() - s.minCoeff() - k_, s.maxCoeff() - sigma_t_);
  }

 private:
  struct Plane {
    Eigen::Vector3d n, g, Eg;
    double r = 0.0;
    int tension_axis = -1;  // the principal value a tension plane holds at sigma_t
  };
  enum : std::uint8_t { A = 1, B = 2, C = 4, T3 = 8, T2 = 16, T1 = 32 };
  static constexpr std::array<std::uint8_t, 12> kShearFirst = {
      A, A | B, A | C, A | T3, A | C | T3, A | B | T3, A | T2 | T3, B | T2 | T3, T3, T3 | T2, T3 | T2 | T1, B};
  static constexpr std::array<std::uint8_t, 12> kTensionFirst = {
      T3, T3 | T2, T3 | T2 | T1, A | T3, A | C | T3, A | B | T3, A | T2 | T3, B | T2 | T3, A, A | B, A | C, B};

  // Plane `bit` of the list above (a, b, c, T3, T2, T1). E = a2 1 1^T + (a1 - a2) I, so E g needs
  // no matrix product.
  Plane plane(int bit) const {
    Plane p;
    p.n.setZero(), p.g.setZero();
    if (bit < 3) {  // N s_i - s_j <= k
      const int i = bit == 1 ? 1 : 2, j = bit == 2 ? 1 : 0;
      p.n[i] = N_phi_, p.n[j] = -1.0;
      p.g[i] = N_psi_, p.g[j] = -1.0;
      p.r = k_;
    } else {
      p.tension_axis = 5 - bit;
      p.n[p.tension_axis] = p.g[p.tension_axis] = 1.0;
      p.r = sigma_t_;
    }
    p.Eg = Eigen::Vector3d::Constant(a2_ * p.g.sum()) + (a1_ - a2_) * p.g;
    return p;
  }

  // Solves the leading m x m block of M lambda = rhs (m <= 3) by Cramer's rule; false when the
  // block is singular to 1e-10 of its largest entry, i.e. the planes of the set are dependent.
  // A 3 x 3 system does not need a pivoting factorisation, and this runs for every yielding point.
  static bool solve_small(int m, const Mat3& M, const Eigen::Vector3d& rhs, Eigen::Vector3d& lambda) {
    double big = 0.0;
    for (int l = 0; l < m; ++l)
      for (int q = 0; q < m; ++q) big = std::max(big, std::abs(M(l, q)));
    if (m == 1) {
      if (!(std::abs(M(0, 0)) > 0.0)) return false;
      lambda[0] = rhs[0] / M(0, 0);
      return true;
    }
    if (m == 2) {
      const double det = M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0);
      if (!(std::abs(det) > 1e-10 * big * big)) return false;
      lambda[0] = (rhs[0] * M(1, 1) - M(0, 1) * rhs[1]) / det;
      lambda[1] = (M(0, 0) * rhs[1] - rhs[0] * M(1, 0)) / det;
      return true;
    }
    // Each lambda is the determinant with its column replaced by rhs.
    const auto det3 = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
      return a[0] * (b[1] * c[2] - b[2] * c[1]) - b[0] * (a[1] * c[2] - a[2] * c[1]) +
             c[0] * (a[1] * b[2] - a[2] * b[1]);
    };
    const Eigen::Vector3d c0 = M.col(0), c1 = M.col(1), c2 = M.col(2);
    const double det = det3(c0, c1, c2);
    if (!(std::abs(det) > 1e-10 * big * big * big)) return false;
    lambda[0] = det3(rhs, c1, c2) / det;
    lambda[1] = det3(c0, rhs, c2) / det;
    lambda[2] = det3(c0, c1, rhs) / det;
    return true;
  }

  // The active set `set` with its m planes in act[0 .. m).
  bool try_set(std::uint8_t set, const Plane* const* act, int m, const Eigen::Vector3d& trial, double scale,
               PrincipalReturn& out) const {
    Mat3 M;
    Eigen::Vector3d rhs, lambda;
    for (int l = 0; l < m; ++l) {
      rhs[l] = act[l]->n.dot(trial) - act[l]->r;
      for (int q = 0; q < m; ++q) M(l, q) = act[l]->n.dot(act[q]->Eg);
    }
    if (!solve_small(m, M, rhs, lambda)) return false;  // dependent planes: a smaller set covers it
    Eigen::Vector3d s = trial, dep = Eigen::Vector3d::Zero();
    for (int q = 0; q < m; ++q) {
      if (lambda[q] < -1e-12 * scale / a1_) return false;
      s -= lambda[q] * act[q]->Eg;
      dep += lambda[q] * act[q]->g;
    }
    // The tension planes are axis-aligned: land on them exactly, not within rounding.
    for (int q = 0; q < m; ++q)
      if (act[q]->tension_axis >= 0) s[act[q]->tension_axis] = act[q]->r;
    if (violation(s) > 1e-12 * scale) return false;
    out.stress = s;
    out.plastic_strain = dep;
    out.shear_active = (set & (A | B | C)) != 0;
    out.tension_active = (set & (T1 | T2 | T3)) != 0;
    return true;
  }

  double N_phi_, N_psi_, k_, sigma_t_, a1_, a2_;
};

}  // namespace tsuchi
