#pragma once
// Principal values of a symmetric tensor in Voigt storage, ascending (most compressive first).
// In plane strain the zz component is itself principal, so only the in-plane 2x2 block needs solving.
#include "tsuchi/core/tensor.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>

namespace tsuchi {

inline Eigen::Vector3d principal_values(const Voigt<2>& s) {
  const double c = 0.5 * (s[0] + s[1]);
  const double hd = 0.5 * (s[0] - s[1]);
  const double r = std::sqrt(hd * hd + s[3] * s[3]);  // not hypot: 5x slower, and no overflow at stress scales
  // c - r <= c + r already: s[2] only has to find its place (std::sort would call a general loop).
  const double lo = c - r, hi = c + r, zz = s[2];
  if (zz <= lo) return {zz, lo, hi};
  if (zz <= hi) return {lo, zz, hi};
  return {lo, hi, zz};
}

inline Eigen::Vector3d principal_values(const Voigt<3>& s) {
  Eigen::SelfAdjointEigenSolver<Mat3> es;
  es.computeDirect(to_matrix<3>(s), Eigen::EigenvaluesOnly);
  return es.eigenvalues();  // ascending
}

// Maximum shear strain gamma_max = eps_1 - eps_3, the difference of the extreme principal strains.
template <int D>
double max_shear_strain(const Voigt<D>& eps) {
  const Eigen::Vector3d e = principal_values(eps);
  return e[2] - e[0];
}

}  // namespace tsuchi
