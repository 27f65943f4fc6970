// Checkpoints and restarts (issue 6): a run stopped at step K and restarted from its checkpoint
// ends bitwise where the uninterrupted run ends (particles, stresses, CSVs, frames), for an
// elastic case and a reduced Mohr-Coulomb triaxial case; a checkpoint of another input, another
// dimension, or a damaged file is refused with a clear message and nothing written. Faults end the
// run with their own exit code and a message saying what, where and what to try.
#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/checkpoint.hpp"
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/model/model.hpp"
#include "tsuchi/solver/explicit_step.hpp"

#include "test_support.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <regex>

namespace {

using namespace tsuchi;
using namespace tsuchi::test;

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Every regular file of a directory by name, with its bytes.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file()) files[e.path().filename().string()] = read_bytes(e.path());
  return files;
}

const char* elastic_input = R"([model]
dimension = 2
gravity = [0.0, -9.81]

[grid]
extent = [0.4, 1.0]
cell_size = 0.05

[[materials]]
name = "soil"
model = "linear_elastic"
density = 1800.0
youngs_modulus = 2.0e6
poisson_ratio = 0.3

[[bodies]]
name = "column"
material = "soil"
min = [0.1, 0.0]
max = [0.3, 0.6]
particles_per_cell = [2, 2]
velocity = [0.3, 0.0]

[boundary]
y_min = "fixed"
x_min = "roller"
x_max = "roller"

[solver]
damping = 0.02

[time]
end = 10.0
courant = 0.4

[output]
interval = 0.02
fields = ["displacement", "velocity", "stress", "strain", "volume"]

[[recorders]]
name = "top_v"
min = [0.0, 0.55]
quantity = "displacement_y"
)";

struct Case {
  std::string input;  // file
  std::vector<std::string> sets;
};

std::string args(const Case& c, const fs::path& out, std::int64_t max_steps, std::int64_t every) {
  std::string a = "run -q " + quoted(fs::path(c.input)) + " -o " + quoted(out);
  for (const auto& s : c.sets) a += " --set " + s;
  a += " --set time.max_steps=" + std::to_string(max_steps) + " --set checkpoint.every_steps=" + std::to_string(every);
  return a;
}

// Runs to `total` steps in one go, and to `split` then on from its checkpoint to `total`; the two
// output directories must be identical file by file, the final checkpoints included.
void expect_bitwise_restart(const Case& c, const TempDir& tmp, std::int64_t split, std::int64_t total) {
  const fs::path whole = tmp.path / "whole", parts = tmp.path / "parts";
  const ProgramResult a = run_program(args(c, whole, total, split));
  ASSERT_EQ(a.status, exit_code::ok) << a.output;
  const ProgramResult b = run_program(args(c, parts, split, split));
  ASSERT_EQ(b.status, exit_code::ok) << b.output;
  const fs::path ck = parts / "checkpoint.tsuchi";
  ASSERT_TRUE(fs::exists(ck)) << b.output;
  const std::string ck_copy = read_bytes(ck);
  const ProgramResult r = run_program(args(c, parts, total, split) + " --restart " + quoted(ck));
  ASSERT_EQ(r.status, exit_code::ok) << r.output;

  const auto x = snapshot(whole), y = snapshot(parts);
  ASSERT_GT(x.size(), 4u);
  for (const auto& [name, bytes] : x) {
    ASSERT_TRUE(y.count(name)) << name << " is missing after the restart";
    EXPECT_TRUE(y.at(name) == bytes) << name << " differs after the restart";
  }
  EXPECT_EQ(x.size(), y.size());
  EXPECT_NE(ck_copy, x.at("checkpoint.tsuchi")) << "the comparison is of a later state than the split";
}

TEST(Restart, ElasticRunContinuesBitwise) {
  TempDir tmp("tsuchi_restart");
  write_file(tmp.path / "column.toml", elastic_input);
  expect_bitwise_restart({(tmp.path / "column.toml").string(), {}}, tmp, 137, 400);
}

