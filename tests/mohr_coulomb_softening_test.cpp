// Strain-softening Mohr-Coulomb (material/mohr_coulomb_softening.hpp) at the level of one point:
// the strength follows the tables in the softening parameter k, the return is Mohr-Coulomb's, and
// constant tables are plain Mohr-Coulomb bit for bit.
#include "tsuchi/element/element_driver.hpp"
#include "tsuchi/io/element_reader.hpp"
#include "tsuchi/material/material.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace tsuchi;
using std::numbers::pi;

constexpr double kPa = 1e3;
double deg(double d) { return d * pi / 180.0; }

// The paper's soil (triaxial test 1 moduli) with c softening from 8.5 to 1 kPa and phi from 30.5
// to 25 degrees; psi 0.
const char* kSoil = R"(
[[materials]]
name = "soil"
model = "mohr_coulomb_softening"
density = 1530.0
shear_modulus = 1311.0e3
poisson_ratio = 0.2
cohesion = [[0.0, 8.5e3], [0.01, 3.0e3], [0.03, 1.0e3]]
friction_angle = [[0.0, 30.5], [0.02, 25.0]]
dilatancy_angle = 0.0
)";

MohrCoulombSoftening model_of(const Material& m) { return std::get<MohrCoulombSoftening>(m.model); }

io::ElementInput read(const std::string& test) { return io::read_element_string(std::string(kSoil) + test, "soil.toml"); }

// Mohr-Coulomb's (s3 - s1) on its surface for a given s3 (tension positive, s1 <= s2 <= s3):
// s1 = s3 N_phi - 2 c sqrt(N_phi).
double mc_deviator(double s3, double c, double phi) {
  const double N = (1 + std::sin(phi)) / (1 - std::sin(phi));
  return s3 * (1 - N) + 2 * c * std::sqrt(N);
}

// The steps of an element path as the driver books them (its rows carry every state field):
// the stress and mode after each step, and k before and after it.
struct Steps {
  struct Step {
    Voigt<3> stress;
    YieldMode mode;
    double k_before, k_after;
  };
  std::vector<Step> steps;
};

Steps steps_of(const std::vector<element::ElementRow>& rows) {
  Steps r;
  for (std::size_t n = 1; n < rows.size(); ++n)
    r.steps.push_back({rows[n].stress, rows[n].mode, rows[n - 1].state_value("softening_parameter"),
                       rows[n].state_value("softening_parameter")});
  return r;
}

// Simple shear at constant vertical stress (the element driver's preset): every shear step ends
// on the Mohr-Coulomb surface of c and phi interpolated at the k booked before it; the first one at
// the peak values, those past the last breakpoint at the residual ones (within 0.5 %, as the
// check is stated; the return makes it exact to rounding).
TEST(MohrCoulombSoftening, SimpleShearFollowsTheTable) {
  const auto in = read(R"(
[test]
type = "simple_shear"
vertical_stress = 50e3
shear_strain = 0.2
increments = 2000
)");
  const MohrCoulombSoftening m = model_of(in.material);
  const auto rows = element::drive_element(in.material, in.path);
  const Steps r = steps_of(rows);
  int shear = 0, residual = 0;
  bool peak_seen = false;
  for (const auto& s : r.steps) {
    if (s.mode != YieldMode::Shear) continue;
    ++shear;
    const Eigen::Vector3d p = PrincipalFrame<3>(s.stress).values;
    const double c = m.cohesion.at(s.k_before), phi = m.phi.at(s.k_before);
    const double expected = mc_deviator(p[2], c, phi);
    ASSERT_NEAR(p[2] - p[0], expected, 0.005 * expected) << "k = " << s.k_before;
    ASSERT_NEAR(p[2] - p[0], expected, 1e-9 * 50 * kPa);
    ASSERT_GT(s.k_after, s.k_before);
    if (!peak_seen) {
      peak_seen = true;
      EXPECT_EQ(s.k_before, 0.0);
      std::printf("simple shear, first yield: s3 - s1 = %.4f kPa, MC peak (c = 8.5 kPa, phi = 30.5) %.4f kPa\n",
                  (p[2] - p[0]) / kPa, mc_deviator(p[2], 8.5 * kPa, deg(30.5)) / kPa);
      EXPECT_NEAR(p[2] - p[0], mc_deviator(p[2], 8.5 * kPa, deg(30.5)), 1e-9 * 50 * kPa);
    }
    if (s.k_before > 0.03) {
      EXPECT_NEAR(p[2] - p[0], mc_deviator(p[2], 1 * kPa, deg(25.0)), 0.005 * expected);
      ++residual;
    }
  }
  const auto& last = r.steps.back();
  const Eigen::Vector3d p = PrincipalFrame<3>(last.stress).values;
  std::printf("simple shear, end: k = %.4f, s3 - s1 = %.4f kPa, MC residual (c = 1 kPa, phi = 25) %.4f kPa\n",
              last.k_after, (p[2] - p[0]) / kPa, mc_deviator(p[2], 1 * kPa, deg(25.0)) / kPa);
  EXPECT_GT(shear, 1000);
  EXPECT_GT(residual, 100);
  // With psi = 0 the flow is a pure shear: k is half the engineering plastic shear strain.
  EXPECT_NEAR(last.k_after, 0.5 * rows.back().plastic_shear_strain, 1e-9);
}

