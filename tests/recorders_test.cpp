// Recorders: the particle set, the reductions and the stop bound, and their input checks.
#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/run/recorder.hpp"
#include "tsuchi/run/simulation.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <cmath>
#include <string>
#include <vector>

namespace {

using namespace tsuchi::test;

using namespace tsuchi;

// An elastic block moving at 1 m/s along x, under gravity along y, with recorders.
const std::string kMoving = R"([model]
dimension = 2
gravity = [0.0, -10.0]

[grid]
origin = [0.0, 0.0]
extent = [1.0, 0.5]
cell_size = 0.05

[[materials]]
name = "rock"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e8
poisson_ratio = 0.25

[[bodies]]
name = "block"
material = "rock"
min = [0.1, 0.1]
max = [0.3, 0.3]
velocity = [1.0, 0.0]

[[bodies]]
name = "other"
material = "rock"
min = [0.5, 0.1]
max = [0.6, 0.2]

[time]
end = 1.0
courant = 0.5

[output]
frames = false

[[recorders]]
name = "drift"
body = "block"
quantity = "displacement_x"
scale = 100.0
stop_above = 5.0

[[recorders]]
name = "bottom_row_y"
body = "block"
max = [1.0, 0.115]
quantity = "position_y"
reduction = "min"

[[recorders]]
name = "mass"
quantity = "mass"
reduction = "sum"
)";

Config config(const std::vector<std::string>& overrides = {}) { return read_config_string(kMoving, "case.toml", overrides); }

TEST(Recorders, SelectAndReduce) {
  const Config c = config();
  const Model<2> m = build_model<2>(c);
  const Recorder<2> drift(c.recorders[0], 0, m), bottom(c.recorders[1], 1, m), mass(c.recorders[2], 2, m);
  EXPECT_EQ(drift.size(), 64u);   // 4 x 4 cells, 2 x 2 particles each
  EXPECT_EQ(bottom.size(), 8u);   // the bottom row of the block: y0 = 0.1125
  EXPECT_EQ(mass.size(), 64u + 16u);
  EXPECT_DOUBLE_EQ(bottom.value(m.particles), 0.1125);
  EXPECT_NEAR(mass.value(m.particles), 2000.0 * (0.04 + 0.01), 1e-9);
  EXPECT_EQ(drift.value(m.particles), 0.0);
}

TEST(Recorders, StopBoundEndsTheRunAtTheFirstCrossing) {
  Config c = config();
  Model<2> m = build_model<2>(c);
  const Recorder<2> drift(c.recorders[0], 0, m);
  double before = 0.0, last = 0.0;
  const RunSummary s = run_simulation<2>(m, c, no_output(), [&](const ExplicitSolver<2>&) {
    before = last;
    last = drift.value(m.particles);
  });
  // Free flight at 1 m/s: 5 cm of drift at t = 0.05 s.
  EXPECT_NE(s.stopped_by.find("drift reached"), std::string::npos) << s.stopped_by;
  EXPECT_GE(last, 5.0);
  EXPECT_LT(before, 5.0);
  EXPECT_NEAR(s.time, 0.05, 2e-3);
}

// A run a recorder stops at t = 0.05 s of time.end = 1 s: the progress (and so the ETA) follows the
// recorder's way to its bound, not the time, which would say 5 % at the end (issue 13).
TEST(Recorders, ProgressFollowsTheRecorderThatStopsTheRun) {
  Config c = config();
  Model<2> m = build_model<2>(c);
  const Recorder<2> drift(c.recorders[0], 0, m);
  RunOptions o = no_output();
  std::vector<Progress> seen;
  o.on_progress = [&](const Progress& p) {
    seen.push_back(p);
    const double expected = std::min(1.0, drift.value(m.particles) / 5.0);
    ASSERT_NEAR(p.fraction, expected, 1e-12) << "step " << p.step;
    ASSERT_EQ(p.leader, "drift");
    ASSERT_EQ(p.leader_bound, 5.0);
    ASSERT_GT(p.fraction, 10.0 * p.time / p.end_time) << "the time would say about 5 % of this";
  };
  const RunSummary s = run_simulation<2>(m, c, o);
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.back().fraction, 1.0);
  EXPECT_EQ(seen.back().step, s.steps);
  // The program's progress lines say the same: the last one 100 % with the recorder's value.
  TempDir tmp("tsuchi_recorders");
  write_file(tmp.path / "moving.toml", kMoving);
  const ProgramResult r = run_program("run " + quoted(tmp.path / "moving.toml") + " -o " + quoted(tmp.path / "out"));
  ASSERT_EQ(r.status, exit_code::ok) << r.output;
  expect_message(r.output, {"% step ", " drift=", "/5 t=", "100.0% step " + std::to_string(s.steps) + " drift=5"});
}

