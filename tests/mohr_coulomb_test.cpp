// Mohr-Coulomb with tension cut-off (METHOD.md section 5) at the level of one material point.
#include "tsuchi/material/mohr_coulomb.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <numbers>
#include <random>
#include <tuple>
#include <utility>

namespace {

using namespace tsuchi;
using std::numbers::pi;

constexpr double kPa = 1e3;
double deg(double d) { return d * pi / 180.0; }

// The paper's soil (test 1 moduli): c = 8.5 kPa, phi = 30.5 deg, G = 1311 kPa, nu = 0.2.
MohrCoulomb soil(double psi_deg = 0.0, TensionRule rule = TensionRule::Flac,
                 TensionSelection selection = TensionSelection::Flac) {
  MohrCoulomb m;
  m.elastic = LinearElastic::from_shear(1311 * kPa, 0.2);
  m.cohesion = 8.5 * kPa;
  m.phi = deg(30.5);
  m.psi = deg(psi_deg);
  m.tension = 0.0;
  m.tension_rule = rule;
  m.tension_selection = selection;
  return m;
}

// 20,000 random trial stresses, many far outside, some near edges and the shear-tension corner,
// with non-associated flow: every corrected stress is on the surface of its mode and inside all
// the others, within 1e-9 of the stress scale.
void check_random_returns(const MohrCoulomb& m, unsigned seed) {
  const auto s = m.strength();
  const double a1 = m.elastic.K + 4 * m.elastic.G / 3, a2 = m.elastic.K - 2 * m.elastic.G / 3;
  const MohrCoulombReturn ret(s.N_phi, s.N_psi, 2 * s.c * s.sqrt_N_phi, s.sigma_t, a1, a2);
  const MohrCoulombReturn& planes = ret;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> wide(-300 * kPa, 50 * kPa), near_apex(-40 * kPa, 50 * kPa);
  const double scale = 100 * kPa;
  int shear = 0, tension = 0;
  for (int k = 0; k < 20000; ++k) {
    auto& u = k % 2 ? wide : near_apex;
    Voigt<3> sig;
    sig << u(rng), u(rng), u(rng), 0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng);
    if (k % 4 == 0) sig[1] = sig[0];  // on an edge of the pyramid before the return
    PrincipalReturn direct;
    const Eigen::Vector3d trial = PrincipalFrame<3>(sig).values;
    for (bool shear_first : {true, false}) {  // an admissible active set exists from either side
      if (ret.violation(trial) > 0) {
        ASSERT_TRUE(ret.solve(trial, shear_first, direct)) << "k = " << k;
      }
    }
    PlasticPoint st;
    const YieldMode mode = m.correct<3>(sig, s, st);
    const Eigen::Vector3d p = PrincipalFrame<3>(sig).values;
    const double f_s = MohrCoulomb::shear_yield(p, s), f_t = s.sigma_t - p[2];
    if (mode == YieldMode::Shear) {
      ++shear;
      ASSERT_LT(std::abs(f_s), 1e-9 * scale) << "k = " << k;
    }
    if (mode == YieldMode::Tension) {
      ++tension;
      ASSERT_LT(std::abs(f_t), 1e-9 * scale) << "k = " << k;
    }
    if (mode != YieldMode::Elastic && m.psi == 0.0) {
      // psi = 0: shear flow has no volume change and a tension release only opens.
      ASSERT_GE(st.plastic_volume, -1e-15 * std::abs(st.plastic_shear)) << "k = " << k;
    }
    ASSERT_GT(f_s, -1e-9 * scale) << "outside the shear surface after return, k = " << k;
    ASSERT_GT(f_t, -1e-9 * scale) << "outside the tension surface after return, k = " << k;
    ASSERT_LT(planes.violation(p), 1e-9 * scale) << "k = " << k;
    ASSERT_GE(st.plastic_shear, 0.0);
  }
  EXPECT_GT(shear, 1000);
  EXPECT_GT(tension, 1000);
}

