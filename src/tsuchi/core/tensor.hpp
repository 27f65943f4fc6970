#pragma once
// Small fixed-size vectors and tensors, with the spatial dimension D a template parameter.
//
// Stress and strain are symmetric and always carry the out-of-plane normal component: in plane
// strain sigma_zz is not zero and is one of the principal stresses (METHOD.md section 5). They are
// stored as "Voigt" vectors of tensor components (not engineering shear strains):
//   D = 2: xx, yy, zz, xy            D = 3: xx, yy, zz, xy, yz, xz
#include <Eigen/Core>

#include <array>
#include <cmath>
#include <type_traits>

namespace tsuchi {

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;

template <int D>
using Mat = Eigen::Matrix<double, D, D>;

template <int D>
inline constexpr int n_voigt = D == 2 ? 4 : 6;

template <int D>
using Voigt = Eigen::Matrix<double, n_voigt<D>, 1>;

using Mat3 = Eigen::Matrix3d;

// Zero of a number or of an Eigen fixed-size type, for code written over both (per-particle and
// per-node arrays).
template <class T>
T zero_of() {
  if constexpr (std::is_arithmetic_v<T>) return T{0};
  else return T::Zero();
}

// Row/column of each shear entry in Voigt order (entries 0..2 are the diagonal).
inline constexpr std::array<std::array<int, 2>, 6> voigt_index{
    {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}}};

template <int D>
Mat3 to_matrix(const Voigt<D>& s) {
  Mat3 m = Mat3::Zero();
  for (int k = 0; k < n_voigt<D>; ++k) {
    const auto [i, j] = voigt_index[static_cast<std::size_t>(k)];
    m(i, j) = s[k];
    m(j, i) = s[k];
  }
  return m;
}

template <int D>
Voigt<D> to_voigt(const Mat3& m) {
  Voigt<D> s;
  for (int k = 0; k < n_voigt<D>; ++k) {
    const auto [i, j] = voigt_index[static_cast<std::size_t>(k)];
    s[k] = 0.5 * (m(i, j) + m(j, i));
  }
  return s;
}

template <int D>
double trace(const Voigt<D>& s) {
  return s[0] + s[1] + s[2];
}

// Double contraction s : e of two symmetric tensors in Voigt storage.
template <int D>
double contract(const Voigt<D>& s, const Voigt<D>& e) {
  double r = s[0] * e[0] + s[1] * e[1] + s[2] * e[2];
  for (int k = 3; k < n_voigt<D>; ++k) r += 2.0 * s[k] * e[k];
  return r;
}

// Deviatoric part s - tr(s)/3 I (the out-of-plane zz included in 2D).
template <int D>
Voigt<D> deviator(const Voigt<D>& s) {
  Voigt<D> dev = s;
  const double mean = trace<D>(s) / 3.0;
  for (int i = 0; i < 3; ++i) dev[i] -= mean;
  return dev;
}

// Von Mises equivalent stress q = sqrt(3 J2).
template <int D>
double von_mises(const Voigt<D>& s) {
  const Voigt<D> dev = deviator<D>(s);
  return std::sqrt(1.5 * contract<D>(dev, dev));
}

// Symmetric part of a velocity gradient (or any D x D matrix) as a Voigt vector; zz stays 0.
template <int D>
Voigt<D> sym_voigt(const Mat<D>& l) {
  Voigt<D> s = Voigt<D>::Zero();
  s[0] = l(0, 0);
  s[1] = l(1, 1);
  s[3] = 0.5 * (l(0, 1) + l(1, 0));
  if constexpr (D == 3) {
    s[2] = l(2, 2);
    s[4] = 0.5 * (l(1, 2) + l(2, 1));
    s[5] = 0.5 * (l(0, 2) + l(2, 0));
  }
  return s;
}

}  // namespace tsuchi
