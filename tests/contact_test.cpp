// Frictional contact (model/contact.hpp, solver/contact_stage.hpp) against what it should give:
// a block sliding down an incline (examples/sliding_block) on a frictional floor and on a rigid
// base body at Coulomb's acceleration, or at rest; two elastic disks colliding without friction
// (examples/disk_collision) with momentum kept, no interpenetration and a rebound, and "bonded"
// exactly as no contact; the same bits on one and two threads; the forces a rigid base body and a
// frictional floor carry under a block at rest.
#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/model/model.hpp"
#include "tsuchi/model/start_warnings.hpp"
#include "tsuchi/run/simulation.hpp"
#include "tsuchi/solver/global_quantities.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace tsuchi {
namespace {

using namespace tsuchi::test;

const std::string kExamples = std::string(TSUCHI_SOURCE_DIR) + "/examples/";

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in.good()) << "cannot read " << path;
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

template <int D>
int body_index(const Model<D>& m, const std::string& name) {
  const auto it = std::find(m.body_names.begin(), m.body_names.end(), name);
  EXPECT_NE(it, m.body_names.end()) << name;
  return static_cast<int>(it - m.body_names.begin());
}

// Mass-weighted mean velocity and position of one body's particles.
template <int D>
struct BodyMean {
  Vec<D> v = Vec<D>::Zero(), x = Vec<D>::Zero();
  double mass = 0.0;
};

template <int D>
BodyMean<D> body_mean(const Model<D>& m, int body) {
  BodyMean<D> r;
  const auto& p = m.particles;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.body_p[i] == body) r.v += p.m_p[i] * p.v_p[i], r.x += p.m_p[i] * p.x_p[i], r.mass += p.m_p[i];
  r.v /= r.mass, r.x /= r.mass;
  return r;
}

// ---------------------------------------------------------------------------------------------
// Sliding block

constexpr double kG = 9.81;

double radians(double deg) { return deg * std::numbers::pi / 180.0; }

// Coulomb's block on an incline at theta: a = g (sin th - mu cos th) while it slides, 0 when
// mu >= tan th.
double coulomb_acceleration(double theta_deg, double mu) {
  return std::max(0.0, kG * (std::sin(radians(theta_deg)) - mu * std::cos(radians(theta_deg))));
}

// "model.gravity=[...]": g tilted by theta, so that the grid's x axis runs down the incline.
std::string tilted_gravity(double theta_deg, int dimension) {
  const double s = kG * std::sin(radians(theta_deg)), c = -kG * std::cos(radians(theta_deg));
  char buf[128];
  if (dimension == 2) std::snprintf(buf, sizeof buf, "model.gravity=[%.17g,%.17g]", s, c);
  else std::snprintf(buf, sizeof buf, "model.gravity=[%.17g,0.0,%.17g]", s, c);
  return buf;
}

// The block's down-slope acceleration over 0.05 s .. time.end: the change of its mean velocity
// (mass-weighted; the particles' masses are equal) over that time, from the step that first
// reaches 0.05 s, once the gravity ramp (0.02 s) and the settling of the normal force are over.
template <int D>
double block_acceleration(const Config& c) {
  Model<D> m = build_model<D>(c);
  const int block = body_index(m, "block");
  double t0 = -1.0, v0 = 0.0, t1 = 0.0, v1 = 0.0;
  run_simulation<D>(m, c, no_output(), [&](const ExplicitSolver<D>& s) {
    const double v = body_mean(s.model(), block).v[0];
    if (t0 < 0.0 && s.time() >= 0.05 - 1e-12) t0 = s.time(), v0 = v;
    t1 = s.time(), v1 = v;
  });
  return (v1 - v0) / (t1 - t0);
}

// The two inputs of examples/sliding_block: the floor y_min a frictional wall, or the block on a
// rigid base body with a [[contact]] pair; theta and mu set by overrides.
Config sliding_block(bool rigid_base, double theta, double mu, std::vector<std::string> more = {}) {
  more.push_back(tilted_gravity(theta, 2));
  char buf[64];
  std::snprintf(buf, sizeof buf, rigid_base ? "contact.0.friction=%.17g" : "boundary.y_min.friction=%.17g", mu);
  more.push_back(buf);
  return read_config_file(kExamples + "sliding_block/" + (rigid_base ? "rigid_base.toml" : "wall.toml"), more);
}

