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

#include <Eigen/LU>

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
  MohrCoulombReturn(double N_phi, double N_psi, double k, double sigma_t, double a1, double a2) {
    E_ << a1, a2, a2, a2, a1, a2, a2, a2, a1;
    const auto shear = [&](int i, int j) {  // N s_i - s_j <= k
      Plane p;
      p.n.setZero(), p.g.setZero(), p.Eg.setZero();
      p.n[i] = N_phi, p.n[j] = -1.0;
      p.g[i] = N_psi, p.g[j] = -1.0;
      p.r = k;
      return p;
    };
    const auto tension = [&](int i) {
      Plane p;
      p.n = p.g = Eigen::Vector3d::Unit(i);
      p.Eg.setZero();
      p.r = sigma_t;
      return p;
    };
    planes_ = {shear(2, 0), shear(1, 0), shear(2, 1), tension(2), tension(1), tension(0)};
    for (auto& p : planes_) p.Eg = E_ * p.g;
  }

  // Returns false only if no candidate set is admissible (not seen in practice); the caller then
  // falls back to the isotropic tension vertex, which is always admissible.
  bool solve(const Eigen::Vector3d& trial, bool shear_first, PrincipalReturn& out) const {
    const double scale = std::max(trial.cwiseAbs().maxCoeff(), std::abs(planes_[0].r)) + 1e-300;
    for (std::uint8_t set : shear_first ? kShearFirst : kTensionFirst)
      if (try_set(set, trial, scale, out)) return true;
    for (std::uint8_t set = 1; set < 64; ++set)  // every other set of one to three planes
      if (std::popcount(set) <= 3 && try_set(set, trial, scale, out)) return true;
    return false;
  }

  // Largest violation over all planes, in any order of the values: the test of admissibility.
  double violation(const Eigen::Vector3d& s) const {
    const double N = planes_[0].n[2], k = planes_[0].r, t = planes_[3].r;
    return std::max(N * s.maxCoeff() - s.minCoeff() - k, s.maxCoeff() - t);
  }

 private:
  struct Plane {
    Eigen::Vector3d n, g, Eg;
    double r = 0.0;
  };
  enum : std::uint8_t { A = 1, B = 2, C = 4, T3 = 8, T2 = 16, T1 = 32 };
  static constexpr std::array<std::uint8_t, 12> kShearFirst = {
      A, A | B, A | C, A | T3, A | C | T3, A | B | T3, A | T2 | T3, B | T2 | T3, T3, T3 | T2, T3 | T2 | T1, B};
  static constexpr std::array<std::uint8_t, 12> kTensionFirst = {
      T3, T3 | T2, T3 | T2 | T1, A | T3, A | C | T3, A | B | T3, A | T2 | T3, B | T2 | T3, A, A | B, A | C, B};

  bool try_set(std::uint8_t set, const Eigen::Vector3d& trial, double scale, PrincipalReturn& out) const {
    std::array<int, 3> act{};
    int m = 0;
    for (int i = 0; i < 6; ++i)
      if (set & (1u << i)) act[m++] = i;
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3> M(m, m);
    Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1> rhs(m);
    for (int l = 0; l < m; ++l) {
      const Plane& pl = planes_[act[l]];
      rhs[l] = pl.n.dot(trial) - pl.r;
      for (int q = 0; q < m; ++q) M(l, q) = pl.n.dot(planes_[act[q]].Eg);
    }
    Eigen::FullPivLU<decltype(M)> lu(M);
    lu.setThreshold(1e-10);
    if (!lu.isInvertible()) return false;  // dependent planes: the set is covered by a smaller one
    const auto lambda = lu.solve(rhs).eval();
    const double a1 = E_(0, 0);
    Eigen::Vector3d s = trial, dep = Eigen::Vector3d::Zero();
    for (int q = 0; q < m; ++q) {
      if (lambda[q] < -1e-12 * scale / a1) return false;
      s -= lambda[q] * planes_[act[q]].Eg;
      dep += lambda[q] * planes_[act[q]].g;
    }
    // The tension planes are axis-aligned: land on them exactly, not within rounding.
    for (int q = 0; q < m; ++q)
      if (act[q] >= 3) s[5 - act[q]] = planes_[act[q]].r;
    if (violation(s) > 1e-12 * scale) return false;
    out.stress = s;
    out.plastic_strain = dep;
    out.shear_active = (set & (A | B | C)) != 0;
    out.tension_active = (set & (T1 | T2 | T3)) != 0;
    return true;
  }

  Mat3 E_;
  std::array<Plane, 6> planes_;
};

}  // namespace tsuchi