// Drained triaxial compression at 50 kPa: the peak deviator is the Mohr-Coulomb one with the peak
// values, q = sigma_c (N_phi - 1) + 2 c sqrt(N_phi), and after softening the residual one.
TEST(MohrCoulombSoftening, TriaxialPeakThenResidual) {
  const double sc = 50 * kPa;
  const auto in = read(R"(
[test]
type = "triaxial_compression"
confining_pressure = 50e3
axial_strain = 0.15
increments = 1500
)");
  const auto rows = element::drive_element(in.material, in.path);
  const auto q_of = [&](double c, double phi) {
    const double N = (1 + std::sin(deg(phi))) / (1 - std::sin(deg(phi)));
    return sc * (N - 1) + 2 * c * std::sqrt(N);
  };
  double q_peak = 0.0;
  for (const auto& row : rows) q_peak = std::max(q_peak, row.q());
  const double q_end = rows.back().q();
  const Steps r = steps_of(rows);
  std::printf("triaxial 50 kPa: peak q %.3f kPa (MC %.3f), end q %.3f kPa (MC residual %.3f), end k %.4f\n",
              q_peak / kPa, q_of(8.5 * kPa, 30.5) / kPa, q_end / kPa, q_of(1 * kPa, 25.0) / kPa,
              r.steps.back().k_after);
  EXPECT_NEAR(q_peak, q_of(8.5 * kPa, 30.5), 0.005 * q_of(8.5 * kPa, 30.5));
  ASSERT_GT(r.steps.back().k_before, 0.03);
  EXPECT_NEAR(q_end, q_of(1 * kPa, 25.0), 0.005 * q_of(1 * kPa, 25.0));
}

MohrCoulomb plain(double psi_deg) {
  MohrCoulomb m;
  m.elastic = LinearElastic::from_shear(1311 * kPa, 0.2);
  m.cohesion = 8.5 * kPa;
  m.phi = deg(30.5);
  m.psi = deg(psi_deg);
  m.tension = 2 * kPa;
  return m;
}

// Tables that do not vary are plain Mohr-Coulomb bit for bit, in 3D and plane strain, along a
// random path that yields in shear and in tension.
template <int D>
void same_as_mohr_coulomb() {
  const MohrCoulomb mc = plain(10.0);
  MohrCoulombSoftening s;
  s.base = mc;
  s.cohesion = {{0.0, 0.01, 0.02}, {8.5 * kPa, 8.5 * kPa, 8.5 * kPa}};
  s.phi = SofteningTable::constant(mc.phi);
  s.psi = SofteningTable::constant(mc.psi);
  PointStateOf<MohrCoulomb> a;
  PointStateOf<MohrCoulombSoftening> b;
  Voigt<D> sa = Voigt<D>::Constant(-20 * kPa), sb = sa;
  for (int k = 3; k < n_voigt<D>; ++k) sa[k] = sb[k] = 0.0;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  int modes[3] = {0, 0, 0};
  for (int n = 0; n < 3000; ++n) {
    Voigt<D> d;
    for (int k = 0; k < n_voigt<D>; ++k) d[k] = 2e-4 * u(rng) + (k == 0 ? 3e-5 : 0.0);
    mc.update<D>(sa, d, Mat<D>::Zero(), mc.context(), a.ref());
    s.update<D>(sb, d, Mat<D>::Zero(), s.context(), b.ref());
    for (int k = 0; k < n_voigt<D>; ++k) ASSERT_EQ(sa[k], sb[k]) << "step " << n;
    for (auto f : {"yield_mode", "plastic_shear_strain", "plastic_volumetric_strain"})
      ASSERT_EQ(a.field(f), b.field(f)) << f << ", step " << n;
    ++modes[static_cast<int>(a.field("yield_mode"))];
  }
  EXPECT_GT(modes[1], 30);
  EXPECT_GT(modes[2], 100);
}
TEST(MohrCoulombSoftening, ConstantTablesAreMohrCoulombBitForBit3D) { same_as_mohr_coulomb<3>(); }
TEST(MohrCoulombSoftening, ConstantTablesAreMohrCoulombBitForBitPlaneStrain) { same_as_mohr_coulomb<2>(); }