// Block 0.4 x 0.1 m (E = 100 MPa), 0.025 m cells, 2 x 2 particles per cell, MUSL + APIC + GIMP.
// Sliding: within 1 % of g (sin th - mu cos th) (measured: 0.000 % at mu = 0, +0.004 % / +0.003 %
// at mu = 0.2, -0.52 % / -0.022 % at mu = 0.5, for 30 / 45 deg; the wall and the rigid base give
// the same bits). Stuck (mu > tan th): |a| < 0.002 g (measured 3.9e-5 g at 30 deg, mu 0.7, and
// 4.4e-5 g at 45 deg, mu 1.5). Not asserted: at 45 deg and mu 1.2, just above tan th, the elastic
// block slips during the ramp and then creeps at a steady 0.019 m/s instead of stopping (docs and
// the issue's note: stick-slip of the elastic block's contact nodes).
TEST(SlidingBlock, AccelerationIsCoulombsOnWallAndRigidBase) {
  struct Case {
    double theta, mu;
  };
  const std::vector<Case> cases{{30, 0.0}, {30, 0.2}, {30, 0.5}, {30, 0.7}, {45, 0.0}, {45, 0.2}, {45, 0.5}, {45, 1.5}};
  for (const bool rigid : {false, true})
    for (const Case& k : cases) {
      const double a = block_acceleration<2>(sliding_block(rigid, k.theta, k.mu));
      const double ref = coulomb_acceleration(k.theta, k.mu);
      std::printf("%-10s theta %2.0f mu %.1f: a = %.5f m/s2, Coulomb %.5f (%s %+.4f)\n", rigid ? "rigid base" : "wall",
                  k.theta, k.mu, a, ref, ref > 0.0 ? "%" : "a/g", ref > 0.0 ? 100.0 * (a / ref - 1.0) : a / kG);
      if (ref > 0.0) EXPECT_NEAR(a, ref, 0.01 * ref) << (rigid ? "rigid base" : "wall") << " " << k.theta << " " << k.mu;
      else EXPECT_LT(std::abs(a), 0.002 * kG) << (rigid ? "rigid base" : "wall") << " " << k.theta << " " << k.mu;
    }
}

// The other schemes and kernels on the wall and the rigid base: USF + APIC and USL + FLIP at 30 deg
// (mu 0.2, 0.5), MUSL + linear shape functions (FLIP) at 30 deg, mu 0.2 and 45 deg, mu 0.5; within
// 1 %. Measured: USF +0.004 % / -0.52 %, USL + FLIP -0.019 % / +0.68 %, linear -0.052 % / +0.022 %.
// Left out: linear at 30 deg, mu 0.5, +29.5 % (+10.3 % at 0.0125 m cells): there a is the small
// difference of gravity's pull and the friction, and the friction is about 4.5 % short, presumably
// the linear kernel's cell-crossing noise (examples/sliding_block/README.md).
TEST(SlidingBlock, SchemesAndKernels) {
  struct Case {
    std::vector<std::string> settings;
    double theta, mu;
  };
  const std::vector<std::string> usf{"solver.scheme=\"usf\""};
  const std::vector<std::string> usl{"solver.scheme=\"usl\"", "solver.velocity_transfer=\"flip\""};
  const std::vector<std::string> linear{"solver.shape_function=\"linear\""};
  const std::vector<Case> cases{{usf, 30, 0.2},    {usf, 30, 0.5},    {usl, 30, 0.2},
                                {usl, 30, 0.5},    {linear, 30, 0.2}, {linear, 45, 0.5}};
  for (const Case& k : cases)
    for (const bool rigid : {false, true}) {
      const double a = block_acceleration<2>(sliding_block(rigid, k.theta, k.mu, k.settings));
      const double ref = coulomb_acceleration(k.theta, k.mu);
      std::printf("%-34s %-10s theta %2.0f mu %.1f: a = %.5f m/s2, Coulomb %.5f (%+.4f %%)\n",
                  k.settings.back().c_str(), rigid ? "rigid base" : "wall", k.theta, k.mu, a, ref,
                  100.0 * (a / ref - 1.0));
      EXPECT_NEAR(a, ref, 0.01 * ref) << k.settings.back() << (rigid ? " rigid base " : " wall ") << k.theta << " "
                                      << k.mu;
    }
}

