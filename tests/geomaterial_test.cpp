// Geomaterial set-up through the input file and the solver: a confining initial stress held by
// eq (2), the K0 profile, the seeded strength imperfection, and the input checks of issue 3.
#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/model/model.hpp"
#include "tsuchi/run/simulation.hpp"

#include <fmt/format.h>
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

namespace {

using namespace tsuchi::test;

using namespace tsuchi;

// The paper's soil (test 3 moduli) as a free block without gravity, under an isotropic 100 kPa.
const std::string kBlock = R"([model]
dimension = 2

[grid]
origin = [0.0, 0.0]
extent = [0.2, 0.2]
cell_size = 0.01

[[materials]]
name = "soil"
model = "mohr_coulomb"
density = 1530.0
shear_modulus = 8.514e6
poisson_ratio = 0.2
cohesion = 8.5e3
friction_angle = 30.5
dilatancy_angle = 0.0
tension_strength = 0.0

[[bodies]]
name = "specimen"
material = "soil"
min = [0.05, 0.05]
max = [0.15, 0.15]
particles_per_cell = 2

[bodies.initial_stress]
isotropic = -100.0e3
subtract = true

[time]
end = 1.0
courant = 0.5
max_steps = 1000

[output]
frames = false
)";

Config config(const std::string& text, const std::vector<std::string>& overrides = {}) {
  return read_config_string(text, "case.toml", overrides);
}

double largest_displacement(const Model<2>& m) {
  double u = 0.0;
  for (const auto& v : m.particles.u_p) u = std::max(u, v.norm());
  return u;
}

TEST(Geomaterial, ConfinedBlockStaysAtRestUnderItsInitialStress) {
  const Config c = config(kBlock);
  Model<2> m = build_model<2>(c);
  const auto s = run_simulation<2>(m, c, no_output());
  EXPECT_EQ(s.steps, 1000);
  EXPECT_LT(largest_displacement(m), 1e-9);
  std::printf("confined block: largest displacement %.3e m after %lld steps\n", largest_displacement(m), static_cast<long long>(s.steps));
  for (const auto& sig : m.particles.sigma_p) {
    ASSERT_NEAR(sig[0], -100e3, 1e-6);
    ASSERT_NEAR(sig[1], -100e3, 1e-6);
    ASSERT_NEAR(sig[2], -100e3, 1e-6);
  }
  for (double mode : *m.particles.state_column("yield_mode")) ASSERT_EQ(mode, 0.0);

  // The same block without eq (2) is pushed apart by its own stress: the check above can fail.
  const Config lc = config(kBlock, {"bodies.0.initial_stress.subtract=false", "time.max_steps=100"});
  Model<2> loose = build_model<2>(lc);
  run_simulation<2>(loose, lc, no_output());
  EXPECT_GT(largest_displacement(loose), 1e-5);
}

TEST(Geomaterial, K0ProfileFollowsDepth) {
  std::string text = replace(kBlock, "[model]\ndimension = 2\n", "[model]\ndimension = 2\ngravity = [0.0, -9.81]\n");
  text = replace(text, "isotropic = -100.0e3\nsubtract = true", "k0 = 0.5\nsurface_stress = -2.0e3");
  const Model<2> m = build_model<2>(config(text));
  const double rho = 1530.0, g = 9.81, top = 0.15;
  for (std::size_t i = 0; i < m.particles.size(); ++i) {
    const auto& sig = m.particles.sigma_p[i];
    const double sv = -2.0e3 - rho * g * (top - m.particles.x_p[i][1]);
    ASSERT_NEAR(sig[1], sv, 1e-9 * std::abs(sv));
    ASSERT_NEAR(sig[0], 0.5 * sv, 1e-9 * std::abs(sv));
    ASSERT_NEAR(sig[2], 0.5 * sv, 1e-9 * std::abs(sv));
    ASSERT_EQ(sig[3], 0.0);
  }
  // Not subtracted (gravity carries it): the model holds no sigma0 at all, and the internal force
  // acts with the whole stress.
  EXPECT_FALSE(m.particles.initial_stress);
  EXPECT_TRUE(m.particles.sigma0_p.empty());
  for (std::size_t i = 0; i < m.particles.size(); ++i)
    ASSERT_EQ(m.particles.stress_above_initial(i), m.particles.sigma_p[i]);
}

