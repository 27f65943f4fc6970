// The unbalanced-force ratio (ExplicitSolver::unbalanced_force_ratio(), FLAC's max unbalanced /
// mean applied nodal force): of order 1 when gravity is switched on, falling as local damping
// brings an elastic column to rest, written to global.csv, and a recorder quantity whose
// stop_below ends the run at equilibrium before time.end; the reaction of a held body
// (bodies.prescribed_velocity) counts as balanced, as a fixed component's does.
#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/model/model.hpp"
#include "tsuchi/run/simulation.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace tsuchi;
using namespace tsuchi::test;

// examples/column_self_weight/column.toml, with a later time.end and a recorder of the ratio.
const std::string kColumn = R"(
[model]
dimension = 2
gravity = [0.0, -9.81]

[grid]
origin = [0.0, 0.0]
extent = [0.2, 1.2]
cell_size = 0.05

[[materials]]
name = "soil"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3

[[bodies]]
name = "column"
material = "soil"
min = [0.0, 0.0]
max = [0.2, 1.0]
particles_per_cell = 2

[boundary]
x_min = "roller"
x_max = "roller"
y_min = "fixed"

[solver]
scheme = "musl"
shape_function = "gimp"
damping = 0.3

[time]
end = 20.0
courant = 0.5

[output]
directory = "results"
interval = 0.0
global_interval = 0.01

[[recorders]]
name = "ratio"
quantity = "unbalanced_force_ratio"
stop_below = 1e-4
)";

TEST(UnbalancedForce, ColumnUnderSelfWeightStopsAtEquilibrium) {
  const Config c = read_config_string(kColumn, "column.toml", {});
  Model<2> m = build_model<2>(c);
  {
    ExplicitSolver<2> fresh(m);
    EXPECT_TRUE(std::isnan(fresh.unbalanced_force_ratio())) << "no solve yet: no ratio";
  }
  std::vector<double> ratio;
  const auto s = run_simulation<2>(m, c, no_output(), [&](const ExplicitSolver<2>& solver) {
    ratio.push_back(solver.unbalanced_force_ratio());
  });
  ASSERT_FALSE(ratio.empty());
  std::printf("column: R = %.4g after step 1, %.3g after step 100, %.3g at the stop, step %lld, t = %.4g s\n", ratio[0],
              ratio[std::min<std::size_t>(99, ratio.size() - 1)], ratio.back(), static_cast<long long>(s.steps), s.time);
  // Gravity just switched on, no stress yet: f = m b everywhere, |f^app| = |m b| / 2, so
  // R = 2 max m / mean m, between 2 and about 4 on this grid (edge nodes carry less mass).
  EXPECT_GT(ratio[0], 1.0);
  EXPECT_LT(ratio[0], 10.0);
  // The recorder's stop_below ended the run at equilibrium, well before time.end.
  EXPECT_NE(s.stopped_by.find("ratio reached"), std::string::npos) << s.stopped_by;
  EXPECT_LT(s.time, c.time.end);
  EXPECT_LE(ratio.back(), 1e-4 * (1.0 + 1e-9));
  for (std::size_t k = 0; k + 1 < ratio.size(); ++k) ASSERT_GT(ratio[k], 1e-4) << "step " << k + 1 << " was below the bound";
  // At rest the stress is the weight of the column above: sigma_yy = -rho g (H - y0) within a few percent.
  double worst = 0.0;
  for (std::size_t i = 0; i < m.particles.size(); ++i) {
    const double y0 = m.particles.x_p[i][1] - m.particles.u_p[i][1];
    const double ref = -2000.0 * 9.81 * (1.0 - y0);
    worst = std::max(worst, std::abs(m.particles.sigma_p[i][1] - ref));
  }
  std::printf("column: largest |sigma_yy - reference| %.3g Pa (reference at the base %.4g Pa)\n", worst, 2000.0 * 9.81);
  EXPECT_LT(worst, 0.05 * 2000.0 * 9.81);
}