// 3D: a box block 0.4 x 0.1 x 0.1 m on the frictional floor z_min, 0.05 m cells (256 particles),
// theta 30 deg: within 1 % of Coulomb at mu 0.2 and 0.5 (measured +0.006 % and +0.33 %, with the y
// faces on rollers: free, they let the block's Poisson bulge leave the grid, issue 41).
TEST(SlidingBlock, ThreeDimensionalBlockOnFrictionalFloor) {
  const std::string input = R"toml(
[model]
dimension = 3
gravity = [0.0, 0.0, -9.81]
gravity_function = "ramp"

[[functions]]
name = "ramp"
table = [[0.0, 0.0], [0.02, 1.0]]

[grid]
origin = [0.0, 0.0, 0.0]
extent = [0.8, 0.1, 0.2]
cell_size = 0.05

[[materials]]
name = "elastic"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e8
poisson_ratio = 0.3

[[bodies]]
name = "block"
material = "elastic"
min = [0.1, 0.0, 0.0]
max = [0.5, 0.1, 0.1]
particles_per_cell = 2

[boundary]
z_min = { friction = 0.2 }
y_min = "roller"  # the block spans the grid across y: a slice of a wider block
y_max = "roller"

[time]
end = 0.2
courant = 0.5

[output]
frames = false
)toml";
  for (const double mu : {0.2, 0.5}) {
    const Config c = read_config_string(input, "block3d.toml",
                                        {tilted_gravity(30.0, 3), "boundary.z_min.friction=" + std::to_string(mu)});
    const double a = block_acceleration<3>(c), ref = coulomb_acceleration(30.0, mu);
    std::printf("3D wall mu %.1f: a = %.5f m/s2, Coulomb %.5f (%+.4f %%)\n", mu, a, ref, 100.0 * (a / ref - 1.0));
    EXPECT_NEAR(a, ref, 0.01 * ref) << mu;
  }
}

// A free rigid block (examples/sliding_block/rigid_block.toml: rigid_mass 80 kg/m, its own mass)
// on an elastic base layer fixed at its bottom, [[contact]] friction mu: it translates by eq (R3) of
// explicit_step.cpp and slides at g (sin th - mu cos th) within 1 % (measured -0.41 % at 30 deg,
// mu 0.2, and -0.55 % at mu 0.5 with the base's ends on rollers, since rigid bodies take no anti-locking remedy; -0.006 % before,
// examples/sliding_block/README.md). Meeting the base with its nodal mass, not as an infinitely
// heavy partner, is what makes this work: treated as infinitely heavy within a step, its explicit
// velocity update rang and the block stuck.
TEST(SlidingBlock, FreeRigidBlockSlidesAtCoulombsAcceleration) {
  for (const double mu : {0.2, 0.5}) {
    const Config c = read_config_file(kExamples + "sliding_block/rigid_block.toml",
                                      {tilted_gravity(30.0, 2), "contact.0.friction=" + std::to_string(mu)});
    const double a = block_acceleration<2>(c), ref = coulomb_acceleration(30.0, mu);
    std::printf("rigid block, mu %.1f: a = %.5f m/s2, Coulomb %.5f (%+.4f %%)\n", mu, a, ref, 100.0 * (a / ref - 1.0));
    EXPECT_NEAR(a, ref, 0.01 * ref) << mu;
  }
}

// A free rigid body much lighter than the soil it touches is warned of before the run (issue 41,
// defect 6): the block of rigid_block.toml at 8e-8 kg/m, 1e-9 of its own mass, rang and left the
// grid at step 30 with no word about its mass. The soil within a cell of it is the base's layer
// 0.025 m deep under it and a cell to each side: 0.45 x 0.025 m at 2000 kg/m^3 = 22.5 kg/m. At
// 80 kg/m (its own) there is no warning, and none for a block a cell above the base.
TEST(SlidingBlock, LightFreeRigidBlockIsWarnedOf) {
  const std::string file = kExamples + "sliding_block/rigid_block.toml";
  Config c = read_config_file(file, {"bodies.1.rigid_mass=8e-8"});
  std::vector<std::string> w = start_warnings<2>(c, build_model<2>(c));
  ASSERT_EQ(w.size(), 1u);
  tsuchi::test::expect_message(w[0], {"free rigid body \"block\" (rigid_mass = 8e-08 kg/m)", "22.5 kg/m",
                                      "body \"base\"", "its particles weigh 80 kg/m"});
  Model<2> m = build_model<2>(c);
  bool left = false;
  try {
    run_simulation<2>(m, c, no_output());
  } catch (const RunError& e) {
    left = exit_code::of(e.fault) == exit_code::left_grid;
  }
  EXPECT_TRUE(left) << "the light block was expected to leave the grid";
  c = read_config_file(file);
  EXPECT_TRUE(start_warnings<2>(c, build_model<2>(c)).empty());
  c = read_config_file(file, {"bodies.1.rigid_mass=8e-8", "bodies.1.min=[0.1, 0.15]", "bodies.1.max=[0.5, 0.25]"});
  EXPECT_TRUE(start_warnings<2>(c, build_model<2>(c)).empty());
}

