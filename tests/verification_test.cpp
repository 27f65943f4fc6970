// Verification of the solver core against analytical solutions, running the real example inputs
// (examples/<case>/*.toml) through the full solver with output switched off.
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/model/model.hpp"
#include "tsuchi/solver/global_quantities.hpp"
#include "tsuchi/run/simulation.hpp"

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
using std::numbers::pi;

std::string example(const std::string& rel) { return std::string(TSUCHI_SOURCE_DIR) + "/examples/" + rel; }

// An example's input and the model built from it.
template <int D>
struct Loaded {
  Config c;
  Model<D> m;
};

template <int D>
Loaded<D> load(const std::string& rel, std::vector<std::string> overrides = {}) {
  overrides.push_back("output.frames=false");
  Config c = read_config_file(example(rel), overrides);
  Model<D> m = build_model<D>(c);
  return {std::move(c), std::move(m)};
}

// Simple shear of a hypoelastic block with the Jaumann rate, METHOD.md eq (23), to gamma = pi:
// tau_xy = G sin(gamma), sigma_xx = -sigma_yy = G (1 - cos(gamma)). Checked every 100 steps on
// the particles far from the block's edges (where the projected velocity field is exactly linear).
TEST(Verification, SimpleShearJaumannToGammaPi) {
  Loaded<2> run = load<2>("simple_shear/simple_shear.toml");
  Model<2>& m = run.m;
  const Config& c = run.c;
  const double G = std::get<LinearElastic>(m.materials[0].model).G;
  const double gamma_dot = c.bodies[0].prescribed_gradient[0][1];
  ASSERT_LE(gamma_dot * *c.time.dt, 1e-3);
  // By id: the solver reorders particles in memory as they move.
  std::vector<char> centre(m.particles.size(), 0);
  std::size_t n_centre = 0;
  for (std::size_t i = 0; i < m.particles.size(); ++i) {
    const auto& x = m.particles.x_p[i];
    if (x[0] > 1.0 && x[0] < 1.6 && x[1] > 0.4 && x[1] < 0.6) centre[m.particles.id_p[i]] = 1, ++n_centre;
  }
  ASSERT_GE(n_centre, 40u);
  double worst = 0.0, gamma_end = 0.0;
  run_simulation<2>(m, c, no_output(), [&](const ExplicitSolver<2>& s) {
    if (s.steps() % 100 != 0 && s.time() < c.time.end * (1 - 1e-12)) return;
    const double g = gamma_dot * s.time();
    gamma_end = g;
    for (std::size_t i = 0; i < m.particles.size(); ++i) {
      if (!centre[m.particles.id_p[i]]) continue;
      const auto& sig = m.particles.sigma_p[i];
      worst = std::max({worst, std::abs(sig[3] - G * std::sin(g)), std::abs(sig[0] - G * (1 - std::cos(g))),
                        std::abs(sig[1] + G * (1 - std::cos(g)))});
    }
  });
  EXPECT_NEAR(gamma_end, pi, 1e-9);
  EXPECT_LT(worst, 1e-3 * G) << "largest stress error over the path, in units of G: " << worst / G;
  std::printf("simple shear: largest error %.3e G up to gamma = %.4f\n", worst / G, gamma_end);
}

struct BarResult {
  double period = 0, amplitude = 0, energy_drift = 0;
};