MohrCoulombSoftening softening(double psi_deg) {
  MohrCoulombSoftening m;
  m.base = plain(0.0);
  m.base.tension = 0.0;
  m.cohesion = {{0.0, 0.01, 0.03}, {8.5 * kPa, 3 * kPa, 1 * kPa}};
  m.phi = {{0.0, 0.02}, {deg(30.5), deg(25.0)}};
  m.psi = {{0.0, 0.02}, {deg(psi_deg), 0.0}};
  return m;
}

// 20,000 random trial stresses at random k and imperfection factors: each lands on the surface
// of its mode for c(k), phi(k) scaled by the factors, inside the others, and the k booked equals
// FLAC's (S1) on the principal plastic strain C (s_trial - s).
TEST(MohrCoulombSoftening, RandomTrialsLandOnTheCurrentSurface) {
  const MohrCoulombSoftening m = softening(10.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> wide(-300 * kPa, 50 * kPa), near_apex(-40 * kPa, 50 * kPa), u01(0, 1);
  const double scale = 100 * kPa;
  int shear = 0, tension = 0;
  for (int n = 0; n < 20000; ++n) {
    PointStateOf<MohrCoulombSoftening> st;
    StateRef s = st.ref();
    s[MohrCoulombSoftening::kSoftening] = 0.04 * u01(rng);
    s[MohrCoulombSoftening::kCohesionFactor] = 1 + 0.02 * (u01(rng) - 0.5);
    s[MohrCoulombSoftening::kFrictionFactor] = 1 + 0.02 * (u01(rng) - 0.5);
    const double k0 = s[MohrCoulombSoftening::kSoftening];
    auto& u = n % 2 ? wide : near_apex;
    Voigt<3> sig;
    sig << u(rng), u(rng), u(rng), 0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng);
    const Voigt<3> trial = sig;
    m.update<3>(sig, Voigt<3>::Zero(), Mat<3>::Zero(), m.context(), s);
    const MohrCoulomb at = m.at(k0);
    const auto str = at.strength(s[MohrCoulombSoftening::kCohesionFactor], s[MohrCoulombSoftening::kFrictionFactor]);
    const Eigen::Vector3d p = PrincipalFrame<3>(sig).values;
    const double f_s = MohrCoulomb::shear_yield(p, str), f_t = str.sigma_t - p[2];
    const auto mode = static_cast<YieldMode>(s[MohrCoulombSoftening::kMode]);
    const double dk = s[MohrCoulombSoftening::kSoftening] - k0;
    if (mode == YieldMode::Shear) {
      ++shear;
      ASSERT_LT(std::abs(f_s), 1e-9 * scale) << n;
      // (S1) on the principal plastic strain of the step (trial and result are coaxial).
      const Eigen::Vector3d e = at.compliance(PrincipalFrame<3>(trial).values - p);
      const double mean = e.mean();
      const double flac = std::sqrt(0.5 * (e.array() - mean).square().sum());
      ASSERT_NEAR(dk, flac, 1e-9 * flac + 1e-18) << n;
      ASSERT_GT(dk, 0.0);
    } else {
      ASSERT_EQ(dk, 0.0) << n;  // tension and elastic steps do not soften
    }
    if (mode == YieldMode::Tension) {
      ++tension;
      ASSERT_LT(std::abs(f_t), 1e-9 * scale) << n;
    }
    ASSERT_GT(f_s, -1e-9 * scale) << n;
    ASSERT_GT(f_t, -1e-9 * scale) << n;
  }
  EXPECT_GT(shear, 1000);
  EXPECT_GT(tension, 1000);
}