TEST(MohrCoulomb, ReturnLandsOnTheSurfaceAndNeverOutside) {
  check_random_returns(soil(10.0), 42);
  check_random_returns(soil(30.5), 43);  // associated
  MohrCoulomb with_tension = soil(0.0);
  with_tension.tension = 4 * kPa;
  check_random_returns(with_tension, 44);
  for (auto [rule, selection] : {std::pair{TensionRule::Flac, TensionSelection::Flac},
                                 {TensionRule::Flac, TensionSelection::Paper},
                                 {TensionRule::Paper, TensionSelection::Paper}}) {
    check_random_returns(soil(0.0, rule, selection), 45);
    MohrCoulomb m = soil(10.0, rule, selection);
    m.tension = 3 * kPa;
    check_random_returns(m, 46);
  }
}

// The paper's release with its selection is continuous where the selection switches (s3 = sigma_t)
// and across the shear surface: a trial moved by 1e-6 Pa moves the result by about as much.
TEST(MohrCoulomb, PaperReleaseIsContinuous) {
  const MohrCoulomb m = soil(0.0, TensionRule::Paper, TensionSelection::Paper);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-60 * kPa, 20 * kPa), unit(-1, 1);
  double worst = 0;
  for (int k = 0; k < 20000; ++k) {
    Voigt<2> a;
    a << u(rng), u(rng), u(rng), 0.3 * u(rng);
    if (k % 2 == 0) {  // put the largest principal value on sigma_t = 0: the selection's switch
      const Eigen::Vector3d p = PrincipalFrame<2>(a).values;
      for (int i = 0; i < 3; ++i) a[i] -= p[2];
    }
    Voigt<2> b = a;
    for (int i = 0; i < 4; ++i) b[i] += 1e-6 * unit(rng);
    PlasticPoint sa, sb;
    m.correct<2>(a, m.strength(), sa);
    m.correct<2>(b, m.strength(), sb);
    worst = std::max(worst, (a - b).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-5);  // Pa, for trials 1e-6 Pa apart
}

// Plane-strain compression from an isotropic state sigma3 = p: eps_yy driven, sigma_xx held at -p
// by iteration, eps_zz = 0. Returns the deviator q = -sigma_yy - p (compression positive) at the
// end and, through `dilatancy`, d eps_v / d gamma over the last steps.
struct PathResult {
  double q_peak = 0, dilatancy = 0;
  double plastic_volume = 0;
};

PathResult plane_strain_compression(const MohrCoulomb& m, double p, double axial = 0.15, int steps = 6000) {
  Voigt<2> sig;
  sig << -p, -p, -p, 0.0;
  PlasticPoint st;
  const double de = -axial / steps;
  const double M = m.elastic.constrained_modulus(), lam = m.elastic.K - 2 * m.elastic.G / 3;
  PathResult r;
  double ev_prev = 0, g_prev = 0, ev = 0, exx = 0, eyy = 0;
  for (int n = 0; n < steps; ++n) {
    // Find d_eps_xx so that sigma_xx stays at -p (secant iteration on the elastic stiffness).
    double dexx = -lam / M * de;
    Voigt<2> trial;
    for (int it = 0; it < 100; ++it) {
      trial = sig;
      PlasticPoint tmp = st;
      Voigt<2> d;
      d << dexx, de, 0.0, 0.0;
      m.update<2>(trial, d, tmp);
      const double err = trial[0] + p;
      if (std::abs(err) < 1e-10 * p) break;
      dexx -= err / M;
    }
    Voigt<2> d;
    d << dexx, de, 0.0, 0.0;
    m.update<2>(sig, d, st);
    exx += dexx;
    eyy += de;
    ev = exx + eyy;
    const double gamma = exx - eyy;
    if (n == steps - 101) ev_prev = ev, g_prev = gamma;
    if (n == steps - 1) r.dilatancy = (ev - ev_prev) / (gamma - g_prev);
    r.q_peak = std::max(r.q_peak, -sig[1] - p);
  }
  r.plastic_volume = st.plastic_volume;
  return r;
}

TEST(MohrCoulomb, PlaneStrainPeakDeviatorMatchesTheory) {
  const MohrCoulomb m = soil();
  const double N = (1 + std::sin(m.phi)) / (1 - std::sin(m.phi));
  for (double p_kPa : {10.0, 50.0, 100.0}) {
    const double p = p_kPa * kPa;
    const double q_theory = p * (N - 1) + 2 * m.cohesion * std::sqrt(N);
    const PathResult r = plane_strain_compression(m, p);
    EXPECT_NEAR(r.q_peak, q_theory, 0.005 * q_theory) << "p = " << p_kPa << " kPa";
    std::printf("p = %5.1f kPa: peak q %.3f kPa, Mohr-Coulomb %.3f kPa\n", p_kPa, r.q_peak / kPa, q_theory / kPa);
  }
  // The published values of METHOD.md section 6.
  EXPECT_NEAR(10 * kPa * (N - 1) + 2 * m.cohesion * std::sqrt(N), 50.4 * kPa, 0.1 * kPa);
  EXPECT_NEAR(100 * kPa * (N - 1) + 2 * m.cohesion * std::sqrt(N), 235.9 * kPa, 0.1 * kPa);
}