// First-mode vibration of a fixed-free bar: centre-of-mass velocity v0 (2/pi) cos(2 pi t / T).
BarResult run_bar(std::vector<std::string> overrides) {
  Loaded<2> run = load<2>("bar_vibration/bar.toml", std::move(overrides));
  Model<2>& m = run.m;
  std::vector<double> t{0.0}, v;
  const auto q0 = global_quantities<2>(m);
  v.push_back(q0.momentum[0] / q0.mass);
  run_simulation<2>(m, run.c, no_output(), [&](const ExplicitSolver<2>& s) {
    const auto q = global_quantities<2>(s.model());
    t.push_back(s.time());
    v.push_back(q.momentum[0] / q.mass);
  });
  std::vector<double> zeros;
  for (std::size_t i = 1; i < v.size(); ++i)
    if (v[i - 1] * v[i] < 0) zeros.push_back(t[i - 1] + (t[i] - t[i - 1]) * v[i - 1] / (v[i - 1] - v[i]));
  BarResult r;
  if (zeros.size() >= 2) r.period = 2.0 * (zeros.back() - zeros.front()) / static_cast<double>(zeros.size() - 1);
  for (double x : v) r.amplitude = std::max(r.amplitude, std::abs(x));
  const auto q1 = global_quantities<2>(m);
  const double e0 = q0.kinetic_energy + q0.strain_energy, e1 = q1.kinetic_energy + q1.strain_energy;
  r.energy_drift = (e1 - e0) / e0;
  return r;
}

class BarVibration : public ::testing::TestWithParam<std::pair<std::string, std::string>> {};

TEST_P(BarVibration, PeriodAndAmplitudeOfTheFirstMode) {
  const auto [scheme, shape] = GetParam();
  const double L = 1.0, E = 1.0e7, rho = 1000.0, v0 = 0.01;
  const double T = 4.0 * L / std::sqrt(E / rho);
  const BarResult r = run_bar({"solver.scheme=\"" + scheme + "\"", "solver.shape_function=\"" + shape + "\""});
  EXPECT_NEAR(r.period, T, 0.01 * T);
  EXPECT_NEAR(r.amplitude, v0 * 2.0 / pi, 0.02 * v0 * 2.0 / pi);
  std::printf("bar %s/%s: period %.6f s (exact %.6f, error %.3f %%), amplitude error %.3f %%, energy drift %.3e over 5 periods\n",
              scheme.c_str(), shape.c_str(), r.period, T, 100 * (r.period / T - 1),
              100 * (r.amplitude / (v0 * 2 / pi) - 1), r.energy_drift);
}

INSTANTIATE_TEST_SUITE_P(Schemes, BarVibration,
                         ::testing::Values(std::pair{"musl", "gimp"}, std::pair{"musl", "ugimp"},
                                           std::pair{"usl", "gimp"}, std::pair{"usf", "gimp"},
                                           std::pair{"musl", "linear"}));

// MUSL with FLIP conserves the bar's energy closely: stated bound 0.1 % over five periods.
TEST(Verification, BarEnergyIsConservedWithMuslFlip) {
  const BarResult r = run_bar({});
  EXPECT_LT(std::abs(r.energy_drift), 1e-3);
}

// Column under self-weight at rest: per particle, sigma_yy against -rho g (H - y0), y0 its
// initial height (the weight above it). Returns the mean relative error of the particles within
// one cell of mid-height, relative to the exact mid-height stress.
template <int D>
double column_error(const std::string& file, double h, double* lateral_ratio = nullptr) {
  Loaded<D> run = load<D>(file, {"grid.cell_size=" + std::to_string(h)});
  Model<D>& m = run.m;
  const double rho = m.materials[0].density, g = 9.81, H = 1.0;
  run_simulation<D>(m, run.c, no_output());
  const auto q = global_quantities<D>(m);
  EXPECT_LT(q.kinetic_energy, 1e-6 * q.strain_energy) << "column not at rest";
  double err = 0, ratio = 0;
  int n = 0;
  for (std::size_t i = 0; i < m.particles.size(); ++i) {
    const double y0 = m.particles.x_p[i][1] - m.particles.u_p[i][1];
    if (std::abs(y0 - 0.5 * H) > h) continue;
    const double exact = -rho * g * (H - y0);
    err += std::abs(m.particles.sigma_p[i][1] - exact) / (rho * g * 0.5 * H);
    ratio += m.particles.sigma_p[i][0] / m.particles.sigma_p[i][1];
    ++n;
  }
  if (lateral_ratio) *lateral_ratio = ratio / n;
  return err / n;
}

