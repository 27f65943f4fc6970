// A free grid face holds nothing (issue 41, defect 1). A GIMP domain reaching past the last row of
// nodes lost the weight of the missing node, and the stress times the lost gradient acted as a
// wall's reaction (model/free_faces.hpp): an elastic block laid on the free bottom face of the
// grid came to rest 2.7 mm down, as on a fixed base, with uGIMP and GIMP under every scheme, while
// the linear kernel let it fall. Now it leaves the grid (exit 7) in every kernel, scheme and
// dimension; a condition on the face, or on its nodes, holds it; and a block one cell above the
// face falls freely, at g t^2 / 2, until its domain reaches the face.
#include "test_support.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/model/model.hpp"
#include "tsuchi/model/start_warnings.hpp"
#include "tsuchi/solver/explicit_step.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace tsuchi;
using tsuchi::test::expect_message;

namespace {

// A 0.4 x 0.5 m elastic block on the bottom of a 1 x 1 m grid, 0.1 m cells, no [boundary].
const std::string kBlock2 = R"toml(
[model]
dimension = 2
gravity = [0.0, -9.81]

[grid]
cell_size = 0.1
extent = [1.0, 1.0]

[[materials]]
name = "soil"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3

[[bodies]]
name = "block"
material = "soil"
min = [0.3, 0.0]
max = [0.7, 0.5]

[time]
end = 0.3

[output]
frames = false
)toml";

const std::string kBlock3 = R"toml(
[model]
dimension = 3
gravity = [0.0, 0.0, -9.81]

[grid]
cell_size = 0.1
extent = [0.6, 0.6, 0.6]

[[materials]]
name = "soil"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3

[[bodies]]
name = "block"
material = "soil"
min = [0.2, 0.2, 0.0]
max = [0.4, 0.4, 0.3]

[time]
end = 0.3

[output]
frames = false
)toml";

// Steps the model until `end`; returns the fault's message ("" if none) and leaves the time.
template <int D>
std::string run_until(Model<D>& m, double end, double* reached = nullptr) {
  ExplicitSolver<D> solver(m);
  const double dt = 2e-4;
  try {
    while (solver.time() < end - 1e-12) solver.step(std::min(dt, end - solver.time()));
  } catch (const RunError& e) {
    EXPECT_EQ(exit_code::of(e.fault), exit_code::left_grid) << e.what();
    if (reached) *reached = solver.time();
    return e.what();
  }
  if (reached) *reached = solver.time();
  return "";
}

template <int D>
double mean_displacement(const Model<D>& m, int axis) {
  double s = 0.0;
  for (std::size_t i = 0; i < m.particles.size(); ++i) s += m.particles.u_p[i][axis];
  return s / static_cast<double>(m.particles.size());
}

const std::vector<std::string> kKernels = {"gimp", "ugimp", "linear"};
const std::vector<std::string> kSchemes = {"musl", "usl", "usf"};

}  // namespace

// On the free bottom face: every kernel and scheme leaves the grid, the GIMP kernels at the first
// step (the domain crosses at once), the linear one when the centres cross (a quarter cell down,
// 0.07 s of free fall). Before: GIMP and uGIMP came to rest 2.7 mm down.
TEST(FreeFace, BlockOnTheFreeBottomLeavesTheGrid2D) {
  for (const auto& kernel : kKernels)
    for (const auto& scheme : kSchemes) {
      Model<2> m = build_model<2>(read_config_string(
          kBlock2, "block.toml", {"solver.shape_function=\"" + kernel + "\"", "solver.scheme=\"" + scheme + "\""}));
      double t = 0.0;
      const std::string msg = run_until(m, 0.3, &t);
      ASSERT_FALSE(msg.empty()) << kernel << " " << scheme << ": held, mean u_y " << mean_displacement(m, 1);
      if (kernel == "linear") {
        EXPECT_NEAR(t, std::sqrt(2.0 * 0.025 / 9.81), 0.005) << msg;  // the lowest centres, 0.025 m up
      } else {
        EXPECT_EQ(t, 0.0) << msg;
        expect_message(msg, {"left the grid across the free face y_min", "of body \"block\"", "y_min = \"fixed\""});
      }
    }
}