// A base shaken by an acceleration pulse (examples/shaking_column, with the base's reaction
// recorded): the driven velocity is a function of the time alone, so the restart split inside the
// pulse continues bitwise.
TEST(Restart, ShakenBaseContinuesBitwise) {
  TempDir tmp("tsuchi_restart");
  const Case c{std::string(TSUCHI_SOURCE_DIR) + "/examples/shaking_column/column.toml", {"output.interval=0.05"}};
  expect_bitwise_restart(c, tmp, 97, 300);
}

// Contact keeps no state between steps (it is decided from each step's velocities), and a free
// rigid body's velocity lives in its particles: the disks in frictional contact (split during the
// impact) and the free rigid block sliding on its base continue bitwise, the contact frames
// (contact_NNNNNN.vtu, contact.pvd) and the contact_nodes column included.
TEST(Restart, ContactContinuesBitwise) {
  TempDir tmp("tsuchi_restart");
  const Case disks{std::string(TSUCHI_SOURCE_DIR) + "/examples/disk_collision/disks.toml",
                   {"contact.0.friction=0.3", "output.interval=0.25"}};
  expect_bitwise_restart(disks, tmp, 61, 150);
}

TEST(Restart, FreeRigidBodyContinuesBitwise) {
  TempDir tmp("tsuchi_restart");
  const Case block{std::string(TSUCHI_SOURCE_DIR) + "/examples/sliding_block/rigid_block.toml", {"output.interval=0.005"}};
  expect_bitwise_restart(block, tmp, 237, 500);
}

TEST(Restart, MohrCoulombTriaxialContinuesBitwise) {
  TempDir tmp("tsuchi_restart");
  // The triaxial test 1 with the cap fixed on a 5 mm grid, frames every 50 steps or so; the split
  // falls while the specimen is yielding.
  const Case c{std::string(TSUCHI_SOURCE_DIR) + "/examples/triaxial/test1_fixed.toml",
               {"grid.cell_size=0.005", "recorders.1.max=[1.0,0.0025]", "recorders.2.max=[1.0,0.0025]",
                "output.interval=0.05", "output.global_interval=0"}};
  expect_bitwise_restart(c, tmp, 900, 1500);
  const std::string rec = read_bytes(tmp.path / "parts" / "recorders.csv");
  EXPECT_NE(rec.find(",1500,"), std::string::npos) << "the restarted run reaches step 1500";
}

// Modified Cam-Clay's state (p_c, v, the stiffness of the time step) is in the checkpoint: a
// block squeezed undrained from 200 kPa, split while it yields, continues bitwise.
// A follower pressure's forces follow the deformation (eq N1): state that the checkpoint holds.
// The cavity of examples/cavity_expansion at 0.25 m cells, split inside the ramp.
TEST(Restart, FollowerPressureContinuesBitwise) {
  const TempDir tmp("tsuchi_follow_restart_");
  const Case c{std::string(TSUCHI_SOURCE_DIR) + "/examples/cavity_expansion/cavity.toml",
               {"grid.cell_size=0.25", "loads.0.max=[1.125,1.125]", "output.interval=0.1"}};
  expect_bitwise_restart(c, tmp, 137, 300);
}

// Stages with follower pressures: the first stage's load follows through the stage, the second
// rebuilds the loads (another pressure, reconfigure) and follows from its start; split in each.
TEST(Restart, StagedFollowerPressureContinuesBitwise) {
  const TempDir tmp("tsuchi_follow_restart_");
  write_file(tmp.path / "block.toml", R"([model]
dimension = 2

[[functions]]
name = "ramp"
table = [[0.0, 0.0], [0.1, 1.0]]

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
pressure = 0.02e6
function = "ramp"
follow = true

[boundary]
x_min = "roller"
y_min = "roller"

[solver]
damping = 0.3

[output]
interval = 0.02

[[stages]]
name = "first"
duration = 0.15

[[stages]]
name = "second"
duration = 0.3
[[stages.loads]]                 # built on the particles of the stage's start: the top row's
kind = "traction"                # centres are then near y = 0.97
body = "block"
plane = { point = [0.0, 0.98], normal = [0.0, 1.0] }
pressure = 0.2e6
function = "ramp"
follow = true
)");
  const Case c{(tmp.path / "block.toml").string(), {}};
  for (const std::int64_t split : {97, 351}) {
    SCOPED_TRACE(split);
    const TempDir run("tsuchi_follow_staged_");
    expect_bitwise_restart(c, run, split, 500);
  }
}