// With the subtraction, every particle holds sigma0 = its starting stress, and eq (2) starts from
// zero: sigma - sigma0 = 0.
TEST(Geomaterial, SubtractedInitialStressIsHeldPerParticle) {
  const Model<2> m = build_model<2>(config(kBlock));
  ASSERT_TRUE(m.particles.initial_stress);
  ASSERT_EQ(m.particles.sigma0_p.size(), m.particles.size());
  for (std::size_t i = 0; i < m.particles.size(); ++i) {
    ASSERT_EQ(m.particles.sigma0_p[i][0], -100.0e3);
    ASSERT_EQ(m.particles.stress_above_initial(i).norm(), 0.0);
  }
}

std::vector<double> factors(const std::vector<std::string>& overrides) {
  const std::string text = replace(kBlock, "[time]", "[bodies.imperfection]\namplitude = 0.05\nseed = 7\n\n[time]");
  const Model<2> m = build_model<2>(config(text, overrides));
  std::vector<double> f = *m.particles.state_column("cohesion_factor");
  const auto& phi = *m.particles.state_column("friction_factor");
  f.insert(f.end(), phi.begin(), phi.end());
  return f;
}

TEST(Geomaterial, ImperfectionIsSeededAndBounded) {
  const std::vector<double> a = factors({}), b = factors({}), c = factors({"bodies.0.imperfection.seed=8"});
  ASSERT_EQ(a.size(), 2 * 400u);
  EXPECT_EQ(a, b) << "same seed, same field, bit for bit";
  EXPECT_NE(a, c);
  double mean = 0.0, var = 0.0;
  for (double f : a) {
    ASSERT_GE(f, 0.95);
    ASSERT_LE(f, 1.05);
    mean += f / static_cast<double>(a.size());
  }
  for (double f : a) var += (f - mean) * (f - mean) / static_cast<double>(a.size());
  // Uniform on [-a, a]: mean 0, standard deviation a / sqrt(3) = 0.0289; 800 draws.
  EXPECT_NEAR(mean, 1.0, 4 * 0.0289 / std::sqrt(800.0));
  EXPECT_NEAR(std::sqrt(var), 0.05 / std::sqrt(3.0), 0.1 * 0.05 / std::sqrt(3.0));

  const std::vector<double> only_c = factors({"bodies.0.imperfection.parameters=[\"cohesion\"]"});
  double spread = 0.0;
  for (std::size_t i = 0; i < 400; ++i) spread = std::max(spread, std::abs(only_c[i] - 1.0));
  for (std::size_t i = 400; i < 800; ++i) ASSERT_EQ(only_c[i], 1.0);
  EXPECT_GT(spread, 0.04);
}

TEST(Geomaterial, TensionStrengthIsCappedAtTheApex) {
  const Config c = config(kBlock, {"materials.0.tension_strength=1e9"});
  const auto& mc = std::get<MohrCoulomb>(c.materials[0].model);
  EXPECT_NEAR(mc.tension, 8.5e3 / std::tan(30.5 * std::numbers::pi / 180.0), 1e-9);
}

// Bad geomaterial input: each refused with the key named.
struct BadCase {
  std::vector<std::string> overrides;
  const char* key;
  const char* words;
};

