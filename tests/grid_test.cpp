// The tiled node storage: every node has one slot, index() and ijk() invert each other, the nodes
// of a tile are contiguous, and padding slots are recognised as such.
#include "tsuchi/grid/grid.hpp"

#include <gtest/gtest.h>

#include <set>

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

}  // namespace