TEST(FreeFace, BlockOnTheFreeBottomLeavesTheGrid3D) {
  for (const auto& kernel : kKernels) {
    Model<3> m = build_model<3>(read_config_string(kBlock3, "block3.toml", {"solver.shape_function=\"" + kernel + "\""}));
    const std::string msg = run_until(m, 0.3);
    ASSERT_FALSE(msg.empty()) << kernel << ": held, mean u_z " << mean_displacement(m, 2);
    if (kernel != "linear") expect_message(msg, {"across the free face z_min"});
  }
}

// The same at x_max with gravity along +x: was held at +6 mm instead of falling 0.44 m.
TEST(FreeFace, UpperFaceToo) {
  Model<2> m = build_model<2>(read_config_string(
      kBlock2, "block.toml", {"model.gravity=[9.81, 0.0]", "bodies.0.min=[0.6, 0.2]", "bodies.0.max=[1.0, 0.6]"}));
  expect_message(run_until(m, 0.3), {"across the free face x_max"});
}

// A condition on the face, or a node set holding the face's nodes, holds the block: it comes to
// rest under 0.1 mm (the elastic settlement of 0.5 m of soil, rho g H^2 / 2M = 0.09 mm at most).
TEST(FreeFace, AHeldFaceHoldsTheBlock) {
  const std::vector<std::vector<std::string>> holds = {
      {"boundary.y_min=\"fixed\""},
      {"boundary.y_min=\"roller\""},
      {"boundary.y_min={friction = 0.5}"},
      {"boundary.nodes=[{name = \"base\", min = [0.0, 0.0], max = [1.0, 0.0], fix = [\"y\"]}]"}};
  for (const auto& hold : holds) {
    Model<2> m = build_model<2>(read_config_string(kBlock2, "block.toml", hold));
    EXPECT_EQ(run_until(m, 0.3), "") << hold[0];
    EXPECT_LT(std::abs(mean_displacement(m, 1)), 2e-4) << hold[0];
  }
}

// One cell above the face the block falls freely, g t^2 / 2 within 0.5 %, until its domain
// reaches the face (0.1 m: t = 0.143 s) and the run stops there.
TEST(FreeFace, BlockAboveTheFaceFallsFreely) {
  for (const auto& kernel : kKernels) {
    Model<2> m = build_model<2>(read_config_string(
        kBlock2, "block.toml",
        {"solver.shape_function=\"" + kernel + "\"", "bodies.0.min=[0.3, 0.1]", "bodies.0.max=[0.7, 0.6]"}));
    const double t = 0.12;
    EXPECT_EQ(run_until(m, t), "") << kernel;
    const double u = mean_displacement(m, 1), ref = -0.5 * 9.81 * t * t;
    EXPECT_NEAR(u, ref, 0.005 * std::abs(ref)) << kernel;
    std::string msg = run_until(m, 0.3);
    EXPECT_FALSE(msg.empty()) << kernel;
  }
}

// `tsuchi check` and `run` warn of a body laid on a free face, naming the body, the face and the
// condition to give; a block one cell up, or on a fixed face, gets no warning.
TEST(FreeFace, StartWarningNamesBodyAndFace) {
  Config c = read_config_string(kBlock2, "block.toml");
  std::vector<std::string> w = start_warnings<2>(c, build_model<2>(c));
  ASSERT_EQ(w.size(), 1u);
  expect_message(w[0], {"8 particles of body \"block\" lie on the free face y_min", "gravity", "y_min = \"fixed\""});
  c = read_config_string(kBlock2, "block.toml", {"boundary.y_min=\"fixed\""});
  EXPECT_TRUE(start_warnings<2>(c, build_model<2>(c)).empty());
  c = read_config_string(kBlock2, "block.toml", {"bodies.0.min=[0.3, 0.1]", "bodies.0.max=[0.7, 0.6]"});
  EXPECT_TRUE(start_warnings<2>(c, build_model<2>(c)).empty());
}