TEST(MohrCoulomb, DilatancyFollowsPsi) {
  const PathResult zero = plane_strain_compression(soil(0.0), 50 * kPa);
  EXPECT_NEAR(zero.dilatancy, 0.0, 1e-9);
  EXPECT_NEAR(zero.plastic_volume, 0.0, 1e-15);
  const MohrCoulomb assoc = soil(30.5);
  const PathResult r = plane_strain_compression(assoc, 50 * kPa);
  // Plastic flow at constant stress: d eps_v / d gamma = sin(psi) (dilation positive).
  EXPECT_NEAR(r.dilatancy, std::sin(assoc.psi), 1e-6);
  EXPECT_GT(r.plastic_volume, 0.0);
}

TEST(MohrCoulomb, TensionFlacRuleHoldsTheLargestStressAtSigmaT) {
  MohrCoulomb m = soil();
  m.tension = 5 * kPa;
  Voigt<3> sig = Voigt<3>::Zero();
  Voigt<3> d = Voigt<3>::Zero();
  d[0] = 2e-3;  // pull along x
  PlasticPoint st;
  const YieldMode mode = m.update<3>(sig, d, st);
  EXPECT_EQ(mode, YieldMode::Tension);
  const Eigen::Vector3d p = PrincipalFrame<3>(sig).values;
  EXPECT_NEAR(p[2], 5 * kPa, 1e-9 * kPa);
  EXPECT_NEAR(sig[0], 5 * kPa, 1e-9 * kPa);
}

// Eq (28) as a release: stretched along x and squeezed along y (plane strain), the x stress drops
// to sigma_t = 0 and the compression along y and z is kept; the booked plastic strain is the
// opening C (sigma_trial - sigma), with volume change s_xx_trial / 3K > 0.
TEST(MohrCoulomb, TensionPaperRuleReleasesOnlyTheTensileDirection) {
  {
    const MohrCoulomb m = soil(0.0, TensionRule::Paper, TensionSelection::Paper);  // sigma_t = 0
    Voigt<2> sig;
    sig << -1 * kPa, -1 * kPa, -1 * kPa, 0.0;
    Voigt<2> d;
    d << 1e-3, -1e-3, 0.0, 0.0;
    const double two_G = 2 * m.elastic.G;  // trial: s_xx = -1 kPa + 2G 1e-3, s_yy = -1 kPa - 2G 1e-3
    PlasticPoint st;
    EXPECT_EQ(m.update<2>(sig, d, st), YieldMode::Tension);
    EXPECT_EQ(sig[0], 0.0);
    EXPECT_NEAR(sig[1], -1 * kPa - two_G * 1e-3, 1e-9 * kPa);
    EXPECT_NEAR(sig[2], -1 * kPa, 1e-9 * kPa);
    EXPECT_NEAR(sig[3], 0.0, 1e-9 * kPa);
    const double released = -1 * kPa + two_G * 1e-3;
    EXPECT_NEAR(st.plastic_volume, released / (3 * m.elastic.K), 1e-12);
    EXPECT_GT(st.plastic_volume, 0.0);
  }
}

// The literal reset to sigma_t on the diagonal would erase the squeeze: repeated stretch-squeeze
// steps of a released point must keep building compression along y, as an elastic body would.
TEST(MohrCoulomb, TensionPaperRuleKeepsResistingCompression) {
  const MohrCoulomb m = soil(0.0, TensionRule::Paper, TensionSelection::Paper);
  Voigt<2> sig = Voigt<2>::Zero();
  Voigt<2> d;
  d << 1e-4, -1e-4, 0.0, 0.0;
  PlasticPoint st;
  for (int n = 0; n < 10; ++n) m.update<2>(sig, d, st);
  // Each step adds 2G 1e-4 to s_xx (released to 0 again) and -2G 1e-4 to s_yy (kept); the point
  // stays inside the shear surface, so s_yy = -10 2G 1e-4. The reset would leave -2G 1e-4.
  EXPECT_NEAR(sig[1], -10 * 2 * m.elastic.G * 1e-4, 1e-9 * kPa);
  EXPECT_EQ(sig[0], 0.0);
  EXPECT_NEAR(st.plastic_volume, 10 * 2 * m.elastic.G * 1e-4 / (3 * m.elastic.K), 1e-12);
}

