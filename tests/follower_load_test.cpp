// Follower pressures (`follow = true` on a pressure, docs/input.md): the area update of eq N1
// (solver/follower_area.hpp) against Nanson's relation, and a block compressed to large strain
// under a follower pressure against the closed form, in 2D and 3D, with every scheme and kernel.
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/model/model.hpp"
#include "tsuchi/run/simulation.hpp"
#include "tsuchi/solver/follower_area.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

namespace {

using namespace tsuchi;
using namespace tsuchi::test;

// A step whose deformation gradient is exactly dF: L = (dF - I) / dt.
template <int D>
Vec<D> after(const Vec<D>& a, const Mat<D>& dF, double dt = 1e-3) {
  return follow_area<D>(a, Mat<D>((dF - Mat<D>::Identity()) / dt), dt);
}

TEST(FollowerArea, RigidRotationTurnsTheNormalAndKeepsTheArea) {
  const double t = 0.7;  // rad
  Mat<2> R2;
  R2 << std::cos(t), -std::sin(t), std::sin(t), std::cos(t);
  const Vec<2> a2(0.3, -0.2);
  const Vec<2> b2 = after<2>(a2, R2);
  EXPECT_NEAR(b2.norm(), a2.norm(), 1e-14);
  EXPECT_NEAR((b2 - R2 * a2).norm(), 0.0, 1e-14);  // the normal turns with the material

  // 3D: a rotation about an oblique axis (Rodrigues).
  const Vec<3> k = Vec<3>(1.0, 2.0, -0.5).normalized();
  Mat<3> K;
  K << 0.0, -k[2], k[1], k[2], 0.0, -k[0], -k[1], k[0], 0.0;
  const Mat<3> R3 = Mat<3>::Identity() + std::sin(t) * K + (1.0 - std::cos(t)) * K * K;
  const Vec<3> a3(0.1, -0.4, 0.25);
  const Vec<3> b3 = after<3>(a3, R3);
  EXPECT_NEAR(b3.norm(), a3.norm(), 1e-14);
  EXPECT_NEAR((b3 - R3 * a3).norm(), 0.0, 1e-14);
}

TEST(FollowerArea, StretchScalesTheAreaAsNansonSays) {
  // a = J F^-T a_0: along axis d, the product of the other stretches (2D plane strain: the
  // thickness keeps its 1 m, so the other in-plane stretch).
  const Vec<2> a2 = after<2>(Vec<2>(1.0, 2.0), Vec<2>(1.5, 0.8).asDiagonal());
  EXPECT_NEAR(a2[0], 0.8 * 1.0, 1e-14);
  EXPECT_NEAR(a2[1], 1.5 * 2.0, 1e-14);
  const Vec<3> a3 = after<3>(Vec<3>(1.0, 2.0, 3.0), Vec<3>(1.5, 0.8, 1.2).asDiagonal());
  EXPECT_NEAR(a3[0], 0.8 * 1.2 * 1.0, 1e-14);
  EXPECT_NEAR(a3[1], 1.5 * 1.2 * 2.0, 1e-14);
  EXPECT_NEAR(a3[2], 1.5 * 0.8 * 3.0, 1e-14);

  // A general F (stretch, shear and turn): J F^-T, and steps compose as the deformation does.
  Mat<3> F1, F2;
  F1 << 1.2, 0.3, -0.1, 0.05, 0.9, 0.2, -0.15, 0.1, 1.1;
  F2 << 0.95, -0.2, 0.0, 0.1, 1.3, 0.05, 0.2, 0.0, 0.85;
  const Vec<3> a0(0.2, -0.7, 0.4);
  const Vec<3> nanson = (F1.determinant() * F1.inverse().transpose()) * a0;
  EXPECT_NEAR((after<3>(a0, F1) - nanson).norm(), 0.0, 1e-13);
  const Mat<3> F = F2 * F1;
  const Vec<3> whole = (F.determinant() * F.inverse().transpose()) * a0;
  EXPECT_NEAR((after<3>(after<3>(a0, F1), F2) - whole).norm(), 0.0, 1e-13);
  Mat<2> G;
  G << 1.1, 0.4, -0.2, 0.7;
  const Vec<2> b0(0.5, 0.3);
  EXPECT_NEAR((after<2>(b0, G) - (G.determinant() * G.inverse().transpose()) * b0).norm(), 0.0, 1e-14);
}

// An elastic block on rollers (x = 0, y = 0 and, in 3D, z = 0: a quarter of a block free at its
// sides) pressed by a pressure p = E / 4 on its top, ramped over 1 s (the P wave crosses it in
// 0.03 s) with local damping. Uniaxial stress sigma_yy = -p (true stress under a follower), and the
// hypoelastic law integrates the rate of deformation to logarithmic strains: in 3D ln l_y = -p/E,
// in plane strain ln l_y = -(1 - nu^2) p/E, l_y = 0.797 (20 % shorter, 9 % wider; 3D: 0.779, the
// top 12 % larger). A dead load keeps the force p A_0, so the true stress is p / l_x in 2D, and the
// block is compressed less (l_y = 0.812). Measured with GIMP at 8 cells across (2 particles per
// cell): l_y 0.4 % (2D) and 0.8 % (3D) above the closed form with every scheme; the top particles'
// forces grow with their own lateral stretch to 0.4 % (0.8 % with linear shape functions).
const char* kBlock2 = R"([model]
dimension = 2

[[functions]]
name = "ramp"
table = [[0.0, 0.0], [1.0, 1.0]]

[grid]
extent = [0.6, 1.2]
cell_size = 0.05

[[materials]]
name = "m"
model = "linear_elastic"
density = 1000.0
youngs_modulus = 1.0e6
poisson_ratio = 0.3

[[bodies]]
name = "block"
material = "m"
min = [0.0, 0.0]
max = [0.4, 1.0]
particles_per_cell = 2

[[loads]]
kind = "traction"
body = "block"
plane = { point = [0.0, 1.0], normal = [0.0, 1.0] }
pressure = 0.25e6
function = "ramp"
follow = true

[boundary]
x_min = "roller"
y_min = "roller"

[solver]
damping = 0.3

[time]
end = 1.3
courant = 0.5
)";