TEST(Restart, ModifiedCamClayContinuesBitwise) {
  TempDir tmp("tsuchi_restart");
  write_file(tmp.path / "clay.toml", kCamClayUndrainedBlock + R"(
[time]
end = 10.0
courant = 0.5

[output]
interval = 0.02
fields = ["stress", "preconsolidation_pressure", "specific_volume", "bulk_modulus", "yield_mode"]
)");
  expect_bitwise_restart({(tmp.path / "clay.toml").string(), {}}, tmp, 211, 500);
}

// Frames labelled and scheduled by a recorder (output.frame_label, output.label_interval): the
// next label frame is part of the checkpoint, so a restart writes the same frames and .pvd.
TEST(Restart, FramesByRecorderContinueBitwise) {
  TempDir tmp("tsuchi_restart");
  const Case c{std::string(TSUCHI_SOURCE_DIR) + "/examples/triaxial/test1_fixed.toml",
               {"grid.cell_size=0.005", "recorders.1.max=[1.0,0.0025]", "recorders.2.max=[1.0,0.0025]",
                "output.interval=0", "output.frame_label='\"axial_strain\"'", "output.label_interval=0.002",
                "'output.fields=[\"id\",\"max_shear_strain\"]'"}};
  expect_bitwise_restart(c, tmp, 700, 1200);
  std::ifstream in(tmp.path / "parts" / "particles.pvd");
  const std::string pvd{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  std::size_t frames = 0;
  for (auto at = pvd.find("<DataSet"); at != std::string::npos; at = pvd.find("<DataSet", at + 1)) ++frames;
  EXPECT_GE(frames, 5u) << pvd;  // t = 0, every 0.2 % of axial strain, and the end
}

// A run that ended at its time.end, restarted from its end-of-run checkpoint with a later
// time.end (docs/input.md, [checkpoint]). The first end, 0.3 s, is the third frame time of an
// interval of 0.1 s, which in doubles is 3 * 0.1 = 0.30000000000000004: the first run must stop
// where a run to the later end passes (on the frame time, not 1 ulp short of it), or the restart
// takes a sliver of a step of 5.6e-17 s to reach the frame, writes that frame twice and drifts.
TEST(Restart, LaterEndFromAFrameTimeContinuesBitwise) {
  TempDir tmp("tsuchi_restart");
  write_file(tmp.path / "column.toml", elastic_input);
  const auto run = [&](const fs::path& out, double end, bool restart) {
    std::string a = "run -q " + quoted(tmp.path / "column.toml") + " -o " + quoted(out) +
                    " --set output.interval=0.1 --set checkpoint.every_steps=1000000" +
                    " --set time.end=" + fmt::format("{}", end);
    if (restart) a += " --restart " + quoted(out / "checkpoint.tsuchi");
    const ProgramResult r = run_program(a);
    EXPECT_EQ(r.status, exit_code::ok) << r.output;
  };
  const fs::path whole = tmp.path / "whole", parts = tmp.path / "parts";
  run(whole, 0.6, false);
  run(parts, 0.3, false);
  const std::string first_end = read_bytes(parts / "checkpoint.tsuchi");
  run(parts, 0.6, true);
  const auto x = snapshot(whole), y = snapshot(parts);
  ASSERT_GT(x.size(), 8u);  // 7 frames, the .pvd, global.csv, recorders.csv, the checkpoint
  for (const auto& [name, bytes] : x) {
    ASSERT_TRUE(y.count(name)) << name << " is missing after the restart";
    EXPECT_TRUE(y.at(name) == bytes) << name << " differs after the restart";
  }
  EXPECT_EQ(x.size(), y.size()) << "the restart wrote a frame the whole run did not";
  EXPECT_NE(first_end, x.at("checkpoint.tsuchi"));
}

// The frame and row counters of a checkpoint are indices of the next frame and global.csv row.
// A crafted one (2^62) was taken as it was and the restart wrote no frame and no row more (issue 41,
// defect 13); now a counter beyond one interval past the checkpoint's time is brought back, so the
// crafted restart writes what a fair one writes, byte for byte.
TEST(Restart, CraftedCountersAreBroughtBackToTheCheckpointTime) {
  TempDir tmp("tsuchi_restart");
  write_file(tmp.path / "column.toml", elastic_input);
  const auto run = [&](const fs::path& out, const std::string& extra) {
    const ProgramResult r = run_program("run -q " + quoted(tmp.path / "column.toml") + " -o " + quoted(out) +
                                        " --set output.interval=0.05 --set output.global_interval=0.01" +
                                        " --set checkpoint.every_steps=1000000 " + extra);
    EXPECT_EQ(r.status, exit_code::ok) << r.output;
  };
  const fs::path fair = tmp.path / "fair", crafted = tmp.path / "crafted";
  run(fair, "--set time.end=0.1");
  run(crafted, "--set time.end=0.1");
  {
    const std::string ck = (crafted / "checkpoint.tsuchi").string();
    Model<2> m = build_model<2>(read_config_file((tmp.path / "column.toml").string()));
    RunProgress r = read_checkpoint<2>(ck, m);
    r.frame_index = std::int64_t{1} << 62, r.row_index = std::int64_t{1} << 62;
    write_checkpoint<2>(ck, m, r);
  }
  run(fair, "--set time.end=0.3 --restart " + quoted(fair / "checkpoint.tsuchi"));
  run(crafted, "--set time.end=0.3 --restart " + quoted(crafted / "checkpoint.tsuchi"));
  const auto x = snapshot(fair), y = snapshot(crafted);
  ASSERT_EQ(x.size(), y.size());
  ASSERT_TRUE(x.count("particles_000006.vtu"));  // frames at 0, 0.05, ..., 0.3
  for (const auto& [name, bytes] : x) {
    ASSERT_TRUE(y.count(name)) << name << " is missing after the crafted restart";
    EXPECT_TRUE(y.at(name) == bytes) << name << " differs after the crafted restart";
  }
}

// A restart with a longer output.interval counted the stored frame index in the new interval: from
// an end at 0.1 s with frames every 0.01 s (next index 11), a restart to 0.3 s every 0.05 s took
// its next frame at 11 x 0.05 = 0.55 s, beyond the end, and wrote only the last. Now it writes
// those of the new interval after the checkpoint: 0.15, 0.2, 0.25 and 0.3 s.
TEST(Restart, LongerIntervalTakesTheFramesOfTheNewOne) {
  TempDir tmp("tsuchi_restart");
  write_file(tmp.path / "column.toml", elastic_input);
  const fs::path out = tmp.path / "out";
  const auto run = [&](const std::string& extra) {
    const ProgramResult r = run_program("run -q " + quoted(tmp.path / "column.toml") + " -o " + quoted(out) +
                                        " --set checkpoint.every_steps=1000000 " + extra);
    EXPECT_EQ(r.status, exit_code::ok) << r.output;
  };
  run("--set time.end=0.1 --set output.interval=0.01");
  run("--set time.end=0.3 --set output.interval=0.05 --restart " + quoted(out / "checkpoint.tsuchi"));
  const std::string pvd = read_bytes(out / "particles.pvd");
  std::vector<double> times;
  const std::regex stamp("timestep=\"([^\"]+)\"");
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), stamp); it != std::sregex_iterator(); ++it)
    times.push_back(std::stod((*it)[1].str()));
  ASSERT_EQ(times.size(), 15u) << pvd;  // 0 ... 0.1 every 0.01, then 0.15, 0.2, 0.25, 0.3
  for (std::size_t k = 0; k < 11; ++k) EXPECT_NEAR(times[k], 0.01 * static_cast<double>(k), 1e-9);
  for (std::size_t k = 11; k < 15; ++k) EXPECT_NEAR(times[k], 0.05 * static_cast<double>(k - 8), 1e-9) << k;
}