// Rotating the stress and the strain increment rotates the result, with the same k booked.
TEST(MohrCoulombSoftening, ObjectiveUnderRotation) {
  const MohrCoulombSoftening m = softening(10.0);
  const Mat3 R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  PointStateOf<MohrCoulombSoftening> a, b;
  Voigt<3> sa = Voigt<3>::Constant(-50 * kPa);
  sa.tail<3>().setZero();
  Voigt<3> sb = sa;
  int yielded = 0;
  for (int n = 0; n < 400; ++n) {
    Voigt<3> d;
    d << 1e-3 * u(rng) - 4e-4, 1e-3 * u(rng), 1e-3 * u(rng), 1e-3 * u(rng), 1e-3 * u(rng), 1e-3 * u(rng);
    m.update<3>(sa, d, Mat3::Zero(), m.context(), a.ref());
    m.update<3>(sb, to_voigt<3>(R * to_matrix<3>(d) * R.transpose()), Mat3::Zero(), m.context(), b.ref());
    const Mat3 diff = R * to_matrix<3>(sa) * R.transpose() - to_matrix<3>(sb);
    ASSERT_LT(diff.cwiseAbs().maxCoeff(), 1e-8 * 100 * kPa) << n;
    // k adds up the steps' rounding: 1e-9 of its value.
    ASSERT_NEAR(a.field("softening_parameter"), b.field("softening_parameter"), 1e-9 * a.field("softening_parameter")) << n;
    yielded += a.field("yield_mode") == 1.0;
    // The path is a random walk that keeps the point in contact with a shrinking surface: its
    // stress is rebuilt on each side and must stay together.
    sb = to_voigt<3>(R * to_matrix<3>(sa) * R.transpose());
  }
  EXPECT_GT(yielded, 50);
  EXPECT_GT(a.field("softening_parameter"), 0.03);  // through to the residual strength
}

// softening_length L on cells of size h: the tables' abscissae times L / h, values unchanged;
// without L the model is used as read.
TEST(MohrCoulombSoftening, CellSizeScalesTheTables) {
  MohrCoulombSoftening m = softening(5.0);
  const MohrCoulombSoftening same = m.with_cell_size(0.002);
  EXPECT_EQ(same.cohesion.strain, m.cohesion.strain);
  EXPECT_EQ(same.cell_size, 0.0);
  m.softening_length = 0.004;
  const MohrCoulombSoftening fine = m.with_cell_size(0.001);
  for (double k : {0.0, 0.003, 0.01, 0.02, 0.05}) {
    EXPECT_NEAR(fine.cohesion.at(4 * k), m.cohesion.at(k), 1e-9 * kPa) << k;
    EXPECT_NEAR(fine.phi.at(4 * k), m.phi.at(k), 1e-15) << k;
    EXPECT_NEAR(fine.psi.at(4 * k), m.psi.at(k), 1e-15) << k;
  }
  EXPECT_NE(fine.describe().find("scaled by 4"), std::string::npos) << fine.describe();
}

// The reader: the tables in degrees become radians; interpolation and the residual.
TEST(MohrCoulombSoftening, ReaderAndInterpolation) {
  const auto in = read(R"(
[test]
type = "simple_shear"
vertical_stress = 50e3
shear_strain = 0.01
)");
  const MohrCoulombSoftening m = model_of(in.material);
  EXPECT_DOUBLE_EQ(m.cohesion.at(0.005), 0.5 * (8.5 + 3.0) * kPa);
  EXPECT_DOUBLE_EQ(m.cohesion.at(0.02), 2.0 * kPa);
  EXPECT_DOUBLE_EQ(m.cohesion.at(1.0), 1.0 * kPa);
  EXPECT_NEAR(m.phi.at(0.01), deg(27.75), 1e-15);
  EXPECT_NEAR(m.phi.at(0.5), deg(25.0), 1e-15);
  EXPECT_EQ(m.psi.at(0.5), 0.0);
  EXPECT_FALSE(m.softening_length.has_value());
  EXPECT_NE(io::describe_material(in.material).find("tables used as given"), std::string::npos);
}

}  // namespace