TEST(Verification, ColumnSelfWeightConvergesAtFirstOrder) {
  const double e1 = column_error<2>("column_self_weight/column.toml", 0.1);
  const double e2 = column_error<2>("column_self_weight/column.toml", 0.05);
  double lateral = 0;
  const double e3 = column_error<2>("column_self_weight/column.toml", 0.025, &lateral);
  std::printf("column 2D: mid-height error %.4f %%, %.4f %%, %.4f %% at h = 0.1, 0.05, 0.025 m\n", 100 * e1,
              100 * e2, 100 * e3);
  EXPECT_LT(e3, 0.02);
  // Linear shape functions give a constant strain per cell: first order, the error halves with h.
  EXPECT_GT(e1 / e2, 1.8);
  EXPECT_GT(e2 / e3, 1.8);
  // Between rollers, plane strain: sigma_xx / sigma_yy = nu / (1 - nu).
  EXPECT_NEAR(lateral, 0.3 / 0.7, 0.01 * 0.3 / 0.7);
}

TEST(Verification, ColumnSelfWeight3D) {
  double lateral = 0;
  const double e3d = column_error<3>("column_self_weight/column_3d.toml", 0.05, &lateral);
  const double e2d = column_error<2>("column_self_weight/column.toml", 0.05);
  std::printf("column 3D: mid-height error %.4f %% (2D: %.4f %%) at h = 0.05 m\n", 100 * e3d, 100 * e2d);
  EXPECT_LT(e3d, 0.03);
  // Rollers on the z faces make the 3D column a plane-strain one: the same answer as 2D.
  EXPECT_NEAR(e3d, e2d, 1e-5);
  EXPECT_NEAR(lateral, 0.3 / 0.7, 0.01 * 0.3 / 0.7);
}

}  // namespace

namespace {

// A free, deforming block (no gravity, no boundary): total momentum is conserved by every scheme
// and shape function, to round-off (stated tolerance 1e-9 of the initial momentum over about 80 steps).
class MomentumConservation : public ::testing::TestWithParam<std::pair<std::string, std::string>> {};

TEST_P(MomentumConservation, FreeBlockKeepsItsMomentum) {
  const auto [scheme, shape] = GetParam();
  const std::string input = R"toml(
[model]
dimension = 2
[grid]
origin = [0.0, 0.0]
extent = [2.0, 2.0]
cell_size = 0.1
[[materials]]
name = "m"
model = "linear_elastic"
density = 1000.0
youngs_modulus = 1.0e6
poisson_ratio = 0.3
[[bodies]]
material = "m"
min = [0.5, 0.5]
max = [1.3, 1.1]
velocity = ["0.5 + 2.0 * (y - 0.8)", "-1.0 + 3.0 * (x - 0.9) * (x - 0.9)"]
[solver]
scheme = ")toml" + scheme + R"toml("
shape_function = ")toml" + shape + R"toml("
[time]
end = 0.1
[output]
frames = false
)toml";
  const Config c = read_config_string(input, "momentum.toml");
  Model<2> m = build_model<2>(c);
  const auto q0 = global_quantities<2>(m);
  RunOptions o;
  o.write_output = false;
  const RunSummary s = run_simulation<2>(m, c, o);
  const auto q1 = global_quantities<2>(m);
  EXPECT_GT(s.steps, 50);
  EXPECT_LT((q1.momentum - q0.momentum).norm(), 1e-9 * q0.momentum.norm());
  EXPECT_NEAR(q1.mass, q0.mass, 1e-12 * q0.mass);
}

INSTANTIATE_TEST_SUITE_P(Schemes, MomentumConservation,
                         ::testing::Values(std::pair{"usf", "gimp"}, std::pair{"usl", "gimp"},
                                           std::pair{"musl", "gimp"}, std::pair{"musl", "linear"},
                                           std::pair{"usf", "ugimp"}));

}  // namespace
