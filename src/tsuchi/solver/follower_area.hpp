#pragma once
// The area vector of a follower pressure (model/loads.hpp, `follow = true`) carried through one
// step by Nanson's relation.
//
// A material surface element of area vector a_0 = n_0 dA_0 is, after a deformation F, the element
// a = J F^-T a_0 = cof(F) a_0 (Nanson's relation; Holzapfel 2000, Nonlinear Solid Mechanics, eq
// 2.54), with J = det F and cof(F) the cofactor matrix. Over one explicit step the particle moves
// with the step's velocity gradient L (the one its stress update uses), so its incremental
// deformation gradient is dF = I + dt L (the same linear map that moves a point x by dt L x), and
//
//   a_{n+1} = cof(I + dt L) a_n                                                        (N1)
//
// Cofactors compose, cof(F_2 F_1) = cof(F_2) cof(F_1), so (N1) step after step gives exactly
// a = cof(F) a_0 for the accumulated F = prod (I + dt L_k): the area vector follows the deformation
// of the particle's neighbourhood with no drift of its own. (The rate form da/dt = (tr L) a - L^T a
// is the derivative of (N1) at dt -> 0; taken by forward Euler it is (N1) to first order only, and
// would not have this exact composition.) Two checks follow from (N1) (tests/follower_load_test.cpp):
// a rigid rotation R (dF = R, cof R = R) turns a and keeps |a|; a stretch dF = diag(l_1, l_2, l_3)
// scales each component by the product of the other stretches (in 2D plane strain, where the
// thickness keeps its 1 m, by the other in-plane stretch).
//
// cof(F) is formed from F's entries directly (no inverse, no division): it stays defined where F is
// singular, and costs a few multiplications per loaded particle and step.
#include "tsuchi/core/tensor.hpp"

namespace tsuchi {

// cof(F) = J F^-T; in 2D the in-plane block of the plane-strain F = diag(F_2D, 1).
template <int D>
Mat<D> cofactor(const Mat<D>& F) {
  Mat<D> c;
  if constexpr (D == 2) {
    c << F(1, 1), -F(1, 0),
         -F(0, 1), F(0, 0);
  } else {
    // Row i of cof(F) is the cross product of the rows i+1 and i+2 of F (cyclically):
    // cof(F)_ij = (F_(i+1) x F_(i+2))_j.
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      c(i, 0) = F(j, 1) * F(k, 2) - F(j, 2) * F(k, 1);
      c(i, 1) = F(j, 2) * F(k, 0) - F(j, 0) * F(k, 2);
      c(i, 2) = F(j, 0) * F(k, 1) - F(j, 1) * F(k, 0);
    }
  }
  return c;
}

// (N1): the area vector (or a force proportional to it, -p a) after a step dt with velocity
// gradient L.
template <int D>
Vec<D> follow_area(const Vec<D>& a, const Mat<D>& L, double dt) {
  const Mat<D> dF = Mat<D>::Identity() + dt * L;
  return cofactor<D>(dF) * a;
}

}  // namespace tsuchi
