// Modified Cam-Clay (docs/materials.md "Modified Cam-Clay") at the level of one material point,
// through the element driver, against the closed forms of critical-state soil mechanics (Wood
// 1990, "Soil behaviour and critical state soil mechanics", ch. 6 and 7), and through the solver
// on a small homogeneous block.
#include "tsuchi/element/element_driver.hpp"
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/io/element_reader.hpp"
#include "tsuchi/material/material.hpp"
#include "tsuchi/model/model.hpp"
#include "tsuchi/run/simulation.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace tsuchi;
using element::Control;
using element::ElementPath;
using element::ElementRow;
using element::Segment;

constexpr double kPa = 1e3;

// A lightly plastic clay: lambda = 0.2, kappa = 0.04 (Lambda = 0.8), M = 1.2, e0 = 1 (v0 = 2),
// nu = 0.3; normally consolidated unless told otherwise.
ModifiedCamClay clay(double ocr = 1.0) {
  ModifiedCamClay m;
  m.lambda = 0.2;
  m.kappa = 0.04;
  m.M = 1.2;
  m.v0 = 2.0;
  m.ocr = ocr;
  m.poisson = 0.3;
  return m;
}

Material material(const ModifiedCamClay& m) { return {"clay", 1800.0, m}; }

ElementPath isotropic_start(double p0) {
  ElementPath path;
  path.kind = "general";
  path.initial_stress << -p0, -p0, -p0, 0, 0, 0;
  return path;
}

// Undrained triaxial compression (volume held): eps_yy = -e, eps_xx = eps_zz = +e/2, all driven.
ElementPath undrained(double p0, double e, int n) {
  ElementPath path = isotropic_start(p0);
  Segment s;
  s.increments = n;
  s.control[0].value = s.control[2].value = e / 2;
  s.control[1].value = -e;
  path.segments.push_back(s);
  return path;
}

// Drained triaxial compression: eps_yy = -e driven, sigma_xx and sigma_zz held.
ElementPath drained(double p0, double e, int n) {
  ElementPath path = isotropic_start(p0);
  Segment s;
  s.increments = n;
  s.control[1].value = -e;
  s.control[0].kind = s.control[2].kind = Control::StressHold;
  path.segments.push_back(s);
  return path;
}

std::vector<ElementRow> drive(const ModifiedCamClay& m, const ElementPath& path) {
  return element::drive_element(material(m), path);
}

// The critical state of undrained compression from p0 on the NCL: with v constant the elastic and
// plastic volume changes cancel, kappa ln(p/p0) + (lambda - kappa) ln(p_c/p0) = 0, and p_c = 2p
// at critical state: p_f = p0 / 2^Lambda, Lambda = (lambda - kappa) / lambda (Wood 1990, 7.2).
TEST(ModifiedCamClay, UndrainedNormallyConsolidatedEndsAtTheCriticalState) {
  const ModifiedCamClay m = clay();
  const double p0 = 200 * kPa;
  const double Lambda = (m.lambda - m.kappa) / m.lambda, p_f = p0 / std::pow(2.0, Lambda), q_f = m.M * p_f;
  double ends[2][2];
  int k = 0;
  for (int n : {100, 1000}) {
    const auto rows = drive(m, undrained(p0, 0.3, n));
    const ElementRow& end = rows.back();
    std::printf("undrained NC, %4d increments to 30 %%: p' = %.6f kPa (closed form %.6f, %+.2e), q = %.6f kPa "
                "(%.6f, %+.2e)\n",
                n, end.p() / kPa, p_f / kPa, end.p() / p_f - 1, end.q() / kPa, q_f / kPa, end.q() / q_f - 1);
    EXPECT_NEAR(end.p(), p_f, 0.005 * p_f);
    EXPECT_NEAR(end.q(), q_f, 0.005 * q_f);
    EXPECT_LT(std::abs(end.eps_v()), 1e-15);
    // Normally consolidated: p' only falls.
    for (std::size_t i = 1; i < rows.size(); ++i) ASSERT_LE(rows[i].p(), rows[i - 1].p() * (1 + 1e-12)) << i;
    ends[k][0] = end.p(), ends[k][1] = end.q(), ++k;
  }
  // The end state does not depend on the increment size (the return is implicit, v constant).
  std::printf("100 vs 1000 increments: p' differs by %.2e, q by %.2e (relative)\n", ends[0][0] / ends[1][0] - 1,
              ends[0][1] / ends[1][1] - 1);
  EXPECT_NEAR(ends[0][0], ends[1][0], 1e-6 * ends[1][0]);
  EXPECT_NEAR(ends[0][1], ends[1][1], 1e-6 * ends[1][1]);
}

