#pragma once
// Small fixed-size vectors and tensors, with the spatial dimension D a template parameter.
//
// Stress and strain are symmetric and always carry the out-of-plane normal component: in plane
// strain sigma_zz is not zero and is one of the principal stresses (METHOD.md section 5). They are
// stored as "Voigt" vectors of tensor components (not engineering shear strains):
//   D = 2: xx, yy, zz, xy            D = 3: xx, yy, zz, xy, yz, xz
#include <Eigen/Core>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

// The small Voigt vectors of a point's update live on the stack, and the next operation reads them
// by pairs, (xx, yy), (zz, xy), (yz, xz). A pair read right after its two entries were stored one
// by one cannot be forwarded from the stores and waits for them to retire (a third of the stress
// update's samples, BENCHMARKS.md ninth part). So the functions below write whole pairs, built in
// a register (_mm_set_pd; Eigen's Vector2d(a, b) goes through the stack as two stores). -0.0 is
// the identity of addition for every double (x + 0.0 turns -0.0 into +0.0): the pair forms give
// the bits of the entry-wise ones, which stay as the fallback without SSE2.
template <int D>
[[gnu::always_inline]] inline void store_pair(Voigt<D>& v, int k, double a, double b) {
#if defined(__SSE2__)
  _mm_storeu_pd(v.data() + k, _mm_set_pd(b, a));
#else
  v[k] = a, v[k + 1] = b;
#endif
}

// v[i] += a for the normal entries xx, yy, zz.
template <int D>
[[gnu::always_inline]] inline void add_to_normal_entries(Voigt<D>& v, double a) {
#if defined(__SSE2__)
  double* const p = v.data();
  _mm_storeu_pd(p, _mm_add_pd(_mm_loadu_pd(p), _mm_set1_pd(a)));
  _mm_storeu_pd(p + 2, _mm_add_pd(_mm_loadu_pd(p + 2), _mm_set_pd(-0.0, a)));
#else
  for (int i = 0; i < 3; ++i) v[i] += a;
#endif
}

// Symmetric part of a velocity gradient (or any D x D matrix) as a Voigt vector; zz stays 0.
template <int D>
Voigt<D> sym_voigt(const Mat<D>& l) {
  Voigt<D> s;
  store_pair<D>(s, 0, l(0, 0), l(1, 1));
  if constexpr (D == 2) {
    store_pair<D>(s, 2, 0.0, 0.5 * (l(0, 1) + l(1, 0)));
  } else {
    store_pair<D>(s, 2, l(2, 2), 0.5 * (l(0, 1) + l(1, 0)));
    store_pair<D>(s, 4, 0.5 * (l(1, 2) + l(2, 1)), 0.5 * (l(0, 2) + l(2, 0)));
  }
  return s;
}

}  // namespace tsuchi