class RefusedRestart : public ::testing::Test {
 protected:
  void SetUp() override {
    write_file(tmp.path / "column.toml", elastic_input);
    const ProgramResult r = run_program(args(c, out, 20, 10));
    ASSERT_EQ(r.status, exit_code::ok) << r.output;
    before = snapshot(out);
  }
  // The restart is refused with exit code 2 and every piece of `expected` in the message, and the
  // output directory is left exactly as it was.
  void expect_refused(const std::string& extra, const std::vector<std::string>& expected) {
    const ProgramResult r = run_program(args(c, out, 40, 10) + " " + extra);
    EXPECT_EQ(r.status, exit_code::input) << r.output;
    expect_message(r.output, expected);
    EXPECT_TRUE(snapshot(out) == before) << "a refused restart changed the output directory";
  }
  TempDir tmp{"tsuchi_restart"};
  Case c{(tmp.path / "column.toml").string(), {}};
  fs::path out = tmp.path / "out";
  fs::path ck = out / "checkpoint.tsuchi";
  std::map<std::string, std::string> before;
};

TEST_F(RefusedRestart, OtherInput) {
  expect_refused("--set materials.0.youngs_modulus=3e6 --restart " + quoted(ck),
                 {ck.string(), "written for another input"});
}

TEST_F(RefusedRestart, OtherDimension) {
  const std::string text = replace(replace(replace(replace(elastic_input, "dimension = 2", "dimension = 3"),
                                                   "[0.0, -9.81]", "[0.0, -9.81, 0.0]"),
                                           "[0.4, 1.0]", "[0.4, 1.0, 0.1]"),
                                   "particles_per_cell = [2, 2]", "particles_per_cell = [2, 2, 2]");
  write_file(tmp.path / "column3.toml",
             replace(replace(replace(text, "min = [0.1, 0.0]", "min = [0.1, 0.0, 0.0]"), "max = [0.3, 0.6]",
                             "max = [0.3, 0.6, 0.1]"),
                     "velocity = [0.3, 0.0]", "velocity = [0.3, 0.0, 0.0]"));
  c.input = (tmp.path / "column3.toml").string();
  c.sets = {"recorders.0.min=[0.0,0.55,0.0]"};
  expect_refused("--restart " + quoted(ck), {ck.string(), "holds a 2D model, the input is 3D"});
}

