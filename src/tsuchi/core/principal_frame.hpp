#pragma once
// A symmetric tensor split into principal values (ascending, tension positive) and the frame that
// rebuilds it from corrected values with the principal directions kept, as the Mohr-Coulomb
// return of METHOD.md section 5 needs.
//
// Plane strain: zz is principal by itself; the in-plane pair is solved in closed form, so the
// rebuilt tensor never mixes z into the plane, even when sigma_zz equals an in-plane value.
#include "tsuchi/core/tensor.hpp"

#include <Eigen/Eigenvalues>

#include <array>
#include <cmath>

namespace tsuchi {

template <int D>
struct PrincipalFrame;

template <>
struct PrincipalFrame<2> {
  Eigen::Vector3d values;      // ascending
  std::array<int, 3> slot{};   // slot[k]: 0 in-plane minor, 1 in-plane major, 2 zz, for values[k]
  double c = 1.0, s = 0.0;     // in-plane direction (cos, sin) of the minor in-plane value

  explicit PrincipalFrame(const Voigt<2>& t) {
    const double half_diff = 0.5 * (t[0] - t[1]);
    const double r = std::sqrt(half_diff * half_diff + t[3] * t[3]);  // hypot is 5x slower; no overflow at stress scales
    // Direction of the minor in-plane value from the half-angle formulas (no trigonometric call):
    // it is the major direction (cos 2a = half_diff / r, sin 2a = t_xy / r) turned by 90 degrees.
    double cm = 1.0, sm = 0.0;  // major direction; any direction when the plane part is isotropic
    if (r > 0.0) {
      const double c2 = half_diff / r, s2 = t[3] / r;
      if (c2 >= 0.0) {
        cm = std::sqrt(0.5 * (1.0 + c2));
        sm = s2 / (2.0 * cm);
      } else {
        sm = std::copysign(std::sqrt(0.5 * (1.0 - c2)), s2);
        cm = s2 / (2.0 * sm);
      }
    }
    c = -sm;
    s = cm;
    const double mean = 0.5 * (t[0] + t[1]);
    const double v[3] = {mean - r, mean + r, t[2]};
    slot = {0, 1, 2};
    // Three-element sort of the slots by value.
    if (v[slot[1]] < v[slot[0]]) std::swap(slot[0], slot[1]);
    if (v[slot[2]] < v[slot[1]]) std::swap(slot[1], slot[2]);
    if (v[slot[1]] < v[slot[0]]) std::swap(slot[0], slot[1]);
    values = {v[slot[0]], v[slot[1]], v[slot[2]]};
  }

  Voigt<2> rebuild(const Eigen::Vector3d& corrected) const {
    double v[3];
    for (int k = 0; k < 3; ++k) v[slot[k]] = corrected[k];
    const double a = v[0], b = v[1];  // minor along (c, s), major along (-s, c)
    Voigt<2> t;
    t[0] = a * c * c + b * s * s;
    t[1] = a * s * s + b * c * c;
    t[2] = v[2];
    t[3] = (a - b) * c * s;
    return t;
  }
};

template <>
struct PrincipalFrame<3> {
  Eigen::Vector3d values;
  Mat3 Q;  // columns: principal directions of values[0..2]

  explicit PrincipalFrame(const Voigt<3>& t) {
    Eigen::SelfAdjointEigenSolver<Mat3> es;
    es.compute(to_matrix<3>(t));  // iterative: computeDirect loses ~1e-9 relative, too much for the return
    values = es.eigenvalues();
    Q = es.eigenvectors();
  }

  Voigt<3> rebuild(const Eigen::Vector3d& corrected) const {
    return to_voigt<3>(Q * corrected.asDiagonal() * Q.transpose());
  }
};

}  // namespace tsuchi
