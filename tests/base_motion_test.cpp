// Driven grid nodes (base motion, [[boundary.nodes]] velocity / acceleration) and the reactions of
// held faces and node sets (reaction_x/y of a recorder with boundary = "..." or nodes = "..."):
// a block on a fixed base carries its weight; a platen's reaction balances the base's; driven
// nodes move the material at their velocity; an acceleration record is integrated exactly; a
// shaken elastic column resonates at Vs / (4 H).
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/model/model.hpp"
#include "tsuchi/run/recorder.hpp"
#include "tsuchi/run/simulation.hpp"
#include "tsuchi/solver/explicit_step.hpp"
#include "test_support.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace tsuchi {
namespace {

using test::no_output;

// An elastic block on a fixed base, brought to rest under gravity by local damping: the base
// carries the block's weight, rho g V = 2000 * 9.81 * 0.2 * 0.9 N/m.
const std::string kBlock = R"toml(
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
name = "block"
material = "soil"
min = [0.0, 0.0]
max = [0.2, 0.9]
particles_per_cell = 2

[boundary]
x_min = "roller"
x_max = "roller"
y_min = "fixed"

[solver]
damping = 0.3

[time]
end = 0.8
courant = 0.5

[output]
frames = false

[[recorders]]
name = "base_force"
boundary = "y_min"
quantity = "reaction_y"
)toml";

TEST(SupportReaction, FixedBaseCarriesTheWeight) {
  const double weight = 2000.0 * 9.81 * 0.2 * 0.9;
  for (const std::string scheme : {"usf", "usl", "musl"})
    for (const std::string transfer : {"apic", "flip"}) {
      const Config c = read_config_string(kBlock, "block.toml",
                                          {"solver.scheme=\"" + scheme + "\"", "solver.velocity_transfer=\"" + transfer + "\""});
      Model<2> m = build_model<2>(c);
      const std::vector<Recorder<2>> rec = make_recorders<2>(c, m);
      double R = 0.0;
      run_simulation<2>(m, c, no_output(), [&](const ExplicitSolver<2>& s) { R = rec[0].value(s); });
      std::printf("%s %s: base reaction %.4f N/m, weight %.4f N/m (%+.4f %%)\n", scheme.c_str(), transfer.c_str(), R,
                  weight, 100.0 * (R / weight - 1.0));
      EXPECT_NEAR(R, weight, 0.005 * weight) << scheme << " " << transfer;
    }
}

// The block (no gravity) pressed by a platen: the node row on its top driven down at 1 mm/s for
// 0.2 s, then held; at rest the platen's reaction is minus the base's (the block is in balance),
// and both are E' eps W with the plane-strain oedometric modulus (side rollers).
TEST(SupportReaction, PlatenBalancesTheBase) {
  const std::string platen = R"toml(
[[functions]]
name = "press"
table = [[0.0, 1.0], [0.2, 1.0], [0.21, 0.0]]

[[boundary.nodes]]
name = "platen"
min = [0.0, 0.9]
max = [0.2, 0.9]
velocity = { y = -0.001 }
function = "press"

[[recorders]]
name = "platen_force"
nodes = "platen"
quantity = "reaction_y"
)toml";
  for (const std::string scheme : {"usf", "usl", "musl"}) {
    std::string text = test::replace(kBlock, "gravity = [0.0, -9.81]", "gravity = [0.0, 0.0]");
    text = test::replace(text, "[solver]", platen + "\n[solver]");
    const Config c = read_config_string(text, "platen.toml", {"solver.scheme=\"" + scheme + "\"", "time.end=1.2"});
    Model<2> m = build_model<2>(c);
    const std::vector<Recorder<2>> rec = make_recorders<2>(c, m);
    double base = 0.0, top = 0.0;
    run_simulation<2>(m, c, no_output(), [&](const ExplicitSolver<2>& s) {
      top = rec[0].value(s);  // the platen's recorder comes first in the file
      base = rec[1].value(s);
    });
    // Compression 0.001 * (0.2 + 0.5 * 0.01) m of 0.9 m; plane-strain oedometric modulus.
    const double E = 1.0e7, nu = 0.3, eps = 0.001 * 0.205 / 0.9;
    const double expected = E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)) * eps * 0.2;
    std::printf("%s: base %.4f N/m, platen %.4f N/m (sum %+.4f %% of the base), E' eps W = %.4f N/m\n", scheme.c_str(),
                base, top, 100.0 * (base + top) / base, expected);
    EXPECT_GT(base, 0.0);
    EXPECT_NEAR(top, -base, 0.01 * base) << scheme;
    EXPECT_NEAR(base, expected, 0.05 * expected) << scheme;
  }
}