// Part of the path too: at 1 % axial strain (G explicit in a step) 100 and 1000 increments agree.
TEST(ModifiedCamClay, UndrainedPathConvergesWithIncrementSize) {
  const ModifiedCamClay m = clay();
  const auto coarse = drive(m, undrained(200 * kPa, 0.01, 10)), fine = drive(m, undrained(200 * kPa, 0.01, 1000));
  const double dq = coarse.back().q() / fine.back().q() - 1, dp = coarse.back().p() / fine.back().p() - 1;
  std::printf("undrained NC to 1 %%: 10 vs 1000 increments: q %+.2e, p' %+.2e (relative)\n", dq, dp);
  EXPECT_LT(std::abs(dq), 0.01);
  EXPECT_LT(std::abs(dp), 0.01);
}

// Drained: the lateral stress held makes dq/dp' = 3, and the path ends on q = M p'.
TEST(ModifiedCamClay, DrainedNormallyConsolidatedFollowsThe3To1LineToTheCriticalState) {
  const ModifiedCamClay m = clay();
  const double p0 = 200 * kPa;
  const auto rows = drive(m, drained(p0, 0.8, 4000));
  double worst = 0;
  for (const auto& r : rows)
    if (r.q() > 0) worst = std::max(worst, std::abs((r.p() - p0) * 3 / r.q() - 1));
  const ElementRow& end = rows.back();
  const double p_cs = p0 / (1 - m.M / 3);  // where the 3:1 line meets q = M p'
  std::printf("drained NC to 80 %%: dq/dp' = 3 within %.1e; q/(M p') = %.5f, p' = %.3f kPa (critical state on the 3:1 "
              "line %.3f); eps_v = %.4f\n",
              worst, end.q() / (m.M * end.p()), end.p() / kPa, p_cs / kPa, end.eps_v());
  EXPECT_LT(worst, 1e-6);
  EXPECT_NEAR(end.q(), m.M * end.p(), 0.005 * m.M * end.p());
  EXPECT_GT(end.eps_v(), 0.0);  // compression
}

// The start hook: p_c = OCR p_y (p_y the isotropic pressure of the ellipse through the starting
// stress), v = v0, K = v0 p / kappa; a p_c already set (a particle file's column) is kept.
TEST(ModifiedCamClay, StartSetsTheStateFromTheStartingStress) {
  const ModifiedCamClay m = clay(2.0);
  const double p = 100 * kPa, q = 60 * kPa;
  const Eigen::Vector3d principal(-p - 2 * q / 3, -p + q / 3, -p + q / 3);  // triaxial compression
  PointStateOf<ModifiedCamClay> st;
  m.start(principal, st.ref());
  EXPECT_NEAR(st.field("preconsolidation_pressure"), 2.0 * (p + q * q / (m.M * m.M * p)), 1e-9 * p);
  EXPECT_EQ(st.field("specific_volume"), 2.0);
  EXPECT_NEAR(st.field("bulk_modulus"), 2.0 * p / m.kappa, 1e-9 * p);
  EXPECT_NEAR(m.stiffness(st.ref()).G, 3 * 2.0 * p / m.kappa * 0.4 / 2.6, 1e-6 * p);
  PointStateOf<ModifiedCamClay> given;
  given.ref()[ModifiedCamClay::kPreconsolidation] = 345 * kPa;
  m.start(principal, given.ref());
  EXPECT_EQ(given.field("preconsolidation_pressure"), 345 * kPa);
  // Through the element driver (which calls the hook): the first row carries the started state.
  const auto rows = drive(clay(8.0), undrained(p, 0.001, 1));
  EXPECT_NEAR(rows.front().state_value("preconsolidation_pressure"), 8 * p, 1e-9 * p);
  EXPECT_NEAR(rows.front().state_value("bulk_modulus"), 2.0 * p / m.kappa, 1e-9 * p);
}

