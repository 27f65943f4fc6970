// Shape functions: the 1D linear and GIMP functions (eqs 15-17) and their tensor-product stencils
// (eqs 18-19). Every check compares a computed quantity with an independent value at a stated
// tolerance.
#include "tsuchi/grid/grid.hpp"
#include "tsuchi/shape/axis_weights.hpp"
#include "tsuchi/shape/gimp.hpp"
#include "tsuchi/shape/linear.hpp"
#include "tsuchi/shape/stencil.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

namespace {

using tsuchi::Grid;
using tsuchi::Stencil;
using tsuchi::Vec;
using tsuchi::shape::gimp_dS;
using tsuchi::shape::gimp_S;
using tsuchi::shape::GimpKernel;
using tsuchi::shape::linear_dS;
using tsuchi::shape::linear_S;
using tsuchi::shape::axis_weights;
using tsuchi::shape::LinearKernel;

constexpr int kSamples = 2000;  // random particle positions per case

// A grid with a non-trivial origin and cell size; n_nodes per axis, indexed but with no fields.
template <int D>
Grid<D> make_grid(double h, int n) {
  Grid<D> g;
  const std::array<double, 3> origin{-1.3, 0.7, 2.1};
  for (int d = 0; d < D; ++d) {
    g.origin[d] = origin[static_cast<std::size_t>(d)];
    g.n_nodes[static_cast<std::size_t>(d)] = n;
  }
  g.h = h;
  g.index_axes();
  return g;
}

// Random positions at least two cells from every grid edge (the stencil drops no node there).
template <int D>
std::vector<Vec<D>> interior_points(const Grid<D>& g, int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::vector<Vec<D>> pts;
  pts.reserve(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    Vec<D> x;
    for (int d = 0; d < D; ++d) {
      const double lo = g.origin[d] + 2.0 * g.h;
      const double hi = g.origin[d] + (g.n_nodes[static_cast<std::size_t>(d)] - 3) * g.h;
      std::uniform_real_distribution<double> u(lo, hi);
      x[d] = u(rng);
    }
    pts.push_back(x);
  }
  // A few special positions: on a node, on a cell centre, a quarter into a cell.
  for (double f : {0.0, 0.5, 0.25, 0.75}) {
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = g.origin[d] + (4.0 + f) * g.h;
    pts.push_back(x);
  }
  return pts;
}

template <int D>
Vec<D> uniform_lp(double lp) {
  Vec<D> v;
  for (int d = 0; d < D; ++d) v[d] = lp;
  return v;
}

// sum_g S = 1 and sum_g G = 0 to 1e-12 (G scaled by h, i.e. relative to 1/h).
template <int D, class Kernel>
void check_partition_of_unity(double lp_over_h) {
  const Grid<D> g = make_grid<D>(0.25, 14);
  const Vec<D> lp = uniform_lp<D>(lp_over_h * g.h);
  Stencil<D, Kernel> st;
  for (const Vec<D>& x : interior_points<D>(g, kSamples, 12345u + static_cast<unsigned>(D))) {
    st.compute(g, x, lp);
    double sum = 0.0;
    Vec<D> gsum = Vec<D>::Zero();
    for (int n = 0; n < st.N; ++n) {
      sum += st.S(n);
      gsum += st.G(n);
    }
    ASSERT_NEAR(sum, 1.0, 1e-12) << "x = " << x.transpose() << ", lp/h = " << lp_over_h;
    for (int d = 0; d < D; ++d)
      ASSERT_NEAR(gsum[d] * g.h, 0.0, 1e-12) << "axis " << d << ", x = " << x.transpose();
  }
}

// sum_g S x_g = x_p and sum_g G (x) x_g = I to 1e-12.
template <int D, class Kernel>
void check_linear_reproduction(double lp_over_h) {
  const Grid<D> g = make_grid<D>(0.25, 14);
  const Vec<D> lp = uniform_lp<D>(lp_over_h * g.h);
  Stencil<D, Kernel> st;
  for (const Vec<D>& x : interior_points<D>(g, kSamples, 777u + static_cast<unsigned>(D))) {
    st.compute(g, x, lp);
    Vec<D> xs = Vec<D>::Zero();
    tsuchi::Mat<D> grad = tsuchi::Mat<D>::Zero();
    for (int n = 0; n < st.N; ++n) {
      const Vec<D> xg = g.position(g.ijk(st.node(n)));
      xs += st.S(n) * xg;
      grad += st.G(n) * xg.transpose();  // grad(i, j) = sum_g G_i x_g,j
    }
    for (int d = 0; d < D; ++d) ASSERT_NEAR(xs[d], x[d], 1e-12) << "axis " << d << ", x = " << x.transpose();
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j)
        ASSERT_NEAR(grad(i, j), i == j ? 1.0 : 0.0, 1e-12) << "(" << i << "," << j << "), x = " << x.transpose();
  }
}