// A recorder as the frame label, and frames by its value (issue 13): every 1 cm of drift of a block
// moving at 1 m/s. The .pvd's timestep is the drift, each frame written after the step that
// passes the next whole centimetre (about 0.01 cm per step).
TEST(Recorders, FramesLabelledAndScheduledByARecorder) {
  TempDir tmp("tsuchi_recorders");
  const Config c = config({"time.end=0.035", "output.frames=true", "output.frame_label=\"drift\"",
                           "output.label_interval=1.0", "output.fields=[\"id\"]"});
  Model<2> m = build_model<2>(c);
  RunOptions o;
  o.output_directory = (tmp.path / "out").string();
  const RunSummary s = run_simulation<2>(m, c, o);
  std::ifstream in(tmp.path / "out" / "particles.pvd");
  const std::string pvd{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  std::vector<double> labels;
  const std::string key = "timestep=\"";
  for (auto at = pvd.find(key); at != std::string::npos; at = pvd.find(key, at + 1))
    labels.push_back(std::stod(pvd.substr(at + key.size())));
  ASSERT_EQ(labels.size(), 5u) << pvd;  // t = 0, drift 1, 2, 3 cm, and the end (3.5 cm)
  EXPECT_EQ(s.frames, 5u);
  EXPECT_EQ(labels[0], 0.0);
  for (int k = 1; k <= 3; ++k) {
    EXPECT_GE(labels[static_cast<std::size_t>(k)], k) << pvd;
    EXPECT_LT(labels[static_cast<std::size_t>(k)], k + 0.02) << pvd;
  }
  EXPECT_NEAR(labels[4], 3.5, 0.02) << pvd;
  // The label must name a recorder.
  try {
    config({"output.frame_label=\"strain\""});
    ADD_FAILURE() << "an unknown frame_label was accepted";
  } catch (const InputError& e) {
    expect_message(e.what(), {"key 'output.frame_label'", "expected the name of a recorder (\"drift\", \"bottom_row_y\", \"mass\"), got \"strain\""});
  }
}

// `check`'s step estimate ignored the stop bounds (issue 13). A recorder of a platen's displacement
// (prescribed velocity) changes at a known rate: 100 * 1 m/s * t reaches 5 at t = 0.05 s, so the
// estimate goes to 0.05 s and not to time.end; and a time.end of 1e6 s is no longer refused as
// 1e10 steps when the platen stops the run after 500.
TEST(Recorders, CheckForeseesThePlatenStop) {
  const Config c = config({"bodies.0.prescribed_velocity={x=1.0}", "time.end=1e6"});
  const auto stop = forecast_stop(c);
  ASSERT_TRUE(stop.has_value());
  EXPECT_EQ(stop->recorder, "drift");
  EXPECT_NEAR(stop->time, 0.05, 1e-15);
  EXPECT_NO_THROW(check_run_length(c, 1e-4));
  EXPECT_THROW(check_run_length(config({"time.end=1e6"}), 1e-4), InputError);  // free flight: not foreseeable
  EXPECT_FALSE(forecast_stop(config()).has_value());
  TempDir tmp("tsuchi_recorders");
  write_file(tmp.path / "moving.toml", kMoving);
  const ProgramResult r = run_program("check " + quoted(tmp.path / "moving.toml") +
                                      " --set 'bodies.0.prescribed_velocity={x=1.0}' --set time.end=1e6");
  ASSERT_EQ(r.status, exit_code::ok) << r.output;
  expect_message(r.output, {"to t = 0.05 s, where drift reaches 5 and stops the run (time.end = 1000000 s)"});
}

TEST(Recorders, BadInputNamesTheKey) {
  const struct {
    std::string override_, key, words;
  } cases[] = {
      {"recorders.0.quantity=\"stress\"", "recorders.0.quantity", "\"stress_xy\""},
      {"recorders.0.quantity=\"velocity_z\"", "recorders.0.quantity", "expected one of"},
      {"recorders.0.body=\"lid\"", "recorders.0.body", "\"block\", \"other\""},
      {"recorders.1.name=\"drift\"", "recorders.1.name", "defined twice"},
      {"recorders.1.name=\"time\"", "recorders.1.name", "column of its own"},
      {"recorders.1.name=\"q kPa\"", "recorders.1.name", "letters, digits and _"},
      {"recorders.2.reduction=\"median\"", "recorders.2.reduction", "\"max\""},
      {"recorders.1.max=[1.0]", "recorders.1.max", "2 numbers"},
  };
  for (const auto& bc : cases) {
    try {
      config({bc.override_});
      ADD_FAILURE() << bc.override_ << " accepted";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(bc.key), std::string::npos) << msg;
      EXPECT_NE(msg.find(bc.words), std::string::npos) << msg;
    }
  }
  // A box that holds no particle of the body is found when the recorders are made, before a run.
  try {
    const Config c = config({"recorders.1.max=[1.0, 0.05]"});
    make_recorders<2>(c, build_model<2>(c));
    ADD_FAILURE() << "empty selection accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("selects no particle"), std::string::npos) << e.what();
  }
}

}  // namespace