TEST(Geomaterial, BadInputNamesTheKey) {
  const BadCase cases[] = {
      {{"materials.0.friction_angle=95"}, "materials.0.friction_angle", "[0, 90)"},
      {{"materials.0.friction_angle=-1"}, "materials.0.friction_angle", "[0, 90)"},
      {{"materials.0.dilatancy_angle=31"}, "materials.0.dilatancy_angle", "no larger than the friction angle"},
      {{"materials.0.cohesion=-1"}, "materials.0.cohesion", ">= 0"},
      {{"materials.0.tension_strength=-1"}, "materials.0.tension_strength", ">= 0"},
      {{"materials.0.poisson_ratio=0.5"}, "materials.0.poisson_ratio", "(-1, 0.5)"},
      {{"materials.0.shear_modulus=0"}, "materials.0.shear_modulus", "positive"},
      {{"materials.0.density=-1"}, "materials.0.density", "positive"},
      {{"materials.0.tension_rule=\"rankine\""}, "materials.0.tension_rule", "\"paper\""},
      {{"bodies.0.initial_stress.k0=0.5"}, "bodies.0.initial_stress", "exactly one of"},
      {{"bodies.0.initial_stress.surface=0.1"}, "bodies.0.initial_stress.surface", "only to a 'k0'"},
      {{"bodies.0.initial_stress.isotropic=\"high\""}, "bodies.0.initial_stress.isotropic", "Pa"},
      {{"bodies.0.imperfection.amplitude=0.01"}, "bodies.0.imperfection.seed", "seed"},
      {{"bodies.0.imperfection.amplitude=1.5", "bodies.0.imperfection.seed=1"}, "bodies.0.imperfection.amplitude", "[0, 1)"},
      {{"bodies.0.imperfection.amplitude=0.01", "bodies.0.imperfection.seed=1", "bodies.0.imperfection.parameters=[\"young\"]"},
       "bodies.0.imperfection.parameters", "\"friction_angle\""},
  };
  for (const auto& bc : cases) {
    try {
      config(kBlock, bc.overrides);
      ADD_FAILURE() << bc.overrides.back() << " was accepted";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(bc.key), std::string::npos) << bc.overrides.back() << ": " << msg;
      EXPECT_NE(msg.find(bc.words), std::string::npos) << bc.overrides.back() << ": " << msg;
      EXPECT_NE(msg.find("case.toml"), std::string::npos) << msg;
    }
  }
}

TEST(Geomaterial, ImperfectionNeedsAMohrCoulombMaterial) {
  std::string text = replace(kBlock, "model = \"mohr_coulomb\"", "model = \"linear_elastic\"");
  text = replace(text, "cohesion = 8.5e3\nfriction_angle = 30.5\ndilatancy_angle = 0.0\ntension_strength = 0.0\n", "");
  try {
    config(text, {"bodies.0.imperfection.amplitude=0.01", "bodies.0.imperfection.seed=1"});
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies.0.imperfection"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("mohr_coulomb"), std::string::npos) << e.what();
  }
}

TEST(Geomaterial, InitialStressOutsideTheYieldSurfaceIsRefused) {
  // 10 kPa of tension with sigma_t = 0, and a deviator beyond the Mohr-Coulomb strength.
  for (const char* o : {"bodies.0.initial_stress.isotropic=10e3", "bodies.0.initial_stress.tensor=[-10e3, -200e3, -10e3, 0]"}) {
    std::vector<std::string> ov{o};
    if (std::string(o).find("tensor") != std::string::npos) {
      const std::string text = replace(kBlock, "isotropic = -100.0e3\n", "");
      try {
        build_model<2>(config(text, ov));
        ADD_FAILURE() << o << " accepted";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("Mohr-Coulomb shear"), std::string::npos) << e.what();
      }
      continue;
    }
    try {
      build_model<2>(config(kBlock, ov));
      ADD_FAILURE() << o << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("bodies.0.initial_stress"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("tension cut-off"), std::string::npos) << e.what();
    }
  }
}

}  // namespace