TEST_F(RefusedRestart, DamagedFile) {
  std::string bytes = read_bytes(ck);
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x10);
  write_file(tmp.path / "damaged.tsuchi", bytes);
  expect_refused("--restart " + quoted(tmp.path / "damaged.tsuchi"), {"damaged.tsuchi", "checksum does not match"});
  write_file(tmp.path / "short.tsuchi", read_bytes(ck).substr(0, 1000));
  expect_refused("--restart " + quoted(tmp.path / "short.tsuchi"), {"short.tsuchi", "checksum does not match"});
  write_file(tmp.path / "text.tsuchi", elastic_input);
  expect_refused("--restart " + quoted(tmp.path / "text.tsuchi"), {"text.tsuchi", "does not start like a tsuchi checkpoint"});
  expect_refused("--restart " + quoted(tmp.path / "none.tsuchi"), {"none.tsuchi", "cannot open the checkpoint"});
}

TEST_F(RefusedRestart, AllowedChangesAreAccepted) {
  // The end time, step limit, time step choice and output settings may change on a restart.
  const ProgramResult r = run_program(args(c, out, 40, 10) + " --set time.courant=0.3 --set output.interval=0.05 --restart " + quoted(ck));
  EXPECT_EQ(r.status, exit_code::ok) << r.output;
}

