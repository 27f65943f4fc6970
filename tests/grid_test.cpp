// The tiled node storage: every node has one slot, index() and ijk() invert each other, the nodes
// of a tile are contiguous, and padding slots are recognised as such. The nodal fields. The block
// schedule: blocks of one colour never write a common node, for any kernel reach, and the active
// tiles hold every node a particle reaches. The threads' parts follow their shares of the
// particles, colour by colour, and any cut gives the same sums bit for bit; the shares follow the
// threads' measured speeds.
#include "tsuchi/grid/block_schedule.hpp"
#include "tsuchi/grid/grid.hpp"
#include "tsuchi/grid/thread_shares.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <set>
#include <vector>

namespace {

using namespace tsuchi;

template <int D>
void check_layout(const std::array<int, D>& n) {
  Grid<D> g;
  g.n_nodes = n;
  std::set<std::int64_t> used;
  std::array<int, D> ijk{};
  const std::size_t nodes = g.node_count();
  for (std::size_t k = 0; k < nodes; ++k) {
    std::size_t rest = k;
    for (int d = 0; d < D; ++d) ijk[d] = static_cast<int>(rest % n[d]), rest /= n[d];
    const std::int64_t idx = g.index(ijk);
    ASSERT_GE(idx, 0);
    ASSERT_LT(idx, static_cast<std::int64_t>(g.size()));
    ASSERT_TRUE(used.insert(idx).second) << "two nodes share slot " << idx;
    ASSERT_EQ(g.ijk(idx), ijk);
    ASSERT_TRUE(g.is_node(idx));
    // Nodes of one tile lie in one run of kTileNodes slots.
    std::array<int, D> corner{};
    for (int d = 0; d < D; ++d) corner[d] = ijk[d] / Grid<D>::T * Grid<D>::T;
    ASSERT_EQ(idx / Grid<D>::kTileNodes, g.index(corner) / Grid<D>::kTileNodes);
  }
  std::size_t padding = 0;
  for (std::size_t idx = 0; idx < g.size(); ++idx) padding += !g.is_node(static_cast<std::int64_t>(idx));
  EXPECT_EQ(padding + nodes, g.size());
  // Padding is less than one tile layer per axis.
  double bound = 1.0;
  for (int d = 0; d < D; ++d) bound *= n[d] + Grid<D>::T - 1;
  EXPECT_LE(static_cast<double>(g.size()), bound);
}

TEST(Grid, TiledLayout2D) {
  check_layout<2>({4, 4});
  check_layout<2>({5, 9});
  check_layout<2>({86, 61});  // the triaxial grid
}

TEST(Grid, TiledLayout3D) {
  check_layout<3>({4, 4, 4});
  check_layout<3>({7, 5, 10});
}

TEST(Grid, OneNodalFieldUnlessAsked) {
  Grid<2> g;
  g.n_nodes = {9, 6};
  g.allocate();
  ASSERT_EQ(g.fields.size(), 1u);
  EXPECT_EQ(g.field().m.size(), g.size());
  EXPECT_EQ(g.field().vL.size(), g.size());
  EXPECT_EQ(g.field().a.size(), g.size());  // kept by default
  EXPECT_EQ(g.bytes(), g.size() * Grid<2>::bytes_per_slot(true));
  const int k = g.add_field();
  EXPECT_EQ(k, 1);
  ASSERT_EQ(g.fields.size(), 2u);
  EXPECT_EQ(g.field(1).p.size(), g.size());
  EXPECT_EQ(g.field(1).m[3], 0.0);
  EXPECT_EQ(g.bytes(), g.size() * (Grid<2>::bytes_per_slot(true) + NodalField<2>::bytes_per_slot(true)));
}

// Without FLIP nothing reads the nodal acceleration: no field holds it, and the grid counts a
// vector less per slot and field (16 of 89 bytes in 2D).
TEST(Grid, NoAccelerationArrayUnlessKept) {
  Grid<2> g;
  g.n_nodes = {9, 6};
  g.keep_acceleration = false;
  g.allocate();
  g.add_field();
  for (const auto& n : g.fields) {
    EXPECT_TRUE(n.a.empty());
    EXPECT_EQ(n.vL.size(), g.size());
  }
  EXPECT_EQ(Grid<2>::bytes_per_slot(false), Grid<2>::bytes_per_slot(true) - sizeof(Vec<2>));
  EXPECT_EQ(g.bytes(), g.size() * (Grid<2>::bytes_per_slot(false) + NodalField<2>::bytes_per_slot(false)));
}

// Particles at random in a grid of n_nodes, scheduled for `reach`; checks the colouring and the
// active tiles against the nodes each non-empty block's particles may write.
template <int D>
void check_schedule(const std::array<int, D>& n, typename BlockSchedule<D>::Reach reach) {
  using S = BlockSchedule<D>;
  Grid<D> g;
  g.n_nodes = n;
  g.h = 0.5;
  g.index_axes();
  std::mt19937_64 rng(7u);
  std::vector<Vec<D>> x(400);
  for (auto& p : x)
    for (int d = 0; d < D; ++d) p[d] = std::uniform_real_distribution<double>(0.0, (n[d] - 1) * g.h)(rng);
  S schedule;
  schedule.build(g, x, reach);
  int P = 1;
  for (int d = 0; d < D; ++d) P *= S::colours_per_axis(reach);
  ASSERT_EQ(static_cast<int>(schedule.colour_blocks().size()), P);
  std::array<int, D> blocks{};
  for (int d = 0; d < D; ++d) blocks[d] = (n[d] - 1 + S::B - 1) / S::B;
  // Both loops may run on several threads: each writes only its own entries.
  std::vector<unsigned char> active(g.size() / Grid<D>::kTileNodes, 0);
  schedule.for_active_nodes([&](std::int64_t k) { active[static_cast<std::size_t>(k / Grid<D>::kTileNodes)] = 1; });
  for (const auto& colour : schedule.colour_blocks()) {
    std::set<std::int64_t> written;  // by the blocks of this colour
    for (const std::int32_t b : colour) {
      std::array<int, D> lo{}, hi{};
      std::int64_t rest = b;
      for (int d = 0; d < D; ++d) {
        const int c = static_cast<int>(rest % blocks[d]);
        rest /= blocks[d];
        lo[d] = std::max(0, c * S::B - reach.below);
        hi[d] = std::min(n[d] - 1, c * S::B + S::B + reach.above);
      }
      std::array<int, D> ijk = lo;
      for (bool more = true; more;) {
        const std::int64_t k = g.index(ijk);
        ASSERT_TRUE(written.insert(k).second) << "two blocks of one colour write node " << k;
        ASSERT_TRUE(active[static_cast<std::size_t>(k / Grid<D>::kTileNodes)]) << "node " << k << " in an inactive tile";
        more = false;
        for (int d = 0; d < D && !more; ++d) {
          if (ijk[d] < hi[d]) ++ijk[d], more = true;
          else ijk[d] = lo[d];
        }
      }
    }
  }
  std::vector<int> visits(x.size(), 0);
  schedule.scatter([&](std::size_t i) { ++visits[i]; });
  EXPECT_EQ(std::count(visits.begin(), visits.end(), 1), static_cast<std::ptrdiff_t>(x.size()));
}

// Every pass of the schedule takes each particle, and each slot of the active tiles, exactly
// once, whatever the thread count the parts were cut for and the team that runs them (a team of
// another size, as in a nested region, splits the lists evenly instead), and the balanced pass
// too, where threads take over blocks of the others' parts.
TEST(BlockSchedule, EveryPassTakesEachParticleOnce) {
  Grid<2> g;
  g.n_nodes = {41, 23};
  g.h = 0.5;
  g.index_axes();
  std::mt19937_64 rng(11u);
  std::vector<Vec<2>> x(3000);
  for (auto& p : x) {
    // Crowded in the lower left: parts cut by particle count differ from parts cut by area.
    const double u = std::uniform_real_distribution<double>(0.0, 1.0)(rng), v = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
    p = Vec<2>(u * u * 20.0, v * v * v * 11.0);
  }
  const int max_threads = omp_get_max_threads();
  for (const int cut_for : {1, 2, 3}) {
    omp_set_num_threads(cut_for);
    BlockSchedule<2> schedule;
    schedule.build(g, x);
    for (const int team : {1, 2, 3}) {
      omp_set_num_threads(team);
      std::vector<int> scattered(x.size(), 0), passed(x.size(), 0), balanced(x.size(), 0);
      std::vector<int> slots(g.size(), 0);
      schedule.scatter([&](std::size_t i) { ++scattered[i]; });
      schedule.for_each_particle([&](std::size_t i) { ++passed[i]; });
      schedule.begin_balanced(2);
#pragma omp parallel
      for (std::size_t pass = 0; pass < 2; ++pass)
        schedule.for_each_particle_balanced(pass, [&](std::size_t i) {
#pragma omp atomic
          ++balanced[i];
        });
      schedule.for_active_nodes([&](std::int64_t k) { ++slots[static_cast<std::size_t>(k)]; });
      const auto n = static_cast<std::ptrdiff_t>(x.size());
      EXPECT_EQ(std::count(scattered.begin(), scattered.end(), 1), n) << cut_for << " / " << team;
      EXPECT_EQ(std::count(passed.begin(), passed.end(), 1), n) << cut_for << " / " << team;
      EXPECT_EQ(std::count(balanced.begin(), balanced.end(), 2), n) << cut_for << " / " << team;
      const auto active = static_cast<std::ptrdiff_t>(schedule.active_tiles().size()) * Grid<2>::kTileNodes;
      EXPECT_EQ(std::count(slots.begin(), slots.end(), 1), active) << cut_for << " / " << team;
      EXPECT_EQ(std::count(slots.begin(), slots.end(), 0), static_cast<std::ptrdiff_t>(g.size()) - active);
    }
  }
  omp_set_num_threads(max_threads);
}

// The crowded particles of EveryPassTakesEachParticleOnce, on its grid.
std::vector<Vec<2>> crowded_particles(std::size_t n) {
  std::mt19937_64 rng(11u);
  std::vector<Vec<2>> x(n);
  for (auto& p : x) {
    const double u = std::uniform_real_distribution<double>(0.0, 1.0)(rng), v = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
    p = Vec<2>(u * u * 20.0, v * v * v * 11.0);
  }
  return x;
}

// Parts cut at uneven shares: the run of blocks thread 0 takes holds its share of the particles
// to within one block, and the scatter's sums at the nodes (each particle adds to the 4 x 4 nodes
// around its cell, in an order-sensitive floating sum) are the same bits as one thread's,
// however the parts are cut.
TEST(BlockSchedule, AnyCutGivesTheSameSums) {
  Grid<2> g;
  g.n_nodes = {41, 23};
  g.h = 0.5;
  g.index_axes();
  const std::vector<Vec<2>> x = crowded_particles(3000);
  std::vector<double> value(x.size());
  std::mt19937_64 rng(5u);
  for (double& a : value) a = std::uniform_real_distribution<double>(-1.0, 1.0)(rng) * 1e3;
  auto sums = [&](const BlockSchedule<2>& schedule) {
    std::vector<double> node(g.size(), 0.0);
    schedule.scatter([&](std::size_t i) {
      const int ci = static_cast<int>(x[i][0] / g.h), cj = static_cast<int>(x[i][1] / g.h);
      for (int dj = -1; dj <= 2; ++dj)
        for (int di = -1; di <= 2; ++di) {
          const int a = std::clamp(ci + di, 0, g.n_nodes[0] - 1), b = std::clamp(cj + dj, 0, g.n_nodes[1] - 1);
          node[static_cast<std::size_t>(g.index({a, b}))] += value[i] * (1.0 + 0.1 * di + 0.01 * dj);
        }
    });
    return node;
  };
  // Particles per block (blocks of B x B cells, 10 along x on this grid).
  std::vector<std::int64_t> in_block(10 * 6, 0);
  for (const Vec<2>& p : x)
    ++in_block[static_cast<std::size_t>(static_cast<int>(p[0] / g.h) / BlockSchedule<2>::B +
                                        10 * (static_cast<int>(p[1] / g.h) / BlockSchedule<2>::B))];
  const auto largest_block = static_cast<double>(*std::max_element(in_block.begin(), in_block.end()));
  const int max_threads = omp_get_max_threads();
  omp_set_num_threads(1);
  BlockSchedule<2> one;
  one.build(g, x);
  const std::vector<double> reference = sums(one);
  omp_set_num_threads(2);
  for (const std::vector<double>& shares : {std::vector<double>{0.5, 0.5}, {0.2, 0.8}, {0.85, 0.15}}) {
    BlockSchedule<2> two;
    two.build(g, x);
    two.cut_parts(shares);
    ASSERT_EQ(two.thread_shares(), shares);
    std::vector<int> thread_of(x.size(), -1);
    two.scatter([&](std::size_t i) { thread_of[i] = omp_get_thread_num(); });
    const auto mine = static_cast<double>(std::count(thread_of.begin(), thread_of.end(), 0));
    EXPECT_NEAR(mine, shares[0] * static_cast<double>(x.size()), largest_block) << shares[0] << " / " << shares[1];
    const std::vector<double> got = sums(two);
    EXPECT_EQ(std::memcmp(got.data(), reference.data(), got.size() * sizeof(double)), 0) << shares[0] << " / " << shares[1];
  }
  omp_set_num_threads(max_threads);
}

// The controller of the shares, fed timings by hand: a thread twice as fast gets two thirds of
// the particles, the noise of single steps does not recut, a stopped thread keeps its floor.
TEST(ThreadShares, FollowTheMeasuredSpeeds) {
  ThreadShares s;
  s.reset(2);
  EXPECT_EQ(s.shares(), (std::vector<double>{0.5, 0.5}));
  EXPECT_FALSE(s.update()) << "nothing timed yet";
  // Thread 0 takes 1,000 particles in 1 ms, thread 1 the same in 2 ms, step after step.
  bool recut = false;
  for (int step = 0; step < 40; ++step) {
    s.add(0, 1e-3, 1000);
    s.add(1, 2e-3, 1000);
    recut = s.update() || recut;
  }
  EXPECT_TRUE(recut);
  EXPECT_NEAR(s.shares()[0], 2.0 / 3.0, 1e-9);
  EXPECT_NEAR(s.shares()[0] + s.shares()[1], 1.0, 1e-15);
  // A step that moves the speeds by less than kRecut leaves the cut alone.
  s.add(0, 1e-3, 1000);
  s.add(1, 1.9e-3, 1000);
  EXPECT_FALSE(s.update());
  EXPECT_NEAR(s.shares()[0], 2.0 / 3.0, 1e-9);
  // A step in which one thread timed nothing changes nothing.
  s.add(0, 1e-3, 1000);
  EXPECT_FALSE(s.update());
  // A thread all but stopped keeps about a quarter of the even share (the floor, then the shares
  // scaled to sum 1), to within the hysteresis kRecut.
  for (int step = 0; step < 60; ++step) {
    s.add(0, 1e-3, 1000);
    s.add(1, 1.0, 1000);
    s.update();
  }
  EXPECT_NEAR(s.shares()[1], ThreadShares::kFloor * 0.5 / (1.0 + ThreadShares::kFloor * 0.5), ThreadShares::kRecut);
  // A new thread count starts afresh.
  s.reset(3);
  EXPECT_EQ(s.shares().size(), 3u);
  EXPECT_NEAR(s.shares()[2], 1.0 / 3.0, 1e-15);
}

TEST(BlockSchedule, ColoursAndActiveTilesFollowTheReach) {
  using S2 = BlockSchedule<2>;
  for (const S2::Reach r : {S2::Reach{0, 0}, S2::Reach{1, 1}, S2::Reach{1, 2}, S2::Reach{2, 3}, S2::Reach{4, 4}})
    check_schedule<2>({43, 30}, r);
  using S3 = BlockSchedule<3>;
  for (const S3::Reach r : {S3::Reach{1, 1}, S3::Reach{3, 2}}) check_schedule<3>({14, 11, 17}, r);
  // Today's kernels: 2 colours per axis, the 3^D tiles around a block.
  EXPECT_EQ(S2::colours_per_axis({1, 1}), 2);
  EXPECT_EQ(S2::colours_per_axis({2, 2}), 3);
  EXPECT_EQ(S2::tile_reach({4, 4}), 2);
}

}  // namespace