// Every node of the grid driven at v_x = 0.1 m/s, reached by a ramp over 10 ms: every particle
// ends with exactly that velocity, FLIP (which adds the nodes' velocity changes) and APIC (which
// takes the nodes' velocity) alike, under every scheme.
const std::string kDriven = R"toml(
[model]
dimension = 2

[grid]
origin = [0.0, 0.0]
extent = [1.0, 0.6]
cell_size = 0.05

[[materials]]
name = "soil"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3

[[bodies]]
name = "block"
material = "soil"
min = [0.2, 0.0]
max = [0.5, 0.3]
particles_per_cell = 2

[[functions]]
name = "ramp"
formula = "min(t / 0.01, 1)"

[boundary]
y_min = "roller"

[[boundary.nodes]]
name = "all"
min = [0.0, 0.0]
max = [1.0, 0.6]
velocity = { x = 0.1 }
function = "ramp"

[time]
end = 0.03
courant = 0.5

[output]
frames = false
)toml";

TEST(BaseMotion, DrivenNodesMoveTheMaterialAtTheirVelocity) {
  for (const std::string scheme : {"usf", "usl", "musl"})
    for (const std::string transfer : {"apic", "flip"}) {
      const Config c = read_config_string(kDriven, "driven.toml",
                                          {"solver.scheme=\"" + scheme + "\"", "solver.velocity_transfer=\"" + transfer + "\""});
      Model<2> m = build_model<2>(c);
      run_simulation<2>(m, c, no_output());
      double worst = 0.0;
      for (std::size_t i = 0; i < m.particles.size(); ++i)
        worst = std::max({worst, std::abs(m.particles.v_p[i][0] - 0.1), std::abs(m.particles.v_p[i][1])});
      EXPECT_LT(worst, 1e-12) << scheme << " " << transfer;
    }
}

// The block resting on a driven base row (v_x = 0.1 m/s after a 10 ms ramp), free otherwise: after
// the transient every particle moves with the base. With PIC (pic_fraction = 1), which damps the
// motion relative to the grid's velocity field; Cundall's local damping would not do here, as it
// opposes the absolute velocity (+x for the whole block) rather than the vibration about the
// base's. A vibration of about 1e-6 m/s stays (of the block's own modes, at the size of the
// spurious gradients where nodes below the mass floor meet the block's moving edges): 2e-5 m/s.
TEST(BaseMotion, DrivenBaseDragsTheBlock) {
  std::string text = test::replace(kDriven, "max = [1.0, 0.6]\nvelocity", "max = [1.0, 0.0]\nvelocity");
  const Config c = read_config_string(
      text, "drag.toml", {"time.end=1.0", "solver.velocity_transfer=\"flip\"", "solver.pic_fraction=1.0"});
  Model<2> m = build_model<2>(c);
  run_simulation<2>(m, c, no_output());
  double worst = 0.0;
  for (std::size_t i = 0; i < m.particles.size(); ++i)
    worst = std::max({worst, std::abs(m.particles.v_p[i][0] - 0.1), std::abs(m.particles.v_p[i][1])});
  std::printf("largest departure from the base's velocity after 1 s: %.3g m/s\n", worst);
  EXPECT_LT(worst, 2e-5);
}

// A constant acceleration a0 on the nodes gives them v = a0 t at the end of every step, whatever
// the step; a triangle record gives its exact integral.
TEST(BaseMotion, AccelerationIsIntegratedExactly) {
  const std::string constant = test::replace(kDriven, "velocity = { x = 0.1 }\nfunction = \"ramp\"",
                                             "acceleration = { x = 2.5 }\ninitial_velocity = { x = 0.01 }");
  const std::string triangle = test::replace(
      test::replace(kDriven, "velocity = { x = 0.1 }\nfunction = \"ramp\"", "acceleration = { x = 3.0 }\nfunction = \"tri\""),
      "[[functions]]", "[[functions]]\nname = \"tri\"\ntable = [[0.0, 0.0], [0.01, 2.0], [0.02, 0.0]]\n\n[[functions]]");
  // integral_0^t of the triangle: 100 t^2 up to 0.01, then 0.01 + 2 (t - 0.01) - 100 (t - 0.01)^2, then 0.02.
  const auto tri = [](double t) {
    if (t <= 0.01) return 100.0 * t * t;
    if (t <= 0.02) return 0.01 + 2.0 * (t - 0.01) - 100.0 * (t - 0.01) * (t - 0.01);
    return 0.02;
  };
  for (const double dt : {1.0e-4, 3.7e-4}) {
    for (int which = 0; which < 2; ++which) {
      const std::string text = test::replace(which == 0 ? constant : triangle, "courant = 0.5", fmt::format("dt = {}", dt));
      const Config c = read_config_string(text, "accel.toml");
      Model<2> m = build_model<2>(c);
      double worst = 0.0;
      std::size_t checked = 0;
      run_simulation<2>(m, c, no_output(), [&](const ExplicitSolver<2>& s) {
        const double t = s.time();
        const double expected = which == 0 ? 0.01 + 2.5 * t : 3.0 * tri(t);
        const auto& n = s.model().grid.field(0);
        for (const std::int64_t k : s.model().node_sets[0].driven_nodes)
          if (n.m[k] > s.model().step.node_mass_floor) worst = std::max(worst, std::abs(n.vL[k][0] - expected)), ++checked;
      });
      EXPECT_GT(checked, 0u);
      EXPECT_LT(worst, 1e-12) << (which == 0 ? "constant" : "triangle") << " dt " << dt;
    }
  }
}