// The decoder itself: a checkpoint round-trips every particle array exactly (with APIC, an
// initial stress held by eq (2) and a Mohr-Coulomb material, so that the affine matrix p.C, sigma0
// and Mohr-Coulomb's state columns are among them).
TEST(Checkpoint, RoundTripsEveryParticleArray) {
  TempDir tmp("tsuchi_checkpoint");
  std::string input = elastic_input;
  input.replace(input.find("[solver]\n"), 9, "[solver]\nvelocity_transfer = \"apic\"\n");
  input.replace(input.find("model = \"linear_elastic\"\n"), 24,
                "model = \"mohr_coulomb\"\ncohesion = 5e3\nfriction_angle = 30.0\n");
  input.replace(input.find("velocity = [0.3, 0.0]\n"), 22,
                "velocity = [0.3, 0.0]\ninitial_stress = { isotropic = -1e3, subtract = true }\n");
  Model<2> m = build_model<2>(read_config_string(input, "column.toml"));
  ASSERT_EQ(m.particles.C_p.size(), m.particles.size());
  for (std::size_t i = 0; i < m.particles.size(); ++i) {
    const double s = static_cast<double>(i);
    m.particles.sigma_p[i] << -1e3 * s, 2.5 * s, 1.0 / (1.0 + s), 1e-7 * s;
    m.particles.C_p[i] << 0.5 * s, -1.0 / (2.0 + s), 3e-4 * s, -s;  // APIC's affine matrix
    (*m.particles.state_column("plastic_shear_strain"))[i] = 1e-3 * s;
    (*m.particles.state_column("yield_mode"))[i] = static_cast<double>(i % 3);
  }
  RunProgress r;
  r.time = 0.125, r.steps = 77, r.dt = 1.5e-4, r.frame_index = 3, r.row_index = 9;
  r.output.frames = {{0.0, "particles_000000.vtu"}, {0.02, "particles_000001.vtu"}};
  r.output.global_bytes = 1234567;
  r.output.global_crc = 0x89abcdefu;
  write_checkpoint<2>((tmp.path / "c.tsuchi").string(), m, r);
  Model<2> fresh = build_model<2>(read_config_string(input, "column.toml"));
  const RunProgress back = read_checkpoint<2>((tmp.path / "c.tsuchi").string(), fresh);
  EXPECT_EQ(back.time, r.time);
  EXPECT_EQ(back.steps, r.steps);
  EXPECT_EQ(back.frame_index, r.frame_index);
  EXPECT_EQ(back.output.frames, r.output.frames);
  EXPECT_EQ(back.output.global_bytes, r.output.global_bytes);
  EXPECT_EQ(back.output.global_crc, r.output.global_crc);
  std::size_t arrays = 0;
  m.particles.for_each_array([&](const char* name, const auto& a) {
    fresh.particles.for_each_array([&](const char* other, const auto& b) {
      if constexpr (std::is_same_v<decltype(a), decltype(b)>)
        if (std::string(name) == other) {
          ++arrays;
          EXPECT_TRUE(a == b) << name;
        }
    });
  });
  // 13 kinematic and stress arrays (with C and sigma0), and one column per state field of
  // Mohr-Coulomb, the model's only constitutive model.
  EXPECT_EQ(arrays, 13u + MohrCoulomb::state_fields.size());
  EXPECT_EQ(fresh.particles.state_columns_held(), MohrCoulomb::state_fields.size());
}

// Faults stop the step with their own kind and name the particle, its body and position.
TEST(Faults, NonFiniteStressIsNamed) {
  Model<2> m = build_model<2>(read_config_string(elastic_input, "column.toml"));
  const std::size_t i = m.particles.size() / 2;
  m.particles.sigma_p[i][0] = std::numeric_limits<double>::quiet_NaN();
  ExplicitSolver<2> solver(m);
  try {
    solver.step(1e-4);
    ADD_FAILURE() << "a NaN stress went unnoticed";
  } catch (const RunError& e) {
    EXPECT_EQ(e.fault, Fault::NonFinite);
    // The NaN reaches the neighbours through the grid in the same step; the lowest index is named.
    EXPECT_TRUE(std::regex_search(e.what(), std::regex("^step 1 \\(t = 0 s\\): particle [0-9]+ of body \"column\" at \\([-0-9.e]+, [-0-9.e]+\\)")))
        << e.what();
    expect_message(e.what(), {"non-finite", "time.courant"});
    EXPECT_EQ(exit_code::of(e.fault), exit_code::non_finite);
  }
}