// A rigid body strains only as its motion is prescribed: the smooth rigid footing
// (examples/footing/footing_smooth.toml, 10 cells per width, the default node-averaged
// anti-locking) pushed 0.4 s into the soil keeps every particle's volume to the bit. Before, its
// particles took the node average of their field's velocity divergence, which carries the soil's
// contact impulses, and one was compressed to zero volume at t = 0.31 s.
TEST(Contact, RigidFootingKeepsItsVolume) {
  const Config c = read_config_file(kExamples + "footing/footing_smooth.toml",
                                    {"grid.cell_size=0.1", "time.end=0.4", "output.frames=false"});
  Model<2> m = build_model<2>(c);
  const int footing = body_index(m, "footing");
  std::vector<double> before;
  for (std::size_t i = 0; i < m.particles.size(); ++i)
    if (m.particles.body_p[i] == footing) before.push_back(m.particles.V_p[i]);
  run_simulation<2>(m, c, no_output());
  std::vector<std::pair<std::int64_t, double>> after;  // particles are reordered: compare by id
  for (std::size_t i = 0; i < m.particles.size(); ++i)
    if (m.particles.body_p[i] == footing) after.emplace_back(m.particles.id_p[i], m.particles.V_p[i]);
  std::sort(after.begin(), after.end());
  ASSERT_EQ(after.size(), before.size());
  for (std::size_t k = 0; k < after.size(); ++k) EXPECT_EQ(after[k].second, before[k]) << "footing particle " << k;
}

// ---------------------------------------------------------------------------------------------
// Two disks

const std::string kDisks = kExamples + "disk_collision/disks.toml";

