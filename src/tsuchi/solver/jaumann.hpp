#pragma once
// Jaumann stress rate, eq (22): sigma <- sigma + d_omega sigma - sigma d_omega, with the spin
// increment d_omega = dt (L - L^T) / 2 and L_ij = dv_i / dx_j. Applied before the constitutive
// increment so that a rigid rotation carries the stress along instead of straining it.
#include "tsuchi/core/tensor.hpp"

namespace tsuchi {

inline void jaumann_rotate(Voigt<2>& s, const Mat<2>& dw) {
  const double w = dw(0, 1);  // the only independent spin component in the plane
  const double sxx = s[0], syy = s[1], szz = s[2], sxy = s[3];
  // sigma_zz is unchanged: the spin is about z. Written by pairs (core/tensor.hpp, store_pair).
  store_pair<2>(s, 0, sxx + 2.0 * w * sxy, syy - 2.0 * w * sxy);
  store_pair<2>(s, 2, szz, sxy + w * (syy - sxx));
}

// With sigma symmetric and d_omega antisymmetric (exactly: its entries are 0.5 dt (L_ij - L_ji)),
// sigma d_omega = -(d_omega sigma)^T term by term, so one product X = d_omega sigma gives both:
// r_ij = (sigma_ij + X_ij) + X_ji, and the stored component is the mean of r_ij and r_ji, as the
// full form m + dw m - m dw followed by symmetrisation gave, to the bit, at half the products.
inline void jaumann_rotate(Voigt<3>& s, const Mat<3>& dw) {
  const Mat3 m = to_matrix<3>(s);
  const Mat3 X = dw * m;
  for (int k = 0; k < 6; ++k) {
    const auto [i, j] = voigt_index[static_cast<std::size_t>(k)];
    const double rij = (m(i, j) + X(i, j)) + X(j, i), rji = (m(j, i) + X(j, i)) + X(i, j);
    s[k] = 0.5 * (rij + rji);
  }
}

}  // namespace tsuchi