// The paper's selection: a point beyond both surfaces with s3 > sigma_t is released in tension
// even where FLAC's h-function says shear. There (h <= 0) the released stress is still beyond the
// shear surface, so both end on it, but only the released one has opened (plastic volume > 0).
TEST(MohrCoulomb, TensionSelectionPaperReleasesEveryPointAboveSigmaT) {
  const MohrCoulomb flac = soil(0.0, TensionRule::Flac, TensionSelection::Flac);
  const MohrCoulomb paper = soil(0.0, TensionRule::Paper, TensionSelection::Paper);
  Voigt<2> trial;
  trial << 0.5 * kPa, -60 * kPa, -20 * kPa, 0.0;  // s3 just above 0, deep beyond the shear surface
  Voigt<2> a = trial, b = trial;
  PlasticPoint sa, sb;
  EXPECT_EQ(flac.correct<2>(a, flac.strength(), sa), YieldMode::Shear);
  EXPECT_EQ(paper.correct<2>(b, paper.strength(), sb), YieldMode::Shear);  // ends on the shear surface
  for (const Voigt<2>& v : {a, b})
    EXPECT_NEAR(MohrCoulomb::shear_yield(PrincipalFrame<2>(v).values, paper.strength()), 0.0, 1e-9 * kPa);
  EXPECT_NEAR(sa.plastic_volume, 0.0, 1e-15);
  EXPECT_NEAR(sb.plastic_volume, 0.5 * kPa / (3 * paper.elastic.K), 1e-12);  // the released 0.5 kPa
}

TEST(MohrCoulomb, ObjectiveUnderRotation) {
  const MohrCoulomb m = soil(10.0);
  const Mat3 R = Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -1, 2).normalized()).toRotationMatrix();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 200; ++k) {
    Voigt<3> sig, d;
    sig << -60 * kPa + 20 * kPa * u(rng), -50 * kPa + 20 * kPa * u(rng), -40 * kPa, 5 * kPa * u(rng), 0, 0;
    d << 1e-3 * u(rng), 1e-3 * u(rng), 1e-3 * u(rng), 1e-3 * u(rng), 1e-3 * u(rng), 1e-3 * u(rng);
    Voigt<3> a = sig;
    PlasticPoint s1, s2;
    m.update<3>(a, d, s1);
    Voigt<3> b = to_voigt<3>(R * to_matrix<3>(sig) * R.transpose());
    m.update<3>(b, to_voigt<3>(R * to_matrix<3>(d) * R.transpose()), s2);
    const Mat3 diff = R * to_matrix<3>(a) * R.transpose() - to_matrix<3>(b);
    ASSERT_LT(diff.cwiseAbs().maxCoeff(), 1e-10 * 100 * kPa) << "k = " << k;
    EXPECT_EQ(s1.mode, s2.mode);
  }
}

TEST(MohrCoulomb, ElasticStateIsLeftUntouched) {
  const MohrCoulomb m = soil();
  Voigt<2> sig;
  sig << -50 * kPa, -60 * kPa, -55 * kPa, 3 * kPa;
  const Voigt<2> before = sig;
  PlasticPoint st;
  EXPECT_EQ(m.correct<2>(sig, m.strength(), st), YieldMode::Elastic);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(sig[i], before[i]);
}