// The disks of examples/disk_collision with frictionless contact. Reference: Sulsky, Chen and
// Schreyer (1994): the disks rebound; with contact they must besides keep momentum, not overlap,
// and lose little energy. Asserted and measured (0.05 m cells, 2 x 2 particles per cell, 177 steps
// to 3 s):
// - total momentum |sum m v| at every step, relative to sum m |v| at the start (it starts at 0):
//   below 1e-12 with solver.mass_threshold = 1e-15 (measured 7e-16, round-off); with the input's
//   default threshold (1e-9) below 1e-9 (measured 4.6e-10, lost at the separation, t = 1.9 - 2.2 s,
//   where a disk's field has nodes lighter than the threshold, which are left out; the same run
//   with one field keeps 8e-16);
// - the centres' relative velocity along the diagonal reverses: approaching at 0.283 m/s, apart at
//   more than 0.2 m/s after (measured 0.261 m/s, a ratio of 0.924);
// - the closest pair of particles of the two disks never nearer than 0.5 particle spacing
//   (0.0125 m; measured 0.0222 m = 0.89 spacing, at t = 1.74 s);
// - kinetic + strain energy at the end at least 80 % of the start's (measured 89.0 %).
TEST(DiskCollision, FrictionlessDisksKeepMomentumDoNotOverlapAndRebound) {
  for (const bool fine_floor : {true, false}) {
    const Config c = read_config_file(kDisks, fine_floor ? std::vector<std::string>{"solver.mass_threshold=1e-15"}
                                                         : std::vector<std::string>{});
    Model<2> m = build_model<2>(c);
    const int lower = body_index(m, "lower"), upper = body_index(m, "upper");
    const auto& p0 = m.particles;
    double scale = 0.0;
    for (std::size_t i = 0; i < p0.size(); ++i) scale += p0.m_p[i] * p0.v_p[i].norm();
    const GlobalQuantities<2> q0 = global_quantities(m);
    const double energy0 = q0.kinetic_energy + q0.strain_energy;
    const Vec<2> diagonal(std::numbers::sqrt2 / 2.0, std::numbers::sqrt2 / 2.0);
    const double approach0 = (body_mean(m, upper).v - body_mean(m, lower).v).dot(diagonal);

    double worst_momentum = 0.0, closest = std::numeric_limits<double>::infinity(), closest_time = 0.0;
    double most_strain = 0.0;
    std::vector<std::size_t> in_lower, in_upper;
    for (std::size_t i = 0; i < p0.size(); ++i) (p0.body_p[i] == lower ? in_lower : in_upper).push_back(i);
    run_simulation<2>(m, c, no_output(), [&](const ExplicitSolver<2>& s) {
      const auto& p = s.model().particles;
      const GlobalQuantities<2> q = global_quantities(s.model());
      worst_momentum = std::max(worst_momentum, q.momentum.norm() / scale);
      most_strain = std::max(most_strain, q.strain_energy);
      for (const std::size_t i : in_lower)
        for (const std::size_t j : in_upper) {
          const double d = (p.x_p[i] - p.x_p[j]).norm();
          if (d < closest) closest = d, closest_time = s.time();
        }
    });
    const GlobalQuantities<2> q = global_quantities(m);
    const double energy = q.kinetic_energy + q.strain_energy;
    const double separation = (body_mean(m, upper).v - body_mean(m, lower).v).dot(diagonal);
    const double spacing = c.grid.cell_size / 2.0;
    std::printf("disks, mass threshold %s: worst |sum m v| / sum m|v|0 = %.3g; relative velocity along the diagonal "
                "%.5f -> %.5f m/s (ratio %.4f); closest particles %.5f m = %.3f spacings at t = %.3f s; energy "
                "%.5f -> %.5f J/m (%.2f %%), peak strain energy %.5f J/m\n",
                fine_floor ? "1e-15" : "1e-9", worst_momentum, approach0, separation, -separation / approach0, closest,
                closest / spacing, closest_time, energy0, energy, 100.0 * energy / energy0, most_strain);
    EXPECT_LT(worst_momentum, fine_floor ? 1e-12 : 1e-9);
    EXPECT_LT(approach0, -0.28);
    EXPECT_GT(separation, 0.2);
    EXPECT_GT(most_strain, 0.3 * energy0);  // they did collide
    EXPECT_GT(closest, 0.5 * spacing);
    EXPECT_GT(energy, 0.8 * energy0);
    EXPECT_LT(energy, 1.0 * energy0);
  }
}

// friction = "bonded" gives the pair one velocity field: the same bits as the input without the
// [[contact]] table, through the impact (120 steps, to about 2 s).
TEST(DiskCollision, BondedIsBitForBitNoContact) {
  const std::string text = read_text(kDisks);
  const std::string contact = "[[contact]]\nbodies = [\"lower\", \"upper\"]\nfriction = 0.0\n";
  const Config bonded = read_config_string(replace(text, "friction = 0.0", "friction = \"bonded\""), "bonded.toml",
                                           {"time.max_steps=120", "output.frames=false"});
  const Config none = read_config_string(replace(text, contact, ""), "none.toml",
                                         {"time.max_steps=120", "output.frames=false"});
  ASSERT_EQ(bonded.contacts.size(), 1u);
  ASSERT_TRUE(none.contacts.empty());
  Model<2> a = build_model<2>(bonded), b = build_model<2>(none);
  run_simulation<2>(a, bonded, no_output());
  run_simulation<2>(b, none, no_output());
  ASSERT_EQ(a.particles.size(), b.particles.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.particles.size(); ++i)
    differ += !(a.particles.x_p[i] == b.particles.x_p[i] && a.particles.v_p[i] == b.particles.v_p[i] &&
                a.particles.sigma_p[i] == b.particles.sigma_p[i]);
  EXPECT_EQ(differ, 0u);
  // The single-field MPM of the paper: the bonded disks rebound as well, a little slower.
  const double rel = (body_mean(a, 1).v - body_mean(a, 0).v).dot(Vec<2>(1.0, 1.0));
  std::printf("bonded disks after 120 steps: relative velocity along (1, 1) %.5f m/s\n", rel);
}

// ---------------------------------------------------------------------------------------------
// Threads