constexpr std::array<double, 3> kGimpLp{0.125, 0.25, 0.5};  // l_p / L

// A kernel's K nodes lie within its declared reach of the particle's cell [i, i+1]: the block
// colouring of the scatter (grid/block_schedule.hpp) and the grid's edge tables rely on it.
template <class Kernel>
void check_reach(double lp_over_h) {
  std::mt19937_64 rng(4242u);
  std::uniform_real_distribution<double> u(1.0, 20.0);
  std::array<double, Kernel::K> w{}, dw{};
  for (int k = 0; k < kSamples; ++k) {
    const double s = k < 5 ? 5.0 + 0.25 * k : u(rng);  // on a node, a quarter, the centre, ...
    const int first = axis_weights<Kernel>(s, 1.0, lp_over_h, w.data(), dw.data());
    const int cell = static_cast<int>(std::floor(s));
    ASSERT_GE(first, cell - Kernel::reach_below) << "s = " << s;
    ASSERT_LE(first + Kernel::K - 1, cell + 1 + Kernel::reach_above) << "s = " << s;
  }
}

TEST(ShapeStencil, LinearWithinReach) { check_reach<LinearKernel>(0.25); }
TEST(ShapeStencil, GimpWithinReach) {
  for (double r : kGimpLp) check_reach<GimpKernel>(r);
}

// Stencil::scatter and Stencil::gather visit the nodes n = a + K r in increasing n, with the
// factors whose products are S(n) and G(n), bit for bit; every row of the stencil is visited in
// 2D, and in 3D at least every row with a nonzero S or G (the rows skipped have S = G = 0 at all
// their nodes).
template <int D, class Kernel>
void check_iteration(double lp_over_h) {
  const Grid<D> g = make_grid<D>(0.25, 14);
  const Vec<D> lp = uniform_lp<D>(lp_over_h * g.h);
  Stencil<D, Kernel> st;
  int skipped_rows = 0;
  for (const Vec<D>& x : interior_points<D>(g, 50, 99u)) {
    st.compute(g, x, lp);
    struct Row {
      double T;
      std::array<double, D - 1> dT;
    };
    std::vector<int> visited;  // rows, in the order scatter visits them
    int a = 0;
    st.scatter([&](double T, const std::array<double, D - 1>& dT) { return Row{T, dT}; },
               [&](std::int64_t k, double w, double dw, const Row& row) {
                 if (a == 0) {
                   // The row starting at node k, after the last one visited (interior nodes are
                   // distinct, so k names it).
                   int r = visited.empty() ? 0 : visited.back() + 1;
                   while (r < st.R && st.node(st.K * r) != k) ++r;
                   ASSERT_LT(r, st.R) << "a row visited out of order";
                   visited.push_back(r);
                 }
                 const int n = a + st.K * visited.back();
                 ASSERT_EQ(k, st.node(n));
                 ASSERT_EQ(w * row.T, st.S(n));
                 const Vec<D> G = st.G(n);
                 ASSERT_EQ(dw * row.T, G[0]);
                 for (int d = 1; d < D; ++d) ASSERT_EQ(w * row.dT[static_cast<std::size_t>(d - 1)], G[d]);
                 a = (a + 1) % st.K;
               });
    ASSERT_EQ(a, 0);
    // The rows not visited carry nothing.
    for (int r = 0; r < st.R; ++r)
      if (std::find(visited.begin(), visited.end(), r) == visited.end()) {
        ++skipped_rows;
        for (int b = 0; b < st.K; ++b) {
          ASSERT_EQ(st.S(b + st.K * r), 0.0);
          ASSERT_TRUE(st.G(b + st.K * r).isZero(0.0));
        }
      }
    if (D == 2) {
      ASSERT_EQ(static_cast<int>(visited.size()), st.R);
    }
    // Gather: the same rows and nodes; S summed along x then times T, as the stages sum.
    std::size_t row_at = 0;
    int m = 0;
    double sum = 0.0, expected = 0.0;
    st.gather(
        0.0,
        [&](double& row_sum, std::int64_t k, double w, double) {
          ASSERT_LT(row_at, visited.size());
          ASSERT_EQ(k, st.node(m + st.K * visited[row_at]));
          row_sum += w;
          ++m;
        },
        [&](const double& row_sum, double T, const std::array<double, D - 1>&) {
          ASSERT_EQ(m, st.K);
          double along = 0.0;
          for (int b = 0; b < st.K; ++b) along += st.wx[static_cast<std::size_t>(b)];
          ASSERT_EQ(row_sum, along);
          sum += T * row_sum, expected += T * along;
          m = 0, ++row_at;
        });
    ASSERT_EQ(row_at, visited.size());
    ASSERT_EQ(sum, expected);
  }
  // GIMP in 3D skips rows: a particle's support spans 2 or 3 nodes per axis.
  if (D == 3 && std::is_same_v<Kernel, GimpKernel>) {
    EXPECT_GT(skipped_rows, 0);
  }
}

