// Building blocks of the step: Jaumann rotation, Hooke increment, principal values, damping.
#include "tsuchi/core/principal.hpp"
#include "tsuchi/material/linear_elastic.hpp"
#include "tsuchi/solver/damping.hpp"
#include "tsuchi/solver/jaumann.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <random>

namespace {

using namespace tsuchi;

// The plane-strain special case equals the general 3D formula with a spin about z.
TEST(Jaumann, PlaneCaseMatchesGeneralFormula) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 100; ++k) {
    Voigt<2> s2(u(rng), u(rng), u(rng), u(rng));
    Voigt<3> s3;
    s3 << s2[0], s2[1], s2[2], s2[3], 0.0, 0.0;
    const double w = 1e-3 * u(rng);
    Mat<2> dw2;
    dw2 << 0, w, -w, 0;
    Mat<3> dw3 = Mat<3>::Zero();
    dw3.topLeftCorner<2, 2>() = dw2;
    jaumann_rotate(s2, dw2);
    jaumann_rotate(s3, dw3);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(s2[i], s3[i], 1e-15);
    EXPECT_NEAR(s3[4], 0.0, 1e-15);
  }
}

// The 3D rotation takes one matrix product: it gives the bits of the two-product form
// m + dw m - m dw, symmetrised, for spins built as the solver builds them, 0.5 dt (L - L^T).
TEST(Jaumann, OneProductGivesTheBitsOfTheTwoProductForm) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 10000; ++k) {
    Voigt<3> s;
    for (int i = 0; i < 6; ++i) s[i] = 1e5 * u(rng);
    Mat<3> L;
    for (int i = 0; i < 9; ++i) L(i) = 10.0 * u(rng);
    const double dt = 1e-5 * (1.0 + u(rng));
    const Mat<3> dw = 0.5 * dt * (L - L.transpose());
    const Mat3 m = to_matrix<3>(s);
    const Mat3 two = m + dw * m - m * dw;
    const Voigt<3> expected = to_voigt<3>(two);
    jaumann_rotate(s, dw);
    for (int i = 0; i < 6; ++i) ASSERT_EQ(s[i], expected[i]) << "k = " << k << ", component " << i;
  }
}

// A small rotation keeps the invariants to second order in the spin increment.
TEST(Jaumann, RotationPreservesInvariantsToSecondOrder) {
  Voigt<3> s;
  s << -100.0, -50.0, -30.0, 20.0, -10.0, 5.0;
  const Eigen::Vector3d before = principal_values(s);
  Mat<3> dw;
  const double w = 1e-4;
  dw << 0, w, -2 * w, -w, 0, w, 2 * w, -w, 0;
  jaumann_rotate(s, dw);
  const Eigen::Vector3d after = principal_values(s);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(after[i], before[i], 1e-5);  // O(w^2 |s|) = 1e-6
}

TEST(Hooke, UniaxialStrainGivesConstrainedModulus) {
  const LinearElastic m = LinearElastic::from_young(1.0e7, 0.25);
  Voigt<2> s = Voigt<2>::Zero();
  Voigt<2> d = Voigt<2>::Zero();
  d[1] = -1e-4;
  m.update<2>(s, d);
  EXPECT_NEAR(s[1], -1e-4 * m.constrained_modulus(), 1e-9);
  EXPECT_NEAR(s[0] / s[1], 0.25 / 0.75, 1e-12);  // nu / (1 - nu)
  EXPECT_NEAR(s[2], s[0], 1e-12);                // plane strain: sigma_zz = sigma_xx here
  EXPECT_NEAR(m.G, 1.0e7 / 2.5, 1e-6);
  EXPECT_NEAR(m.K, 1.0e7 / 1.5, 1e-6);
}

TEST(Principal, MaxShearStrainIsRotationInvariant) {
  Eigen::Matrix3d e = Eigen::Vector3d(-0.02, 0.005, 0.01).asDiagonal();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Voigt<3> rotated = to_voigt<3>(R * e * R.transpose());
  EXPECT_NEAR(max_shear_strain<3>(rotated), 0.03, 1e-14);
  // 2D: in-plane rotation of diag(-0.02, 0.01) with eps_zz = 0.
  const double c = std::cos(0.3), s = std::sin(0.3);
  Voigt<2> e2;
  e2 << -0.02 * c * c + 0.01 * s * s, -0.02 * s * s + 0.01 * c * c, 0.0, (-0.02 - 0.01) * c * s;
  const Eigen::Vector3d p = principal_values(e2);
  EXPECT_NEAR(p[0], -0.02, 1e-15);
  EXPECT_NEAR(p[1], 0.0, 1e-15);
  EXPECT_NEAR(p[2], 0.01, 1e-15);
}

// Local damping opposes the velocity with |f| alpha, so its power f_damp v is never positive.
TEST(Damping, AlwaysDissipates) {
  for (double f : {-3.0, -0.5, 0.0, 2.0})
    for (double v : {-1.0, -1e-9, 0.0, 1e-9, 4.0}) {
      const double fd = local_damping_force(f, v, 0.3);
      EXPECT_LE(fd * v, 0.0);
      EXPECT_DOUBLE_EQ(std::abs(fd), v == 0.0 ? 0.0 : 0.3 * std::abs(f));
    }
}

}  // namespace