TEST(Faults, VolumeCollapseIsNamed) {
  Model<2> m = build_model<2>(read_config_string(elastic_input, "column.toml"));
  // Every particle heading for the column's axis at 100 m/s: one step of 1 ms crushes the cells.
  for (std::size_t i = 0; i < m.particles.size(); ++i) m.particles.v_p[i] = Vec<2>(m.particles.x_p[i][0] < 0.2 ? 100.0 : -100.0, 0.0);
  ExplicitSolver<2> solver(m);
  try {
    solver.step(1e-3);
    ADD_FAILURE() << "a collapsed particle went unnoticed";
  } catch (const RunError& e) {
    EXPECT_EQ(e.fault, Fault::VolumeCollapse) << e.what();
    expect_message(e.what(), {"zero or negative volume", "of body \"column\""});
  }
}

TEST(Faults, UnstableFixedStepSavesTheLastGoodState) {
  TempDir tmp("tsuchi_faults");
  // A soft column in free fall with a fixed dt just below the initial stable limit: the growing
  // speed lowers the limit below dt after a few steps.
  std::string text = replace(elastic_input, "courant = 0.4", "dt = 0.012");
  text = replace(text, "youngs_modulus = 2.0e6", "youngs_modulus = 1.0e4");
  text = replace(text, "y_min = \"fixed\"", "y_min = \"free\"");
  text = replace(text, "min = [0.1, 0.0]", "min = [0.1, 0.3]");
  text = replace(text, "max = [0.3, 0.6]", "max = [0.3, 0.9]");
  text = replace(text, "gravity = [0.0, -9.81]", "gravity = [0.0, -30.0]");
  write_file(tmp.path / "fall.toml", text);
  const fs::path out = tmp.path / "out";
  const ProgramResult r = run_program("run -q " + quoted(tmp.path / "fall.toml") + " -o " + quoted(out) +
                                      " --set checkpoint.every_steps=1000");
  EXPECT_EQ(r.status, exit_code::unstable_step) << r.output;
  expect_message(r.output, {"above the stable limit", "time.courant", "latest checkpoint is step",
                            (out / "checkpoint.tsuchi").string()});
  // Where and when (issue 13): the step, the time, the particle that sets the limit and its body;
  // advice that works from the command line although the file sets time.dt; and the command that
  // continues, with the run's own -o and --set.
  EXPECT_TRUE(std::regex_search(r.output, std::regex("step [0-9]+ \\(t = [-0-9.e]+ s\\): particle [0-9]+ of body "
                                                     "\"column\" at \\([-0-9.e]+, [-0-9.e]+\\): time.dt = 0.012 s")))
      << r.output;
  expect_message(r.output, {"set a smaller time.dt (--set time.dt=", "or replace time.dt by time.courant in",
                            "continue with tsuchi run " + (tmp.path / "fall.toml").string() + " -o " + out.string() +
                                " --set checkpoint.every_steps=1000 --set time.dt=0.006 --restart " +
                                (out / "checkpoint.tsuchi").string()});
  EXPECT_TRUE(fs::exists(out / "checkpoint.tsuchi"));
  // The saved state restarts with a smaller step.
  const ProgramResult again = run_program("run -q " + quoted(tmp.path / "fall.toml") + " -o " + quoted(out) +
                                          " --set time.dt=0.002 --set time.max_steps=50 --restart " +
                                          quoted(out / "checkpoint.tsuchi"));
  EXPECT_EQ(again.status, exit_code::ok) << again.output;
}

}  // namespace