TEST(ShapeStencil, IterationOrder2D) {
  check_iteration<2, LinearKernel>(0.25);
  check_iteration<2, GimpKernel>(0.25);
}
TEST(ShapeStencil, IterationOrder3D) {
  check_iteration<3, LinearKernel>(0.25);
  check_iteration<3, GimpKernel>(0.5);
}

TEST(ShapeStencil, LinearPartitionOfUnity2D) { check_partition_of_unity<2, LinearKernel>(0.25); }
TEST(ShapeStencil, LinearPartitionOfUnity3D) { check_partition_of_unity<3, LinearKernel>(0.25); }

TEST(ShapeStencil, GimpPartitionOfUnity2D) {
  for (double r : kGimpLp) check_partition_of_unity<2, GimpKernel>(r);
}
TEST(ShapeStencil, GimpPartitionOfUnity3D) {
  for (double r : kGimpLp) check_partition_of_unity<3, GimpKernel>(r);
}

TEST(ShapeStencil, LinearReproduction2D) { check_linear_reproduction<2, LinearKernel>(0.25); }
TEST(ShapeStencil, LinearReproduction3D) { check_linear_reproduction<3, LinearKernel>(0.25); }

TEST(ShapeStencil, GimpLinearReproduction2D) {
  for (double r : kGimpLp) check_linear_reproduction<2, GimpKernel>(r);
}
TEST(ShapeStencil, GimpLinearReproduction3D) {
  for (double r : kGimpLp) check_linear_reproduction<3, GimpKernel>(r);
}

// ---- 1D GIMP against eq 17 ------------------------------------------------------------------

double hat(double s, double L) { return std::max(0.0, 1.0 - std::abs(s) / L); }

// (1 / 2 l_p) * integral of the hat over [xi - l_p, xi + l_p], split at the hat's kinks -L, 0, L
// so that each piece is linear; 2-point Gauss-Legendre is exact on each piece.
double gimp_reference(double xi, double L, double lp) {
  const double a = xi - lp, b = xi + lp;
  std::vector<double> cuts{a};
  for (double k : {-L, 0.0, L})
    if (k > a && k < b) cuts.push_back(k);
  cuts.push_back(b);
  const double g = 1.0 / std::sqrt(3.0);
  double integral = 0.0;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double m = 0.5 * (cuts[i] + cuts[i + 1]), r = 0.5 * (cuts[i + 1] - cuts[i]);
    integral += r * (hat(m - g * r, L) + hat(m + g * r, L));
  }
  return integral / (2.0 * lp);
}

double gimp_reference_derivative(double xi, double L, double lp) {
  return (hat(xi + lp, L) - hat(xi - lp, L)) / (2.0 * lp);
}

TEST(GimpShape, MatchesIntegralOfHat) {
  for (double L : {1.0, 0.05}) {
    for (double r : {0.125, 0.25, 0.4, 0.5}) {
      const double lp = r * L;
      const double lo = -L - lp - 0.1 * L, hi = L + lp + 0.1 * L;
      constexpr int n = 4001;
      for (int k = 0; k < n; ++k) {
        const double xi = lo + (hi - lo) * k / (n - 1);
        ASSERT_NEAR(gimp_S(xi, L, lp), gimp_reference(xi, L, lp), 1e-10)
            << "xi/L = " << xi / L << ", lp/L = " << r << ", L = " << L;
        // dS has units 1/L: compare L * dS to 1e-10.
        ASSERT_NEAR(L * gimp_dS(xi, L, lp), L * gimp_reference_derivative(xi, L, lp), 1e-10)
            << "xi/L = " << xi / L << ", lp/L = " << r << ", L = " << L;
      }
      // Also exactly at every breakpoint.
      for (double bp : {L + lp, L - lp, lp, 0.0})
        for (double xi : {bp, -bp}) {
          EXPECT_NEAR(gimp_S(xi, L, lp), gimp_reference(xi, L, lp), 1e-10) << "breakpoint xi/L = " << xi / L;
          EXPECT_NEAR(L * gimp_dS(xi, L, lp), L * gimp_reference_derivative(xi, L, lp), 1e-10)
              << "breakpoint xi/L = " << xi / L;
        }
    }
  }
}