// Plane-strain compression through the whole solver: every particle's vertical velocity is
// prescribed as -rate * y (a homogeneous axial strain rate), the sides are free, and the
// confining pressure is the initial stress held by eq (2). The lateral strain comes out of the
// grid momentum balance, so the plateau of q = -<sigma_yy> - p tests the return, eq (2) and the
// solver together against p (N_phi - 1) + 2 c sqrt(N_phi).
// The averages are over the whole specimen, as a lab measures forces. The top two cells'
// particles are left out of the per-particle checks: the upper nodes are half-supported, so the
// projected velocity there is not the prescribed linear field and the top cell sees a different
// strain, which the node-averaged volumetric strain (solver.anti_locking = "node") carries one
// cell further down.
TEST(Geomaterial, PlaneStrainCompressionThroughTheSolverReachesMohrCoulombStrength) {
  std::string text = replace(kBlock, "extent = [0.2, 0.2]\ncell_size = 0.01", "extent = [0.1, 0.12]\ncell_size = 0.005");
  text = replace(text, "min = [0.05, 0.05]\nmax = [0.15, 0.15]",
                 "min = [0.025, 0.0]\nmax = [0.075, 0.1]\n"
                 "prescribed_velocity = { y = 0.0 }\nprescribed_velocity_gradient = { y = [0.0, -0.2] }");
  text = replace(text, "end = 1.0\ncourant = 0.5\nmax_steps = 1000", "end = 0.15\ncourant = 0.5");
  const double G[] = {1311e3, 6401e3, 8514e3}, P[] = {10e3, 50e3, 100e3};
  for (int t = 0; t < 3; ++t) {
    const Config c = config(text, {fmt::format("materials.0.shear_modulus={}", G[t]),
                                   fmt::format("bodies.0.initial_stress.isotropic={}", -P[t])});
    Model<2> m = build_model<2>(c);
    const auto& p = m.particles;
    std::vector<char> inner(p.size(), 0);  // by id: the solver reorders particles in memory
    std::size_t n_inner = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.x_p[i][1] < 0.09) inner[p.id_p[i]] = 1, ++n_inner;
    double q_peak = 0.0, q_end = 0.0, sxx_err = 0.0;
    run_simulation<2>(m, c, no_output(), [&](const ExplicitSolver<2>&) {
      double syy = 0.0, sxx = 0.0;
      for (const auto& sig : p.sigma_p) syy += sig[1], sxx += sig[0];
      const double n = static_cast<double>(p.size());
      q_end = -syy / n - P[t];
      q_peak = std::max(q_peak, q_end);
      sxx_err = std::max(sxx_err, std::abs(sxx / n + P[t]));
    });
    const double q_mc = mohr_coulomb_peak(P[t]);
    std::printf("p = %3.0f kPa: solver peak q %.3f kPa (%+.2f %%), at 15 %% strain %.3f kPa (%+.2f %%), Mohr-Coulomb %.3f "
                "kPa; mean sigma_xx off by at most %.3f kPa\n",
                P[t] / 1e3, q_peak / 1e3, 100 * (q_peak / q_mc - 1), q_end / 1e3, 100 * (q_end / q_mc - 1), q_mc / 1e3,
                sxx_err / 1e3);
    EXPECT_NEAR(q_peak, q_mc, 0.005 * q_mc);
    EXPECT_NEAR(q_end, q_mc, 0.01 * q_mc);
    EXPECT_LT(sxx_err, 0.01 * P[t]);
    double plastic_volume = 0.0;
    std::size_t shear = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (!inner[p.id_p[i]]) continue;
      plastic_volume = std::max(plastic_volume, std::abs((*p.state_column("plastic_volumetric_strain"))[i]));
      shear += (*p.state_column("yield_mode"))[i] == static_cast<double>(YieldMode::Shear);
    }
    EXPECT_LT(plastic_volume, 1e-12) << "psi = 0";
    // Every particle flows in shear at 15 % strain, but for a few at the free sides' corners
    // (2 of 720 with the node-averaged volumetric strain: their own strain, from half-supported
    // nodes, differs and the average carries it to a neighbour, which unloads elastically).
    EXPECT_GE(static_cast<double>(shear), 0.99 * static_cast<double>(n_inner)) << "particles flowing in shear at 15 % strain";
  }
}