// The frictional disks (mu 0.3) and the block on the rigid base (mu 0.3, 45 deg, sliding), 300
// steps each on one and two threads: every particle's position and velocity, and the base's
// reaction at every step, the same bits.
TEST(Contact, OneAndTwoThreadsGiveTheSameBits) {
  const Config disks = read_config_file(kDisks, {"contact.0.friction=0.3", "output.frames=false"});
  const Config block = sliding_block(true, 45.0, 0.3, {"time.max_steps=300", "output.frames=false"});
  for (const Config* c : {&disks, &block}) {
    std::vector<std::vector<double>> results;
    for (const int threads : {1, 2}) {
      const int before = omp_get_max_threads();
      omp_set_num_threads(threads);
      Model<2> m = build_model<2>(*c);
      std::vector<double> r;
      // The base's reaction (the disks have no prescribed body: their reaction() is NaN).
      const auto base = std::find(m.body_names.begin(), m.body_names.end(), "base");
      const int b = base == m.body_names.end() ? -1 : static_cast<int>(base - m.body_names.begin());
      run_simulation<2>(m, *c, no_output(), [&](const ExplicitSolver<2>& s) {
        if (b < 0) return;
        const Vec<2> f = s.reaction(b);
        r.insert(r.end(), {f[0], f[1]});
      });
      omp_set_num_threads(before);
      for (std::size_t i = 0; i < m.particles.size(); ++i)
        r.insert(r.end(), {m.particles.x_p[i][0], m.particles.x_p[i][1], m.particles.v_p[i][0], m.particles.v_p[i][1]});
      results.push_back(std::move(r));
    }
    ASSERT_EQ(results[0].size(), results[1].size());
    EXPECT_TRUE(results[0] == results[1]) << c->source;
  }
}

// ---------------------------------------------------------------------------------------------
// Forces at rest

const std::string kRestingBlock = R"toml(
[model]
dimension = 2
gravity = [0.0, -9.81]

[grid]
origin = [0.0, 0.0]
extent = [0.6, 0.3]
cell_size = 0.025

[[materials]]
name = "elastic"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e8
poisson_ratio = 0.3

[[bodies]]
name = "block"
material = "elastic"
min = [0.1, 0.1]
max = [0.5, 0.2]
particles_per_cell = 2

[solver]
damping = 0.0

[time]
end = 0.4
courant = 0.5

[output]
frames = false
)toml";

// The block of kRestingBlock on a rigid base body 0.1 m thick (0 .. 0.1 m, [[contact]] mu 0.3).
std::string on_rigid_base() {
  return replace(kRestingBlock, "[solver]", R"toml([[bodies]]
name = "base"
material = "elastic"
min = [0.0, 0.0]
max = [0.6, 0.1]
particles_per_cell = 2
prescribed_velocity = { x = 0.0, y = 0.0 }

[[contact]]
bodies = ["block", "base"]
friction = 0.3

[solver])toml");
}

// The block set on a rigid base body with gravity on at once (dropped from zero height), no
// damping: it vibrates on the base, and the mean over 0.2 - 0.4 s of ExplicitSolver::reaction(base)
// is the force that holds the base at rest (eq R1 of explicit_step.cpp): minus the force the rest
// of the model puts on it, so +y here, carrying the block through contact and the base's own
// weight. Asserted: that mean minus the base's weight is the block's weight within 2 %, its x
// component 0 within 0.1 % (measured +0.001 % and 0; the largest contact force, 1.8 times the
// weight, comes as for a load applied at once).
TEST(Contact, RigidBaseCarriesTheBlockSetOnIt) {
  const Config c = read_config_string(on_rigid_base(), "drop.toml", {});
  Model<2> m = build_model<2>(c);
  const int base = body_index(m, "base"), block = body_index(m, "block");
  const double block_weight = body_mean(m, block).mass * kG, base_weight = body_mean(m, base).mass * kG;
  Vec<2> mean = Vec<2>::Zero();
  double peak = 0.0;
  int n = 0;
  run_simulation<2>(m, c, no_output(), [&](const ExplicitSolver<2>& s) {
    const Vec<2> r = s.reaction(base);
    peak = std::max(peak, r[1] - base_weight);
    if (s.time() > 0.2) mean += r, ++n;
  });
  mean /= n;
  std::printf("rigid base: mean reaction over 0.2 - 0.4 s (%.4f, %.4f) N/m; base weight %.3f, block weight %.3f: "
              "contact force %.3f (%+.3f %%); largest %.1f\n",
              mean[0], mean[1], base_weight, block_weight, mean[1] - base_weight,
              100.0 * ((mean[1] - base_weight) / block_weight - 1.0), peak);
  EXPECT_GT(peak, 1.5 * block_weight);
  EXPECT_NEAR(mean[1] - base_weight, block_weight, 0.02 * block_weight);
  EXPECT_NEAR(mean[0], 0.0, 1e-3 * block_weight);
}