// The 3D pre-check from the invariants (MohrCoulomb::surely_elastic) skips the principal frame only
// for stresses the frame's values also find inside both surfaces: over 200,000 random stresses in
// random orientations, from deep inside to far outside, for three strengths, not one is passed that
// yields, and correct() leaves every passed stress untouched. It is not empty either: an isotropic
// stress is decided exactly (its bounds are exact), and of the random stresses inside by more than
// a quarter of the shear room most pass.
TEST(MohrCoulomb, InvariantPreCheckPassesNoYieldingStress) {
  std::mt19937 rng(2026);
  std::uniform_real_distribution<double> mean(-400 * kPa, 20 * kPa), unit(-1.0, 1.0), size(0.0, 1.0);
  for (auto [phi, c, t] : {std::tuple{30.5, 8.5, 0.0}, std::tuple{40.0, 0.0, 0.0}, std::tuple{20.0, 30.0, 4.0}}) {
    MohrCoulomb m = soil();
    m.phi = deg(phi), m.cohesion = c * kPa, m.tension = t * kPa;
    const auto s = m.strength();
    int passed = 0, deep = 0, deep_passed = 0;
    for (int k = 0; k < 200000; ++k) {
      // Principal values about a mean, with a deviator up to 1.5 times the shear strength there.
      const double sm = mean(rng);
      const double room = std::max(0.0, sm * (1 - s.N_phi) + 2 * s.c * s.sqrt_N_phi) / (1 + s.N_phi);
      Eigen::Vector3d dev(unit(rng), unit(rng), unit(rng));
      dev.array() -= dev.mean();
      if (dev.norm() > 0) dev *= 1.5 * room * size(rng) / dev.norm();
      const Eigen::Quaterniond q(Eigen::Vector4d(unit(rng), unit(rng), unit(rng), unit(rng)).normalized());
      const Mat3 R = q.toRotationMatrix();
      const Voigt<3> sig = to_voigt<3>(R * (dev.array() + sm).matrix().asDiagonal() * R.transpose());
      const Eigen::Vector3d p = PrincipalFrame<3>(sig).values;
      const double f_s = MohrCoulomb::shear_yield(p, s), f_t = s.sigma_t - p[2];
      const bool sure = MohrCoulomb::surely_elastic(sig, s);
      if (sure) {
        ++passed;
        ASSERT_GE(f_s, 0.0) << "k = " << k;
        ASSERT_GE(f_t, 0.0) << "k = " << k;
        Voigt<3> after = sig;
        PlasticPoint st;
        ASSERT_EQ(m.correct<3>(after, s, st), YieldMode::Elastic);
        ASSERT_EQ(after, sig);
      }
      if (f_s > 0.25 * 2 * s.c * s.sqrt_N_phi + 0.25 * std::abs(sm) * (s.N_phi - 1) && f_t > 0.25 * std::abs(sm)) {
        ++deep;
        deep_passed += sure;
      }
    }
    EXPECT_GT(passed, 20000) << "phi = " << phi;
    EXPECT_GT(deep_passed, deep / 2) << "phi = " << phi << ": " << deep_passed << " of " << deep;
    // Isotropic stresses: passed exactly where they are inside, up to the 1e-12 margin.
    const double apex = s.N_phi > 1 ? 2 * s.c * s.sqrt_N_phi / (s.N_phi - 1) : 0.0;  // f_s = 0 there
    const double corner = std::min(apex, s.sigma_t);
    for (double x : {-1e6, -1e4, -1.0}) {
      Voigt<3> iso;
      iso << corner + x, corner + x, corner + x, 0, 0, 0;
      EXPECT_TRUE(MohrCoulomb::surely_elastic(iso, s)) << "phi = " << phi << ", " << x << " Pa inside";
      iso.head<3>().setConstant(corner + 1e-3);
      EXPECT_FALSE(MohrCoulomb::surely_elastic(iso, s)) << "phi = " << phi << ", 1e-3 Pa outside";
    }
  }
}

// The plane-strain frame rebuilds the tensor exactly, also when sigma_zz ties an in-plane value.
TEST(PrincipalFrame, PlaneRebuildIsExact) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 1000; ++k) {
    Voigt<2> t;
    t << u(rng), u(rng), u(rng), u(rng);
    if (k % 3 == 0) t[2] = 0.5 * (t[0] + t[1]) + std::hypot(0.5 * (t[0] - t[1]), t[3]);
    const PrincipalFrame<2> f(t);
    EXPECT_LE(f.values[0], f.values[1]);
    EXPECT_LE(f.values[1], f.values[2]);
    const Voigt<2> back = f.rebuild(f.values);
    for (int i = 0; i < 4; ++i) ASSERT_NEAR(back[i], t[i], 1e-14);
  }
}

}  // namespace