// examples/shaking_column: a linear elastic column, H = 10 m of soil with Vs = 100 m/s, one cell
// wide with every node held vertically (simple shear, 1D), on a base shaken by one sine cycle of
// acceleration (0.1 s). The transfer function of uniform undamped soil on rigid rock (Kramer 1996,
// Geotechnical Earthquake Engineering, section 7.2.1), |U_top / U_base| = 1 / |cos(2 pi f H / Vs)|,
// peaks at f1 = Vs / (4 H) = 2.5 Hz: the peak of |V_top / V_base| from the run's velocities.
TEST(BaseMotion, ShakenColumnResonatesAtVsOver4H) {
  const Config c = read_config_file(std::string(TSUCHI_SOURCE_DIR) + "/examples/shaking_column/column.toml");
  Model<2> m = build_model<2>(c);
  std::vector<double> t, top, base;
  run_simulation<2>(m, c, no_output(), [&](const ExplicitSolver<2>& s) {
    const auto& p = s.model().particles;
    double sum = 0.0, count = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.x_p[i][1] - p.u_p[i][1] > 9.75) sum += p.v_p[i][0], count += 1.0;
    t.push_back(s.time());
    top.push_back(sum / count);
    // The base velocity of the pulse a = sin(20 pi t), t < 0.1 s.
    const double tb = std::min(s.time(), 0.1);
    base.push_back((1.0 - std::cos(20.0 * std::numbers::pi * tb)) / (20.0 * std::numbers::pi));
  });
  // |V_top(f) / V_base(f)| on 1 mHz steps over 1.5 - 4 Hz (the first mode only).
  double best_f = 0.0, best = 0.0;
  for (double f = 1.5; f <= 4.0; f += 0.001) {
    std::complex<double> T{0.0, 0.0}, B{0.0, 0.0};
    for (std::size_t k = 0; k < t.size(); ++k) {
      const std::complex<double> e = std::polar(1.0, -2.0 * std::numbers::pi * f * t[k]);
      T += top[k] * e, B += base[k] * e;
    }
    const double ratio = std::abs(T) / std::abs(B);
    if (ratio > best) best = ratio, best_f = f;
  }
  const double f1 = 100.0 / (4.0 * 10.0);
  std::printf("resonance of the shaken column: %.4f Hz (Vs / 4H = %.4f Hz, %+.3f %%), peak |H| = %.1f\n", best_f, f1,
              100.0 * (best_f / f1 - 1.0), best);
  EXPECT_NEAR(best_f, f1, 0.02 * f1);
}

