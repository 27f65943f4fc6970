// The grid frames' projection (solver/grid_projection.hpp, eq P1): the nodal masses sum to the
// particles' mass, a field linear in the position comes back exact at the nodes the particles
// surround on every side, nodes no particle reaches hold nothing, and the grid frame's points and
// cells are those of the nodes with mass (io/grid_vtu_writer.hpp).
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/io/grid_vtu_writer.hpp"
#include "tsuchi/model/model.hpp"
#include "tsuchi/solver/grid_projection.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>

namespace {

using namespace tsuchi;

// A block of 2 x 2 (x 2) particles per cell, 0.3 m to 0.7 m in a 1 m grid of 0.1 m cells, resting
// on the fixed base in `on_base` (its GIMP domains then touch the grid's edge).
template <int D>
Model<D> block(const std::string& shape, bool on_base) {
  const std::string lo = on_base ? "0.0" : "0.3";
  const std::string text =
      D == 2 ? "[model]\ndimension = 2\n[grid]\nextent = [1.0, 1.0]\ncell_size = 0.1\n"
             : "[model]\ndimension = 3\n[grid]\nextent = [1.0, 1.0, 1.0]\ncell_size = 0.1\n";
  const std::string body =
      D == 2 ? "min = [0.3, " + lo + "]\nmax = [0.7, 0.7]\n" : "min = [0.3, " + lo + ", 0.3]\nmax = [0.7, 0.7, 0.7]\n";
  const Config c = read_config_string(
      text +
          "[[materials]]\nname = \"soil\"\nmodel = \"linear_elastic\"\ndensity = 2000.0\nyoungs_modulus = 1.0e7\n"
          "poisson_ratio = 0.3\n[[bodies]]\nname = \"block\"\nmaterial = \"soil\"\n" + body +
          "[boundary]\ny_min = \"fixed\"\n[solver]\nshape_function = \"" + shape + "\"\n[time]\nend = 0.001\n",
      "block.toml");
  return build_model<D>(c);
}

// sigma_xx = 1000 + 2000 x - 500 y (Pa), sigma_xy = 300 z, velocity (1, -2, 3) m/s: each particle
// holds the field at its position.
template <int D>
double linear_sxx(const Vec<D>& x) {
  return 1000.0 + 2000.0 * x[0] - 500.0 * x[1];
}

template <int D>
void set_linear_fields(Model<D>& m) {
  auto& p = m.particles;
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.sigma_p[i].setZero();
    p.sigma_p[i][0] = linear_sxx<D>(p.x_p[i]);
    for (int d = 0; d < D; ++d) p.v_p[i][d] = d == 0 ? 1.0 : d == 1 ? -2.0 : 3.0;
  }
}

template <int D>
void check_projection(const std::string& shape, bool on_base) {
  SCOPED_TRACE(shape + (on_base ? ", on the base" : ", inside"));
  Model<D> m = block<D>(shape, on_base);
  set_linear_fields(m);
  const GridProjection<D> g = project_to_grid<D>(m, {"velocity", "stress"});
  ASSERT_EQ(g.stride, D + (D == 2 ? 4 : 6));
  double particle_mass = 0.0, node_mass = 0.0;
  for (std::size_t i = 0; i < m.particles.size(); ++i) particle_mass += m.particles.m_p[i];
  for (const double mi : g.m) node_mass += mi;
  EXPECT_NEAR(node_mass, particle_mass, 1e-14 * particle_mass);  // sum_i S_ip = 1, eq (P1)
  // Nodes whose whole support the particles fill: 0.4 <= x <= 0.6 (and y, z); on the base, y from 0.
  const double y_lo = on_base ? 0.0 : 0.4;
  int interior = 0;
  for (std::size_t b = 0; b < g.nodes(); ++b) {
    const std::array<int, D> ijk = g.ijk(b);
    const Vec<D> x = m.grid.position(ijk);
    bool inner = true;
    for (int d = 0; d < D; ++d) {
      const double lo = d == 1 ? y_lo : 0.4;
      inner = inner && x[d] > lo - 1e-9 && x[d] < 0.6 + 1e-9;
    }
    // The block's domains cover 0.3..0.7 m (y from 0 on the base): no node beyond takes mass or a value.
    bool reached = true;
    for (int d = 0; d < D; ++d) reached = reached && x[d] > (d == 1 && on_base ? 0.0 : 0.3) - 1e-9 && x[d] < 0.7 + 1e-9;
    if (!reached) {
      EXPECT_EQ(g.m[b], 0.0);
      for (int j = 0; j < g.stride; ++j) EXPECT_EQ(g.values[b * static_cast<std::size_t>(g.stride) + j], 0.0);
    }
    // A node of the base is not surrounded: its support is cut by the grid's edge.
    if (!inner || (on_base && ijk[1] == 0)) continue;
    ++interior;
    const double* q = g.values.data() + b * static_cast<std::size_t>(g.stride);
    EXPECT_NEAR(q[0], 1.0, 1e-12);                          // velocity x
    EXPECT_NEAR(q[1], -2.0, 1e-12);                         // velocity y
    EXPECT_NEAR(q[D], linear_sxx<D>(x), 1e-9);              // sigma_xx, P1 of a linear field
    EXPECT_NEAR(q[D + 1], 0.0, 1e-12);                      // sigma_yy
  }
  EXPECT_GT(interior, D == 2 ? 8 : 26);
}

TEST(GridProjection, ConservesMassAndReproducesLinearFields2D) {
  for (const char* shape : {"gimp", "ugimp", "linear"})
    for (const bool on_base : {false, true}) check_projection<2>(shape, on_base);
}

TEST(GridProjection, ConservesMassAndReproducesLinearFields3D) {
  for (const char* shape : {"gimp", "linear"})
    for (const bool on_base : {false, true}) check_projection<3>(shape, on_base);
}

// The frame: one point per node with mass, one quad per grid cell whose 4 nodes have mass. The
// block's GIMP domains fill 0.3..0.7 m, which give weight to the nodes 0.3..0.7 m only: 5 x 5
// nodes and 4 x 4 cells.
TEST(GridProjection, FrameHoldsTheNodesWithMassAndTheirCells) {
  Model<2> m = block<2>("gimp", false);
  const GridProjection<2> g = project_to_grid<2>(m, {"stress"});
  const std::string doc = grid_vtu_document<2>(m, g);
  std::smatch s;
  ASSERT_TRUE(std::regex_search(doc, s, std::regex("NumberOfPoints=\"(\\d+)\" NumberOfCells=\"(\\d+)\"")));
  EXPECT_EQ(std::stoi(s[1]), 25);
  EXPECT_EQ(std::stoi(s[2]), 16);
  const GridFrameSize size = grid_vtu_size<2>(m, {"stress"});
  EXPECT_EQ(size.points, 25u);
  EXPECT_EQ(size.cells, 16u);
  // The estimate before a run is the frame's size to within the digits of its offsets and counts.
  EXPECT_NEAR(size.bytes, static_cast<double>(doc.size()), 200.0);
  // The units in the field data, as VTK stores a string: its character codes.
  std::string codes;
  for (const char ch : std::string("stress [Pa]: Cauchy stress, tension positive, nodal value sum_p S_ip m_p q_p / m_i"))
    codes += std::to_string(static_cast<int>(ch)) + " ";
  EXPECT_NE(doc.find(codes + "0"), std::string::npos);
}

}  // namespace
