#pragma once
// Jaumann stress rate, eq (22): sigma <- sigma + d_omega sigma - sigma d_omega, with the spin
// increment d_omega = dt (L - L^T) / 2 and L_ij = dv_i / dx_j. Applied before the constitutive
// increment so that a rigid rotation carries the stress along instead of straining it.
#include "tsuchi/core/tensor.hpp"

namespace tsuchi {

inline void jaumann_rotate(Voigt<2>& s, const Mat<2>& dw) {
  const double w = dw(0, 1);  // the only independent spin component in the plane
  const double sxx = s[0], syy = s[1], sxy = s[3];
  s[0] = sxx + 2.0 * w * sxy;
  s[1] = syy - 2.0 * w * sxy;
  s[3] = sxy + w * (syy - sxx);
  // sigma_zz is unchanged: the spin is about z.
}

inline void jaumann_rotate(Voigt<3>& s, const Mat<3>& dw) {
  const Mat3 m = to_matrix<3>(s);
  const Mat3 r = m + dw * m - m * dw;
  s = to_voigt<3>(r);
}

}  // namespace tsuchi