// Over-consolidation: lightly (OCR 1.5) contracts, heavily (OCR 8) dilates (Wood 1990, 7.3-7.4).
TEST(ModifiedCamClay, LightlyOverconsolidatedContractsHeavilyOverconsolidatedDilates) {
  const double p0 = 100 * kPa;
  {
    const auto d = drive(clay(1.5), drained(p0, 0.4, 2000));
    const auto u = drive(clay(1.5), undrained(p0, 0.3, 1000));
    std::printf("OCR 1.5: drained eps_v at 40 %% = %+.4f (compression positive); undrained p' %.2f -> %.2f kPa\n",
                d.back().eps_v(), p0 / kPa, u.back().p() / kPa);
    EXPECT_GT(d.back().eps_v(), 0.01);
    EXPECT_LT(u.back().p(), 0.95 * p0);
    // Undrained critical state: the same kappa/lambda balance from p_c = 1.5 p0.
    const double p_f = p0 * std::pow(1.5 / 2.0, 0.8);
    EXPECT_NEAR(u.back().p(), p_f, 0.005 * p_f);
  }
  {
    const ModifiedCamClay m = clay(8.0);
    const auto d = drive(m, drained(p0, 0.6, 3000));
    const auto u = drive(m, undrained(p0, 0.3, 1000));
    double q_peak = 0, eps_v_min = 0;
    std::size_t i_peak = 0;
    for (std::size_t i = 0; i < d.size(); ++i) {
      if (d[i].q() > q_peak) q_peak = d[i].q(), i_peak = i;
      eps_v_min = std::min(eps_v_min, d[i].eps_v());
    }
    const ElementRow& end = d.back();
    std::printf("OCR 8: drained peak q = %.3f kPa at %.2f %% axial strain, q at 60 %% = %.3f kPa (q/(M p') = %.4f), "
                "eps_v at 60 %% = %+.4f; undrained p' %.2f -> %.2f kPa\n",
                q_peak / kPa, -100 * d[i_peak].strain[1], end.q() / kPa, end.q() / (m.M * end.p()), end.eps_v(),
                p0 / kPa, u.back().p() / kPa);
    EXPECT_LT(end.eps_v(), -0.01);                        // dilated
    EXPECT_GT(q_peak, 1.1 * end.q());                     // a peak, then softening ...
    EXPECT_NEAR(end.q(), m.M * end.p(), 0.02 * end.q());  // ... toward the critical state
    EXPECT_GT(u.back().p(), 1.2 * p0);                    // undrained: p' rises
    const double p_f = p0 * std::pow(8.0 / 2.0, 0.8);
    EXPECT_NEAR(u.back().p(), p_f, 0.005 * p_f);
  }
}

// Isotropic loading along the NCL: dv = -lambda d ln p', unloading dv = +kappa d ln p'. The
// specific volume is v0 exp(-eps_v), as the model books it.
TEST(ModifiedCamClay, IsotropicCompressionFollowsTheNclAndUnloadsAlongKappa) {
  const ModifiedCamClay m = clay();
  const double p0 = 100 * kPa;
  ElementPath path = isotropic_start(p0);
  for (double target : {2 * p0, p0}) {
    Segment s;
    s.increments = 200;
    for (int c = 0; c < 3; ++c) s.control[c] = {Control::StressTarget, -target};
    path.segments.push_back(s);
  }
  const Material mat = material(m);
  std::vector<double> v;
  double worst = 0;  // the model's v against v0 exp(-eps_v) of the summed strain
  for (const auto& r : element::drive_element(mat, path)) {
    v.push_back(r.state_value("specific_volume"));
    worst = std::max(worst, std::abs(v.back() / (m.v0 * std::exp(-r.eps_v())) - 1));
  }
  EXPECT_LT(worst, 1e-13);
  const double dv_load = v[200] - v[0], dv_unload = v[400] - v[200];
  std::printf("isotropic 100 -> 200 kPa: dv = %.6f (-lambda ln 2 = %.6f); back to 100 kPa: dv = %.6f (kappa ln 2 = %.6f)\n",
              dv_load, -m.lambda * std::log(2.0), dv_unload, m.kappa * std::log(2.0));
  EXPECT_NEAR(dv_load, -m.lambda * std::log(2.0), 0.005 * m.lambda * std::log(2.0));
  EXPECT_NEAR(dv_unload, m.kappa * std::log(2.0), 0.005 * m.kappa * std::log(2.0));
}