TEST(GimpShape, IsEvenWithOddDerivative) {
  const double L = 0.3;
  for (double r : {0.125, 0.25, 0.4, 0.5}) {
    const double lp = r * L;
    for (int k = 0; k <= 400; ++k) {
      const double xi = 1.6 * L * k / 400.0;
      EXPECT_EQ(gimp_S(xi, L, lp), gimp_S(-xi, L, lp)) << "xi/L = " << xi / L;
      EXPECT_EQ(gimp_dS(xi, L, lp), -gimp_dS(-xi, L, lp)) << "xi/L = " << xi / L;
    }
  }
}

TEST(GimpShape, ContinuousAtBreakpoints) {
  const double L = 0.7;
  const double eps = 1e-9 * L;
  for (double r : {0.125, 0.25, 0.4, 0.5}) {
    const double lp = r * L;
    for (double bp : {L + lp, L - lp, lp}) {
      for (double xi : {bp, -bp}) {
        const double sl = gimp_S(xi - eps, L, lp), sr = gimp_S(xi + eps, L, lp);
        const double dl = gimp_dS(xi - eps, L, lp), dr = gimp_dS(xi + eps, L, lp);
        EXPECT_LT(std::abs(sl - sr), 1e-7) << "S jumps at xi/L = " << xi / L << ", lp/L = " << r;
        EXPECT_LT(std::abs(dl - dr) * L, 1e-7) << "dS jumps at xi/L = " << xi / L << ", lp/L = " << r
                                              << ": " << dl << " vs " << dr;
      }
    }
  }
}

TEST(GimpShape, HandValues) {
  const double L = 2.0, lp = 0.5;  // lp = L/4
  // Centre: 1 - lp / (2 L) = 0.875.
  EXPECT_NEAR(gimp_S(0.0, L, lp), 0.875, 1e-15);
  EXPECT_NEAR(gimp_dS(0.0, L, lp), 0.0, 1e-15);
  // Linear region lp < |xi| < L - lp: the hat itself.
  EXPECT_NEAR(gimp_S(1.0, L, lp), 0.5, 1e-15);
  EXPECT_NEAR(gimp_dS(1.0, L, lp), -0.5, 1e-15);
  EXPECT_NEAR(gimp_dS(-1.0, L, lp), 0.5, 1e-15);
  // Tail at xi = L: (lp)^2 / (4 L lp) = lp / (4 L) = 1/16.
  EXPECT_NEAR(gimp_S(L, L, lp), 1.0 / 16.0, 1e-15);
  EXPECT_NEAR(gimp_dS(L, L, lp), -lp / (2.0 * L * lp), 1e-15);
  // Outside the support.
  EXPECT_EQ(gimp_S(L + lp, L, lp), 0.0);
  EXPECT_EQ(gimp_dS(-(L + lp), L, lp), 0.0);
  EXPECT_EQ(gimp_S(10.0, L, lp), 0.0);
}

// ---- GimpKernel::weights ------------------------------------------------------------------

