#pragma once
// Helpers shared by the test suites: editing input text, checking error messages, running the
// `tsuchi` program in a scratch directory, a run without output, and the Mohr-Coulomb peak the
// geomaterial tests compare against.
#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/run/simulation.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace tsuchi::test {

namespace fs = std::filesystem;

// `text` with the first occurrence of `from` replaced by `to` (which must exist).
inline std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  if (pos == std::string::npos) {
    ADD_FAILURE() << "'" << from << "' not in the input";
    return text;
  }
  return text.replace(pos, from.size(), to);
}

// The message contains every one of `parts`.
inline void expect_message(const std::string& msg, const std::vector<std::string>& parts) {
  for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' missing from: " << msg;
}

// The message of the InputError that reading `text` (as file `file`, with `sets` as --set)
// throws, or "accepted".
inline std::string input_error_of(const std::string& text, const std::string& file,
                                  const std::vector<std::string>& sets = {}) {
  try {
    read_config_string(text, file, sets);
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

// A run that writes nothing.
inline RunOptions no_output() {
  RunOptions o;
  o.write_output = false;
  return o;
}

// Plane-strain (and triaxial) Mohr-Coulomb deviator at failure with sigma3 = -p:
// p (N_phi - 1) + 2 c sqrt(N_phi). Defaults: the paper's soil, c = 8.5 kPa, phi = 30.5 deg; in Pa.
inline double mohr_coulomb_peak(double p, double c = 8.5e3, double phi_deg = 30.5) {
  const double s = std::sin(phi_deg * std::numbers::pi / 180.0);
  const double N = (1.0 + s) / (1.0 - s);
  return p * (N - 1.0) + 2.0 * c * std::sqrt(N);
}

// A fresh directory under the system's temporary one, removed with everything in it.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& prefix) {
    std::random_device rd;
    path = fs::temp_directory_path() / (prefix + "_" + std::to_string(::getpid()) + "_" + std::to_string(rd()));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

inline void write_file(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
  ASSERT_TRUE(out.good()) << "cannot write " << p;
}

struct ProgramResult {
  int status = -1;
  std::string output;  // stdout and stderr together
};

// Runs the `tsuchi` program built with the tests, with `args` as given to the shell.
inline ProgramResult run_program(const std::string& args) {
  ProgramResult r;
  const std::string cmd = std::string("'") + TSUCHI_BINARY + "' " + args + " 2>&1";
  std::FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) {
    ADD_FAILURE() << "popen failed: " << cmd;
    return r;
  }
  char buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) r.output.append(buf, n);
  const int st = ::pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

// p in single quotes for the shell (the temporary paths hold no quote). Appended piece by piece:
// GCC 12 warns wrongly (-Wrestrict) about "'" + s + "'".
inline std::string quoted(const fs::path& p) {
  std::string r(1, '\'');
  r += p.string();
  r += '\'';
  return r;
}

// A normally consolidated Modified Cam-Clay block (lambda 0.2, kappa 0.04, M 1.2, e0 1, nu 0.3), 2 x 2
// cells of 5 cm, squeezed at constant volume (vx = +0.1 x, vy = -0.1 y) from an isotropic 200 kPa
// held by eq (2): the [model], [grid], [[materials]] and [[bodies]] of a run; [time] and
// [output] are the test's.
inline const std::string kCamClayUndrainedBlock = R"([model]
dimension = 2

[grid]
origin = [0.0, 0.0]
extent = [0.2, 0.2]
cell_size = 0.05

[[materials]]
name = "clay"
model = "modified_cam_clay"
density = 1800.0
lambda = 0.2
kappa = 0.04
critical_state_slope = 1.2
initial_void_ratio = 1.0
ocr = 1.0
poisson_ratio = 0.3

[[bodies]]
name = "specimen"
material = "clay"
min = [0.05, 0.05]
max = [0.15, 0.15]
particles_per_cell = 2
prescribed_velocity = { x = 0.0, y = 0.0 }
prescribed_velocity_gradient = { x = [0.1, 0.0], y = [0.0, -0.1] }

[bodies.initial_stress]
isotropic = -200.0e3
subtract = true
)";

}  // namespace tsuchi::test