// examples/shaking_table_slope without the shaking (its function set to 0) and with gravity on at
// once, brought to rest by local damping in 1.5 s: the table (the face y_min) carries the weight of
// the particles (0.5 %), and the horizontal forces of the table and the two walls on the soil add
// up to 0 (1 % of the left wall's, the largest).
TEST(BaseMotion, SlopeOnTheTableCarriesItsWeight) {
  const Config c = read_config_file(std::string(TSUCHI_SOURCE_DIR) + "/examples/shaking_table_slope/slope.toml",
                                    {"functions.0.formula=\"1\"", "functions.1.formula=\"0\"", "solver.damping=0.3",
                                     "time.end=1.5", "output.frames=false"});
  Model<2> m = build_model<2>(c);
  const std::vector<Recorder<2>> rec = make_recorders<2>(c, m);
  double mass = 0.0;
  for (const double mp : m.particles.m_p) mass += mp;
  double normal = 0.0, shear = 0.0, left = 0.0, right = 0.0;
  run_simulation<2>(m, c, no_output(), [&](const ExplicitSolver<2>& s) {
    shear = rec[2].value(s);
    normal = rec[3].value(s);
    left = rec[4].value(s);
    right = rec[5].value(s);
  });
  const double weight = mass * 9.81;
  std::printf("slope: table normal force %.1f N/m, weight %.1f N/m (%+.3f %%); horizontal: table %.1f, left wall "
              "%.1f, right wall %.1f, sum %.3g N/m\n",
              normal, weight, 100.0 * (normal / weight - 1.0), shear, left, right, shear + left + right);
  EXPECT_NEAR(normal, weight, 0.005 * weight);
  // At rest the horizontal forces on the soil balance (no horizontal load): the table's set and
  // the walls' share no node.
  EXPECT_NEAR(shear + left + right, 0.0, 0.01 * std::abs(left));
}

// The same bits on one and two threads: the shaken column (driven base) and the platen (support
// reactions), 300 steps each.
TEST(BaseMotion, OneAndTwoThreadsGiveTheSameBits) {
  const Config column = read_config_file(std::string(TSUCHI_SOURCE_DIR) + "/examples/shaking_column/column.toml",
                                         {"time.max_steps=300"});
  const Config block = read_config_string(kBlock, "block.toml", {"time.max_steps=300", "solver.scheme=\"usf\""});
  for (const Config* c : {&column, &block}) {
    std::vector<std::vector<double>> results;
    for (const int threads : {1, 2}) {
      const int before = omp_get_max_threads();
      omp_set_num_threads(threads);
      Model<2> m = build_model<2>(*c);
      const std::vector<Recorder<2>> rec = make_recorders<2>(*c, m);
      std::vector<double> r;
      run_simulation<2>(m, *c, no_output(), [&](const ExplicitSolver<2>& s) { r.push_back(rec.back().value(s)); });
      omp_set_num_threads(before);
      for (std::size_t i = 0; i < m.particles.size(); ++i)
        r.insert(r.end(), {m.particles.x_p[i][0], m.particles.x_p[i][1], m.particles.v_p[i][0], m.particles.v_p[i][1]});
      results.push_back(std::move(r));
    }
    ASSERT_EQ(results[0].size(), results[1].size());
    EXPECT_TRUE(results[0] == results[1]) << c->source;
  }
}