TEST(GimpKernel, ThreeNodesAroundTheNearestOne) {
  const double L = 0.4;
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(3.0, 20.0);
  for (double r : {0.125, 0.25, 0.5}) {
    const double lp = r * L;
    for (int k = 0; k < 1000; ++k) {
      const double s = u(rng);
      std::array<double, GimpKernel::K> w{}, dw{};
      const int c = axis_weights<GimpKernel>(s, 1.0 / L, lp, w.data(), dw.data());
      ASSERT_EQ(GimpKernel::K, 3);
      // The middle node c + 1 is the nearest one (ties at half-integers accepted either way).
      const double dmid = std::abs(s - (c + 1));
      EXPECT_LE(dmid, 0.5 + 1e-12) << "s = " << s << ", first node " << c;
      EXPECT_LE(dmid, std::abs(s - c) + 1e-12);
      EXPECT_LE(dmid, std::abs(s - (c + 2)) + 1e-12);
      EXPECT_NEAR(w[0] + w[1] + w[2], 1.0, 1e-12) << "s = " << s;
      EXPECT_NEAR((dw[0] + dw[1] + dw[2]) * L, 0.0, 1e-12) << "s = " << s;
      for (int j = 0; j < 3; ++j) {
        const double xi = (s - (c + j)) * L;
        // The kernel's branch-free form equals the piecewise definition to round-off.
        EXPECT_NEAR(w[static_cast<std::size_t>(j)], gimp_S(xi, L, lp), 1e-13) << "s = " << s;
        EXPECT_NEAR(dw[static_cast<std::size_t>(j)] * L, gimp_dS(xi, L, lp) * L, 1e-13) << "s = " << s;
      }
    }
  }
}

TEST(GimpKernel, NodeExactlyUnderParticle) {
  // s on node 5: nodes 4, 5, 6 with weights (lp/4L, 1 - lp/2L, lp/4L) and the middle one nearest.
  const double L = 1.0, lp = 0.25;
  std::array<double, 3> w{}, dw{};
  const int c = axis_weights<GimpKernel>(5.0, 1.0 / L, lp, w.data(), dw.data());
  EXPECT_EQ(c, 4);
  EXPECT_NEAR(w[0], lp / (4.0 * L), 1e-15);
  EXPECT_NEAR(w[1], 1.0 - lp / (2.0 * L), 1e-15);
  EXPECT_NEAR(w[2], lp / (4.0 * L), 1e-15);
  // xi = x_p - x_v: moving the particle away from the node on its left lowers that node's weight.
  EXPECT_NEAR(dw[0], -1.0 / (2.0 * L), 1e-15);
  EXPECT_NEAR(dw[1], 0.0, 1e-15);
  EXPECT_NEAR(dw[2], 1.0 / (2.0 * L), 1e-15);
}