// Random trial stresses return onto the ellipse (converged, not merely reduced), objectively, and
// p_c follows the hardening law exactly for the plastic volumetric strain booked.
TEST(ModifiedCamClay, ReturnIsConvergedObjectiveAndHardensExactly) {
  std::mt19937 rng(18);
  std::uniform_real_distribution<double> u(-1, 1);
  int yielded = 0, released = 0;
  double worst_f = 0, worst_rot = 0, worst_pc = 0;
  for (int k = 0; k < 20000; ++k) {
    ModifiedCamClay m = clay(k % 4 == 0 ? 8.0 : 1.0 + 0.5 * (1 + u(rng)));
    if (k % 2) m.shear_modulus = 5e6;  // the constant-G variant too
    const double p0 = 150 * kPa * (1 + u(rng));
    Voigt<3> sig;
    sig << -p0, -p0, -p0, 0, 0, 0;
    for (int i = 3; i < 6; ++i) sig[i] = 0.2 * p0 * u(rng);
    PointStateOf<ModifiedCamClay> st;
    m.start(PrincipalFrame<3>(sig).values, st.ref());
    if (m.outside(PrincipalFrame<3>(sig).values, st.ref()).any()) continue;
    Voigt<3> d;
    const double size = k % 3 == 0 ? 0.2 : 0.01;
    for (int i = 0; i < 6; ++i) d[i] = size * u(rng);
    // The same point rotated by a random R: trial and result rotate together.
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(3 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
    Voigt<3> sig_r = to_voigt<3>(R * to_matrix<3>(sig) * R.transpose());
    const Voigt<3> d_r = to_voigt<3>(R * to_matrix<3>(d) * R.transpose());
    PointStateOf<ModifiedCamClay> st_r = st;
    const double pc0 = st.field("preconsolidation_pressure"), v0 = st.field("specific_volume");
    m.update<3>(sig, d, Mat<3>::Zero(), m.context(), st.ref());
    m.update<3>(sig_r, d_r, Mat<3>::Zero(), m.context(), st_r.ref());
    ASSERT_TRUE(sig.allFinite()) << k;
    const double scale = std::max(sig.cwiseAbs().maxCoeff(), 1.0);
    worst_rot = std::max(worst_rot, (to_voigt<3>(R * to_matrix<3>(sig) * R.transpose()) - sig_r).cwiseAbs().maxCoeff() / scale);
    const double mode = st.field("yield_mode");
    if (mode == 2) {
      ++released;
      EXPECT_EQ(sig, Voigt<3>::Zero());
      continue;
    }
    const double pc = st.field("preconsolidation_pressure");
    const double x = -st.field("plastic_volumetric_strain");  // compression positive
    worst_pc = std::max(worst_pc, std::abs(pc / (pc0 * std::exp(v0 * x / (m.lambda - m.kappa))) - 1));
    if (mode == 1) {
      ++yielded;
      const double p = -trace<3>(sig) / 3, q = von_mises<3>(sig);
      worst_f = std::max(worst_f, std::abs(q * q / (m.M * m.M) + p * (p - pc)) / (pc * pc));
    }
  }
  std::printf("%d returns, %d released: |f| / p_c^2 <= %.1e, rotated result off by %.1e, p_c off the hardening law by %.1e\n",
              yielded, released, worst_f, worst_rot, worst_pc);
  EXPECT_GT(yielded, 5000);
  EXPECT_LT(worst_f, 1e-9);
  EXPECT_LT(worst_rot, 1e-9);
  EXPECT_LT(worst_pc, 1e-12);
}

// No tensile strength: a point stretched from zero or small stress never becomes NaN, ends at or
// inside the ellipse with p' >= 0, and its time-step modulus stays at least v p_min / kappa.
TEST(ModifiedCamClay, ZeroStressAndTensionAreHandled) {
  const ModifiedCamClay m = clay();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  PointStateOf<ModifiedCamClay> st;
  Voigt<3> sig = Voigt<3>::Zero();
  m.start(Eigen::Vector3d::Zero(), st.ref());
  EXPECT_DOUBLE_EQ(st.field("preconsolidation_pressure"), m.p_min);  // OCR 1 x the floor
  for (int k = 0; k < 20000; ++k) {
    Voigt<3> d;
    for (int i = 0; i < 6; ++i) d[i] = 1e-3 * u(rng);
    m.update<3>(sig, d, Mat<3>::Zero(), m.context(), st.ref());
    ASSERT_TRUE(sig.allFinite()) << k;
    const double p = -trace<3>(sig) / 3, q = von_mises<3>(sig), pc = st.field("preconsolidation_pressure");
    ASSERT_GE(p, 0.0) << k;
    ASSERT_LE(q * q / (m.M * m.M) + p * (p - pc), 1e-9 * pc * pc) << k;
    ASSERT_GE(m.stiffness(st.ref()).K, st.field("specific_volume") * m.p_min / m.kappa * (1 - 1e-12)) << k;
  }
}

// The two element examples (examples/element_tests/modified_cam_clay_*.toml, their README), read
// and driven as `tsuchi element` does.
TEST(ModifiedCamClay, ElementExamplesReachTheirClosedForms) {
  const std::string dir = std::string(TSUCHI_SOURCE_DIR) + "/examples/element_tests/";
  {
    const io::ElementInput in = io::read_element_file(dir + "modified_cam_clay_undrained_nc.toml");
    const auto rows = element::drive_element(in.material, in.path, in.iteration);
    const double p_f = 200 * kPa / std::pow(2.0, 0.8);
    std::printf("example undrained NC: p' = %.4f kPa, q = %.4f kPa (closed form %.4f, %.4f)\n", rows.back().p() / kPa,
                rows.back().q() / kPa, p_f / kPa, 1.2 * p_f / kPa);
    EXPECT_NEAR(rows.back().p(), p_f, 0.005 * p_f);
    EXPECT_NEAR(rows.back().q(), 1.2 * p_f, 0.005 * 1.2 * p_f);
  }
  {
    const io::ElementInput in = io::read_element_file(dir + "modified_cam_clay_drained_ocr8.toml");
    const auto rows = element::drive_element(in.material, in.path, in.iteration);
    double q_peak = 0;
    for (const auto& r : rows) q_peak = std::max(q_peak, r.q());
    const ElementRow& end = rows.back();
    std::printf("example drained OCR 8: peak q = %.3f kPa, at the end q = %.3f kPa, q/(M p') = %.4f, eps_v = %+.4f\n",
                q_peak / kPa, end.q() / kPa, end.q() / (1.2 * end.p()), end.eps_v());
    EXPECT_GT(q_peak, 1.1 * end.q());
    EXPECT_NEAR(end.q(), 1.2 * end.p(), 0.02 * end.q());
    EXPECT_LT(end.eps_v(), 0.0);
  }
}

// Through the solver: a 2 x 2-cell plane-strain block squeezed at constant volume (prescribed
// velocities vx = +r x, vy = -r y) from an isotropic 200 kPa held by eq (2) follows the element
// driver's undrained plane-strain curve (eps_xx = -eps_yy, eps_zz = 0).
TEST(ModifiedCamClay, UndrainedBlockThroughTheSolverFollowsTheElementDriver) {
  const std::string text = test::kCamClayUndrainedBlock + R"(
[time]
end = 0.5
courant = 0.5

[output]
frames = false
)";
  const Config c = read_config_string(text, "block.toml");
  Model<2> model = build_model<2>(c);
  const auto& p = model.particles;
  struct Sample {
    double e, p, q;
  };
  std::vector<Sample> solver;
  double t = 0;
  run_simulation<2>(model, c, test::no_output(), [&](const ExplicitSolver<2>& s) {
    t = s.time();
    if (s.steps() % 25) return;
    Voigt<2> mean = Voigt<2>::Zero();
    for (const auto& sig : p.sigma_p) mean += sig;
    mean /= static_cast<double>(p.size());
    Voigt<3> s3;
    s3 << mean[0], mean[1], mean[2], mean[3], 0, 0;
    solver.push_back({0.1 * t, -trace<3>(s3) / 3, von_mises<3>(s3)});
  });
  ASSERT_GT(solver.size(), 10u);
  // The element driver along the same strains, eps_yy = -0.1 t (the velocity gradient is Eulerian
  // and constant: the summed strain rate).
  ElementPath path = isotropic_start(200 * kPa);
  Segment seg;
  seg.increments = 2000;
  seg.control[0].value = 0.05;
  seg.control[1].value = -0.05;
  path.segments.push_back(seg);
  const auto rows = element::drive_element(c.materials[0], path);
  double worst = 0;  // relative to the driver's final q
  for (const Sample& s : solver) {
    const double f = s.e / 0.05 * 2000;
    const auto i = static_cast<std::size_t>(std::min(f, 1999.0));
    const double w = std::min(f - static_cast<double>(i), 1.0);
    const double q = (1 - w) * rows[i].q() + w * rows[i + 1].q();
    worst = std::max(worst, std::abs(s.q - q) / rows.back().q());
  }
  const Sample& end = solver.back();
  std::printf("solver block, %zu samples to %.2f %% strain: q within %.2e of the element driver; at the end p' = %.3f kPa, "
              "q = %.3f kPa (driver %.3f, %.3f)\n",
              solver.size(), 100 * end.e, worst, end.p / kPa, end.q / kPa, rows.back().p() / kPa, rows.back().q() / kPa);
  EXPECT_LT(worst, 0.01);
}

}  // namespace