const char* kBlock3 = R"([model]
dimension = 3

[[functions]]
name = "ramp"
table = [[0.0, 0.0], [1.0, 1.0]]

[grid]
extent = [0.4, 0.8, 0.4]
cell_size = 0.05

[[materials]]
name = "m"
model = "linear_elastic"
density = 1000.0
youngs_modulus = 1.0e6
poisson_ratio = 0.3

[[bodies]]
name = "block"
material = "m"
min = [0.0, 0.0, 0.0]
max = [0.2, 0.6, 0.2]
particles_per_cell = 2

[[loads]]
kind = "traction"
body = "block"
plane = { point = [0.0, 0.6, 0.0], normal = [0.0, 1.0, 0.0] }
pressure = 0.25e6
function = "ramp"
follow = true

[boundary]
x_min = "roller"
y_min = "roller"
z_min = "roller"

[solver]
damping = 0.3

[time]
end = 1.3
courant = 0.5
)";

struct Stretch {
  double y = 0.0;  // mean y / y0 over the block
  // Of the loaded particles two cells or more from the free sides (where the nodal velocities
  // around them follow the motion of the material): the mean |F| / |F_0|, and the mean lateral
  // stretch of the same particles, x / x0 (times z / z0 in 3D), the area ratio of their top.
  double force = 0.0, area = 0.0;
  double all = 0.0;  // |sum F| / |sum F_0| over every loaded particle
};