TEST(GimpStencil, TensorProduct3D) {
  const Grid<3> g = make_grid<3>(0.2, 12);
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Stencil<3, GimpKernel> st;
  for (int trial = 0; trial < 50; ++trial) {
    Vec<3> x, lp;
    for (int d = 0; d < 3; ++d) {
      x[d] = g.origin[d] + (3.0 + 5.0 * u(rng)) * g.h;
      lp[d] = (0.1 + 0.4 * u(rng)) * g.h;  // a different half-width on each axis
    }
    st.compute(g, x, lp);
    ASSERT_EQ(st.N, 27);
    double sum = 0.0;
    for (int n = 0; n < st.N; ++n) {
      const Vec<3> xg = g.position(g.ijk(st.node(n)));
      std::array<double, 3> s1{}, d1{};
      for (int d = 0; d < 3; ++d) {
        s1[static_cast<std::size_t>(d)] = gimp_S(x[d] - xg[d], g.h, lp[d]);
        d1[static_cast<std::size_t>(d)] = gimp_dS(x[d] - xg[d], g.h, lp[d]);
      }
      EXPECT_NEAR(st.S(n), s1[0] * s1[1] * s1[2], 1e-14) << "node " << st.node(n);
      EXPECT_NEAR(st.G(n)[0] * g.h, d1[0] * s1[1] * s1[2] * g.h, 1e-13);
      EXPECT_NEAR(st.G(n)[1] * g.h, s1[0] * d1[1] * s1[2] * g.h, 1e-13);
      EXPECT_NEAR(st.G(n)[2] * g.h, s1[0] * s1[1] * d1[2] * g.h, 1e-13);
      sum += st.S(n);
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
    // The 27 nodes are distinct.
    std::vector<std::int64_t> nodes;
    for (int n = 0; n < st.N; ++n) nodes.push_back(st.node(n));
    std::sort(nodes.begin(), nodes.end());
    EXPECT_TRUE(std::unique(nodes.begin(), nodes.end()) == nodes.end());
  }
}

TEST(GimpStencil, NodesOffTheGridGetZeroWeightAndAValidIndex) {
  // A particle a quarter cell from the lower x face: the node left of the grid is dropped.
  const Grid<2> g = make_grid<2>(0.5, 6);
  Vec<2> x(g.origin[0] + 0.25 * g.h, g.origin[1] + 2.5 * g.h);
  const Vec<2> lp = uniform_lp<2>(0.25 * g.h);
  Stencil<2, GimpKernel> st;
  st.compute(g, x, lp);
  const auto n_total = static_cast<std::int64_t>(g.size());
  double sum = 0.0;
  for (int n = 0; n < st.N; ++n) {
    EXPECT_GE(st.node(n), 0);
    EXPECT_LT(st.node(n), n_total);
    sum += st.S(n);
  }
  // What is lost is exactly the weight of the missing node at xi = 1.25 h along x.
  EXPECT_NEAR(sum, 1.0 - gimp_S(1.25 * g.h, g.h, lp[0]), 1e-12);
}

// ---- linear MPM ---------------------------------------------------------------------------

TEST(LinearShape, HandValues) {
  EXPECT_DOUBLE_EQ(linear_S(0.0, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(linear_S(0.25, 1.0), 0.75);
  EXPECT_DOUBLE_EQ(linear_S(-0.25, 1.0), 0.75);
  EXPECT_DOUBLE_EQ(linear_S(-0.5, 2.0), 0.75);
  EXPECT_DOUBLE_EQ(linear_S(1.5, 2.0), 0.25);
  EXPECT_EQ(linear_S(1.0, 1.0), 0.0);
  EXPECT_EQ(linear_S(-1.5, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(linear_dS(0.3, 1.0), -1.0);
  EXPECT_DOUBLE_EQ(linear_dS(-0.3, 0.5), 2.0);
  EXPECT_DOUBLE_EQ(linear_dS(0.9, 0.25 * 4.0), -1.0);
  EXPECT_EQ(linear_dS(1.2, 1.0), 0.0);
  EXPECT_EQ(linear_dS(-1.0, 1.0), 0.0);
}

TEST(LinearShape, KernelWeights) {
  std::array<double, 2> w{}, dw{};
  const int c = axis_weights<LinearKernel>(3.25, 1.0 / 0.5, 0.0, w.data(), dw.data());
  EXPECT_EQ(c, 3);
  EXPECT_DOUBLE_EQ(w[0], 0.75);
  EXPECT_DOUBLE_EQ(w[1], 0.25);
  EXPECT_DOUBLE_EQ(dw[0], -2.0);
  EXPECT_DOUBLE_EQ(dw[1], 2.0);
  // Consistent with the 1D function of the node distance.
  for (double s : {0.1, 2.5, 7.99}) {
    const double L = 0.3;
    const int i = axis_weights<LinearKernel>(s, 1.0 / L, 0.0, w.data(), dw.data());
    for (int k = 0; k < 2; ++k) {
      const double xi = (s - (i + k)) * L;
      EXPECT_NEAR(w[static_cast<std::size_t>(k)], linear_S(xi, L), 1e-14) << "s = " << s;
      EXPECT_NEAR(dw[static_cast<std::size_t>(k)] * L, linear_dS(xi, L) * L, 1e-14) << "s = " << s;
    }
  }
}

TEST(LinearStencil, HandValues2D) {
  // Particle at (0.25, 0.5) in cell units of the cell with lower-left node (2, 3), h = 0.5.
  Grid<2> g = make_grid<2>(0.5, 8);
  const Vec<2> x(g.origin[0] + 2.25 * g.h, g.origin[1] + 3.5 * g.h);
  Stencil<2, LinearKernel> st;
  st.compute(g, x, Vec<2>::Zero());
  ASSERT_EQ(st.N, 4);
  const std::array<double, 4> S{0.75 * 0.5, 0.25 * 0.5, 0.75 * 0.5, 0.25 * 0.5};
  const std::array<std::array<int, 2>, 4> ij{{{2, 3}, {3, 3}, {2, 4}, {3, 4}}};
  for (int n = 0; n < 4; ++n) {
    const auto k = static_cast<std::size_t>(n);
    EXPECT_EQ(st.node(n), g.index(ij[k]));
    EXPECT_NEAR(st.S(n), S[k], 1e-14);
  }
  // G = (dSx Sy, Sx dSy) with dS = -+1/h = -+2.
  EXPECT_NEAR(st.G(0)[0], -2.0 * 0.5, 1e-14);
  EXPECT_NEAR(st.G(0)[1], 0.75 * -2.0, 1e-14);
  EXPECT_NEAR(st.G(3)[0], 2.0 * 0.5, 1e-14);
  EXPECT_NEAR(st.G(3)[1], 0.25 * 2.0, 1e-14);
}

}  // namespace