// With local damping 0.05 the block comes to rest on the rigid base, and the base's reaction is the
// block's weight within 2 % in every step over 0.3 - 0.4 s. Before the damping force was left off
// the nodes where contact may act, it jumped between -4.2 % and +4.2 % from step to step: the force
// -alpha |f| sign(v) at the block's contact nodes, with sign(v) of a velocity of 1e-13 m/s.
TEST(Contact, RigidBaseCarriesTheBlockWithLocalDamping) {
  const Config c = read_config_string(on_rigid_base(), "drop.toml", {"solver.damping=0.05"});
  Model<2> m = build_model<2>(c);
  const int base = body_index(m, "base"), block = body_index(m, "block");
  const double block_weight = body_mean(m, block).mass * kG, base_weight = body_mean(m, base).mass * kG;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  run_simulation<2>(m, c, no_output(), [&](const ExplicitSolver<2>& s) {
    if (s.time() < 0.3) return;
    const double r = s.reaction(base)[1] - base_weight;
    lo = std::min(lo, r), hi = std::max(hi, r);
  });
  std::printf("damped: contact force over 0.3 - 0.4 s from %.2f to %.2f N/m, block weight %.2f\n", lo, hi,
              block_weight);
  EXPECT_NEAR(lo, block_weight, 0.02 * block_weight);
  EXPECT_NEAR(hi, block_weight, 0.02 * block_weight);
}

// The block on the frictional floor y_min (mu 0.3), gravity ramped over 0.02 s, no damping: the
// wall's force on the material (ContactStage::wall_force), averaged over 0.1 - 0.2 s, is the
// block's weight, up, within 1 %, and 0 along the wall (measured +0.0002 %); with damping 0.05 as
// well (measured -0.0000 %, and at the last step too: before the wall's nodes were spared the
// damping force a single step's was off by up to 1.16 %).
TEST(Contact, FrictionalFloorCarriesTheBlocksWeight) {
  std::string input = replace(kRestingBlock, "min = [0.1, 0.1]\nmax = [0.5, 0.2]", "min = [0.1, 0.0]\nmax = [0.5, 0.1]");
  input = replace(input, "gravity = [0.0, -9.81]", "gravity = [0.0, -9.81]\ngravity_function = \"ramp\"");
  input = replace(input, "[solver]", R"toml([[functions]]
name = "ramp"
table = [[0.0, 0.0], [0.02, 1.0]]

[boundary]
y_min = { friction = 0.3 }

[solver])toml");
  for (const double damping : {0.0, 0.05}) {
    const Config c = read_config_string(input, "floor.toml", {"time.end=0.2", "solver.damping=" + std::to_string(damping)});
    Model<2> m = build_model<2>(c);
    const double weight = body_mean(m, 0).mass * kG;
    Vec<2> mean = Vec<2>::Zero(), last = Vec<2>::Zero();
    int n = 0;
    run_simulation<2>(m, c, no_output(), [&](const ExplicitSolver<2>& s) {
      ASSERT_EQ(s.contact().wall_force().size(), 1u);
      last = s.contact().wall_force()[0];
      if (s.time() > 0.1) mean += last, ++n;
    });
    mean /= n;
    std::printf("frictional floor, damping %.2f: wall force over 0.1 - 0.2 s (%.4f, %.4f) N/m, at the end (%.4f, "
                "%.4f), weight %.4f N/m (mean %+.4f %%, end %+.4f %%)\n",
                damping, mean[0], mean[1], last[0], last[1], weight, 100.0 * (mean[1] / weight - 1.0),
                100.0 * (last[1] / weight - 1.0));
    EXPECT_NEAR(mean[1], weight, 0.01 * weight);
    EXPECT_NEAR(mean[0], 0.0, 1e-3 * weight);
  }
}

}  // namespace
}  // namespace tsuchi