template <int D>
Stretch compress(const std::string& text, const std::vector<std::string>& sets) {
  const Config c = read_config_string(text, "block.toml", sets);
  Model<D> m = build_model<D>(c);
  const Model<D> start = m;
  run_simulation<D>(m, c, no_output());
  const auto& p = m.particles;
  Stretch s;
  for (std::size_t i = 0; i < p.size(); ++i) s.y += p.x_p[i][1] / (p.x_p[i][1] - p.u_p[i][1]);
  s.y /= static_cast<double>(p.size());
  std::vector<std::size_t> at(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) at[static_cast<std::size_t>(p.id_p[i])] = i;
  const double width = D == 2 ? 0.4 : 0.2, h = m.grid.h;
  const auto& load = m.loads.surface[0];
  const auto& load0 = start.loads.surface[0];
  Vec<D> sum = Vec<D>::Zero(), sum0 = Vec<D>::Zero();
  int n = 0;
  for (std::size_t e = 0; e < load.id.size(); ++e) {
    sum += load.force[e], sum0 += load0.force[e];
    const std::size_t i = at[static_cast<std::size_t>(load.id[e])];
    const Vec<D> x = p.x_p[i], x0 = p.x_p[i] - p.u_p[i];
    double area = x[0] / x0[0];
    bool inner = x0[0] < width - 2.0 * h;
    if constexpr (D == 3) inner = inner && x0[2] < width - 2.0 * h, area *= x[2] / x0[2];
    if (!inner) continue;
    s.force += load.force[e].norm() / load0.force[e].norm(), s.area += area, ++n;
  }
  s.force /= n, s.area /= n;
  s.all = sum.norm() / sum0.norm();
  return s;
}

TEST(FollowerPressure, BlockCompressedToLargeStrainFollowsTheClosedForm) {
  const double nu = 0.3, q = 0.25;  // p / E
  for (const std::string scheme : {"musl", "usl", "usf"})
    for (const std::string kernel : {"gimp", "linear"}) {
      // Linear shape functions with USL crush a top particle at 16 % compression (exit 8), with USF
      // throw one out of the grid (exit 7), under a dead load as under a follower: cell-crossing
      // trouble of those schemes, not the load's. Linear runs with MUSL here.
      if (scheme != "musl" && kernel == "linear") continue;
      // Linear shape functions compress the block 8-10 % beyond the closed form at 8 cells across
      // (a dead load alike); their follower still carries its particles' own stretch, checked here.
      const bool gimp = kernel == "gimp";
      SCOPED_TRACE(scheme + " " + kernel);
      const std::vector<std::string> sets = {"solver.scheme=\"" + scheme + "\"", "solver.shape_function=\"" + kernel + "\""};
      {
        const Stretch s = compress<2>(kBlock2, sets);
        const double ly = std::exp(-(1.0 - nu * nu) * q);
        if (gimp) {
          EXPECT_NEAR(s.y / ly, 1.0, 0.01) << s.y;
        }
        EXPECT_NEAR(s.force / s.area, 1.0, 0.01) << s.force;
      }
      {
        const Stretch s = compress<3>(kBlock3, sets);
        const double ly = std::exp(-q);
        if (gimp) {
          EXPECT_NEAR(s.y / ly, 1.0, 0.01) << s.y;
        }
        EXPECT_NEAR(s.force / s.area, 1.0, 0.01) << s.force;
      }
    }
}

TEST(FollowerPressure, DeadLoadDepartsFromTheClosedForm) {
  // Without `follow` the force stays p A_0: the block ends near the dead load's own solution,
  // ln l_y = -(1 - nu^2) q / l_x with ln l_x = nu (1 + nu) q / l_x, not the follower's.
  const double nu = 0.3, q = 0.25;
  const Stretch s = compress<2>(replace(kBlock2, "follow = true\n", ""), {});
  double lx = 1.0;
  for (int k = 0; k < 100; ++k) lx = std::exp(nu * (1.0 + nu) * q / lx);
  const double ly_dead = std::exp(-(1.0 - nu * nu) * q / lx), ly_follow = std::exp(-(1.0 - nu * nu) * q);
  EXPECT_NEAR(s.y / ly_dead, 1.0, 0.01) << s.y;
  EXPECT_GT(s.y / ly_follow, 1.015) << s.y;  // 1.9 % above
  EXPECT_NEAR(s.all, 1.0, 1e-12);  // the dead force is the initial one
}

}  // namespace