TEST(UnbalancedForce, WrittenToGlobalCsv) {
  const fs::path dir = fs::temp_directory_path() / ("tsuchi_test_unbalanced_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const Config c = read_config_string(kColumn, "column.toml", {"time.end=0.05", "output.global_interval=0"});
  Model<2> m = build_model<2>(c);
  RunOptions o;
  o.output_directory = dir.string();
  std::vector<double> ratio;
  run_simulation<2>(m, c, o, [&](const ExplicitSolver<2>& s) { ratio.push_back(s.unbalanced_force_ratio()); });
  std::ifstream in(dir / "global.csv");
  std::string line;
  std::getline(in, line);
  // The ratio is the last column but one (released_particles follows).
  const auto column = [](const std::string& l) {
    const std::size_t end = l.rfind(',');
    const std::size_t begin = l.rfind(',', end - 1) + 1;
    return l.substr(begin, end - begin);
  };
  EXPECT_EQ(column(line), "unbalanced_force_ratio");
  std::vector<std::string> last;
  while (std::getline(in, line)) last.push_back(column(line));
  ASSERT_EQ(last.size(), ratio.size() + 1);  // the row at t = 0 and one per step
  EXPECT_EQ(last[0], "nan");                 // no solve before the first step
  for (std::size_t k = 0; k < ratio.size(); ++k) EXPECT_NEAR(std::stod(last[k + 1]), ratio[k], 1e-5 * ratio[k]);
  fs::remove_all(dir);
}

TEST(UnbalancedForce, RecorderTakesNoParticleSet) {
  for (const std::string key : {"body = \"column\"", "min = [0.0, 0.0]", "reduction = \"max\""}) {
    const std::string text = kColumn + key + "\n";
    try {
      read_config_string(text, "column.toml", {});
      ADD_FAILURE() << key << " accepted";
    } catch (const InputError& e) {
      expect_message(e.what(), {"whole-model number", "remove it"});
    }
  }
  EXPECT_THROW(read_config_string(replace(kColumn, "unbalanced_force_ratio", "unbalanced_force"), "c.toml", {}), InputError);
  try {
    read_config_string(kColumn, "column.toml", {"output.frame_label=\"ratio\""});
    ADD_FAILURE() << "frame_label = a whole-model recorder accepted";
  } catch (const InputError& e) {
    expect_message(e.what(), {"frame_label", "only after the first step"});
  }
}

// A held body (bodies.prescribed_velocity) is a kinematic constraint, like a FLAC grid point given
// a fixed velocity: the nodal force in a held component where its particles have weight is the
// constraint's reaction, and counts as balanced. Here a platen held still on top of the column:
// the column, fixed at both ends, settles under its weight and R falls below the bound as in the
// test above, while the same ratio with the held nodes counted (computed here from the nodal
// forces) stays at the platen's reaction, about 8, and would never end the run.
TEST(UnbalancedForce, HeldBodyReactionCountsAsBalanced) {
  const std::string text = replace(kColumn, "[boundary]", R"([[bodies]]
name = "platen"
material = "soil"
min = [0.0, 1.0]
max = [0.2, 1.1]
particles_per_cell = 2
prescribed_velocity = { x = 0.0, y = 0.0 }

[boundary])");
  const Config c = read_config_string(text, "column.toml", {});
  Model<2> m = build_model<2>(c);
  std::vector<double> ratio, counted;
  const auto s = run_simulation<2>(m, c, no_output(), [&](const ExplicitSolver<2>& solver) {
    ratio.push_back(solver.unbalanced_force_ratio());
    // The same ratio with only the fixed components balanced. Every node with mass is one of the
    // step's: nothing here moves far enough to leave a node with a stale mass.
    const auto& n = m.grid.field(0);
    double largest = 0.0, sum = 0.0, count = 0.0;
    for (std::size_t k = 0; k < n.m.size(); ++k) {
      if (!(n.m[k] > m.step.node_mass_floor)) continue;
      Vec<2> f = n.f[k];
      for (int d = 0; d < 2; ++d)
        if (m.grid.fixed_g[k] & (1u << d)) f[d] = 0.0;
      const Vec<2> ext = n.m[k] * m.step.gravity;
      largest = std::max(largest, f.norm());
      sum += 0.5 * (ext.norm() + (n.f[k] - ext).norm());
      count += 1.0;
    }
    counted.push_back(largest / (sum / count));
  });
  ASSERT_GT(ratio.size(), 100u);
  std::printf("held platen: R = %.3g at the stop, step %lld, t = %.4g s; with the held nodes counted %.3g\n",
              ratio.back(), static_cast<long long>(s.steps), s.time, counted.back());
  EXPECT_NE(s.stopped_by.find("ratio reached"), std::string::npos) << s.stopped_by;
  EXPECT_LT(s.time, c.time.end);
  // Gravity just switched on: the largest force is a node's weight, the same with or without the
  // held nodes (the two sums differ in order only).
  EXPECT_NEAR(ratio[0], counted[0], 1e-12 * counted[0]);
  for (std::size_t k = ratio.size() - 100; k < ratio.size(); ++k) EXPECT_GT(counted[k], 1.0) << "step " << k + 1;
  double fastest = 0.0;
  for (std::size_t i = 0; i < m.particles.size(); ++i) fastest = std::max(fastest, m.particles.v_p[i].norm());
  std::printf("held platen: fastest particle at the stop %.3g m/s\n", fastest);
  EXPECT_LT(fastest, 1e-3);  // at rest: g t would be 1.9 m/s
}

// The per-tile partial sums are added in tile order: 1 and 2 threads give bitwise the same ratio.
TEST(UnbalancedForce, SameForEveryThreadCount) {
  auto ratios = [](int threads) {
    const Config c = read_config_string(kColumn, "column.toml", {"time.end=0.02"});
    Model<2> m = build_model<2>(c);
    std::vector<double> r;
    const int before = omp_get_max_threads();
    omp_set_num_threads(threads);
    run_simulation<2>(m, c, no_output(), [&](const ExplicitSolver<2>& s) { r.push_back(s.unbalanced_force_ratio()); });
    omp_set_num_threads(before);
    return r;
  };
  const auto one = ratios(1), two = ratios(2);
  ASSERT_EQ(one.size(), two.size());
  ASSERT_FALSE(one.empty());
  for (std::size_t k = 0; k < one.size(); ++k) ASSERT_EQ(one[k], two[k]) << "step " << k + 1;
}

}  // namespace