// set_boundary_conditions visits each set's own box (not every node per set): against the
// definition of node_sets.hpp, node by node over every set in input order, on 60 seeded boxes
// that overlap, start and end on nodes, within the 1e-9 h tolerance of one, between nodes or
// beyond the grid, fixing or driving components: the same nodes, driven nodes and masks, held
// components and held list, in 2D and 3D.
template <int D>
void check_node_sets_against_definition() {
  std::mt19937 rng(20261207u);
  const double h = 0.1;
  const int cells[3] = {13, 9, 6};
  auto coordinate = [&](int d) {
    const int k = std::uniform_int_distribution<int>(-2, cells[d] + 2)(rng);
    const double offsets[5] = {0.0, 0.4e-9, -0.4e-9, 0.3, -0.3};
    return (k + offsets[std::uniform_int_distribution<int>(0, 4)(rng)]) * h;
  };
  std::string text = fmt::format(R"toml(
[model]
dimension = {0}
[grid]
origin = [{1}]
extent = [{2}]
cell_size = {3}
[[materials]]
name = "soil"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[[bodies]]
name = "block"
material = "soil"
min = [{4}]
max = [{5}]
[time]
end = 0.01
courant = 0.5
[output]
frames = false
[boundary]
x_min = "roller"
y_max = "fixed"
)toml", D, D == 2 ? "0.0, 0.0" : "0.0, 0.0, 0.0", D == 2 ? "1.3, 0.9" : "1.3, 0.9, 0.6", h,
                                 D == 2 ? "0.2, 0.2" : "0.2, 0.2, 0.2", D == 2 ? "0.5, 0.5" : "0.5, 0.5, 0.5");
  const char* axes = "xyz";
  int written = 0;
  while (written < 60) {
    double lo[3], hi[3];
    bool holds_a_node = true;
    for (int d = 0; d < D; ++d) {
      lo[d] = coordinate(d), hi[d] = coordinate(d);
      if (hi[d] < lo[d]) std::swap(lo[d], hi[d]);
      // A box must hold a node (an input error otherwise): a node number within [lo, hi] on the grid.
      const double first = std::max(0.0, std::ceil(lo[d] / h - 1e-6)), last = std::min<double>(cells[d], std::floor(hi[d] / h + 1e-6));
      holds_a_node = holds_a_node && first <= last && lo[d] <= first * h + 1e-9 * h && hi[d] >= last * h - 1e-9 * h;
    }
    if (!holds_a_node) continue;
    std::string fix, vel;
    for (int d = 0; d < D; ++d) {
      const int role = std::uniform_int_distribution<int>(0, 2)(rng);  // free, fixed, driven
      if (role == 1) fix += fmt::format("{}\"{}\"", fix.empty() ? "" : ", ", axes[d]);
      if (role == 2) vel += fmt::format("{}{} = {}", vel.empty() ? "" : ", ", axes[d], 0.01 * (written + 1));
    }
    if (fix.empty() && vel.empty()) fix = "\"x\"";
    text += "[[boundary.nodes]]\nmin = [";
    for (int d = 0; d < D; ++d) text += fmt::format("{}{:.17g}", d ? ", " : "", lo[d]);
    text += "]\nmax = [";
    for (int d = 0; d < D; ++d) text += fmt::format("{}{:.17g}", d ? ", " : "", hi[d]);
    text += "]\n";
    if (!fix.empty()) text += "fix = [" + fix + "]\n";
    if (!vel.empty()) text += "velocity = { " + vel + " }\n";
    ++written;
  }
  const Config c = read_config_string(text, "sets.toml");
  const Model<D> m = build_model<D>(c);
  const Grid<D>& g = m.grid;
  const auto& configs = c.boundary.node_sets;
  ASSERT_EQ(m.node_sets.size(), configs.size());
  std::vector<std::vector<std::int64_t>> nodes(configs.size()), driven(configs.size());
  std::vector<std::vector<std::uint8_t>> masks(configs.size());
  std::vector<std::int64_t> held;
  std::size_t driven_total = 0;
  for (std::int64_t k = 0; k < static_cast<std::int64_t>(g.size()); ++k) {
    if (!g.is_node(k)) continue;
    const auto ijk = g.ijk(k);
    std::uint8_t mask = 0;
    for (int d = 0; d < D; ++d) {
      if (d == 0 && ijk[0] == 0) mask |= 1u;                                          // x_min roller
      if (d == 1 && ijk[1] == g.n_nodes[1] - 1) mask |= static_cast<std::uint8_t>((1u << D) - 1);  // y_max fixed
    }
    std::array<int, D> by;
    by.fill(-1);
    const Vec<D> x = g.position(ijk);
    for (std::size_t s = 0; s < configs.size(); ++s) {
      bool inside = true;
      for (int d = 0; d < D; ++d) inside = inside && x[d] >= configs[s].min[d] - 1e-9 * h && x[d] <= configs[s].max[d] + 1e-9 * h;
      if (!inside) continue;
      nodes[s].push_back(k);
      for (int d = 0; d < D; ++d) {
        if (configs[s].fix[d]) mask |= static_cast<std::uint8_t>(1u << d), by[d] = -1;
        if (configs[s].driven[d]) mask |= static_cast<std::uint8_t>(1u << d), by[d] = static_cast<int>(s);
      }
    }
    for (std::size_t s = 0; s < configs.size(); ++s) {
      std::uint8_t bits = 0;
      for (int d = 0; d < D; ++d)
        if (by[d] == static_cast<int>(s)) bits = static_cast<std::uint8_t>(bits | (1u << d));
      if (bits) driven[s].push_back(k), masks[s].push_back(bits), ++driven_total;
    }
    EXPECT_EQ(g.fixed_g[static_cast<std::size_t>(k)], mask) << "node " << k;
    if (mask) held.push_back(k);
  }
  for (std::size_t s = 0; s < configs.size(); ++s) {
    EXPECT_EQ(m.node_sets[s].nodes, nodes[s]) << "set " << s;
    EXPECT_EQ(m.node_sets[s].driven_nodes, driven[s]) << "set " << s;
    EXPECT_EQ(m.node_sets[s].driven_mask, masks[s]) << "set " << s;
  }
  EXPECT_EQ(m.held_nodes, held);
  EXPECT_GT(driven_total, 10u);  // the draw drives some components somewhere
}

TEST(NodeSets, HoldTheNodesTheirDefinitionGives) { check_node_sets_against_definition<2>(); }
TEST(NodeSets, HoldTheNodesTheirDefinitionGives3D) { check_node_sets_against_definition<3>(); }

}  // namespace
}  // namespace tsuchi
