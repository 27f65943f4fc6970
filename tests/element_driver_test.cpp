// The material-point driver (`tsuchi element`): lab-test paths of one stress point against closed
// forms, the stress-controlled components actually held, and the program's CSV and error handling.
#include "tsuchi/core/errors.hpp"
#include "tsuchi/element/element_csv.hpp"
#include "tsuchi/element/element_driver.hpp"
#include "tsuchi/io/element_reader.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace tsuchi::test;

namespace fs = std::filesystem;
using namespace tsuchi;
using element::ElementRow;

constexpr double kPa = 1e3;

// The paper's soil: c = 8.5 kPa, phi = 30.5 deg, G = 1311 kPa, nu = 0.2, psi = 0, sigma_t = 0.
const std::string kSoil = R"([[materials]]
name = "soil"
model = "mohr_coulomb"
density = 1530.0
shear_modulus = 1.311e6
poisson_ratio = 0.2
cohesion = 8.5e3
friction_angle = 30.5
dilatancy_angle = 0.0
tension_strength = 0.0
)";

const std::string kElastic = R"([[materials]]
name = "rubber"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
)";

io::ElementInput read(const std::string& text) { return io::read_element_string(text, "element.toml"); }

std::vector<ElementRow> drive(const io::ElementInput& in) {
  return element::drive_element(in.material, in.path, in.iteration);
}

double peak_deviator(const std::vector<ElementRow>& rows) {
  double d = 0.0;
  for (const auto& r : rows) d = std::max(d, r.deviator());
  return d;
}

std::string compression_test(const std::string& type, double p) {
  return kSoil + fmt::format(R"(
[test]
type = "{}"
confining_pressure = {}
axial_strain = 0.15
increments = 1500
)",
                             type, p);
}

// ---- Mohr-Coulomb peaks ---------------------------------------------------------------------

TEST(ElementDriver, TriaxialCompressionPeakIsMohrCoulomb) {
  for (double p : {10 * kPa, 50 * kPa, 100 * kPa}) {
    const auto rows = drive(read(compression_test("triaxial_compression", p)));
    ASSERT_EQ(rows.size(), 1501u);
    const double peak = peak_deviator(rows), expected = mohr_coulomb_peak(p);
    std::printf("triaxial p = %5.0f kPa: peak deviator %.6f kPa, closed form %.6f kPa, rel. error %.2e\n", p / kPa,
                peak / kPa, expected / kPa, std::abs(peak / expected - 1.0));
    EXPECT_NEAR(peak / expected, 1.0, 0.005) << "p = " << p;
    // A perfectly plastic return lands on the surface itself: far tighter than required.
    EXPECT_NEAR(peak / expected, 1.0, 1e-8) << "p = " << p;
    for (const auto& r : rows) {
      ASSERT_LT(std::abs(r.stress[0] + p), 1e-9 * p) << "sig_xx not held, increment " << r.increment;
      ASSERT_LT(std::abs(r.stress[2] + p), 1e-9 * p) << "sig_zz not held, increment " << r.increment;
      // Axisymmetric: q = sigma1 - sigma3.
      ASSERT_NEAR(r.q(), r.deviator(), 1e-9 * p) << "increment " << r.increment;
    }
    EXPECT_EQ(rows.back().mode, YieldMode::Shear);
    EXPECT_NEAR(rows.back().strain[1], -0.15, 1e-14);
  }
}

// A triaxial cell is symmetric about its axis, so eps_xx = eps_zz. At Mohr-Coulomb's triaxial
// compression edge (the two lateral principal stresses equal) the plastic flow lambda_a g_a +
// lambda_b g_b may split between x and z in any proportion without changing the stress; the driver
// ties eps_zz to eps_xx (element_driver.cpp), which picks the symmetric split lambda_a = lambda_b.
// Past the peak the stress is constant, the strain increments are plastic, and each lateral one is
//   d eps_lateral / d eps_axial = -N_psi / 2,     N_psi = (1 + sin psi) / (1 - sin psi).
// Before the tie, psi = 5 deg gave eps_xx 0.0227 against eps_zz 0.0299 at 5 % axial strain.
TEST(ElementDriver, TriaxialCompressionFlowsAlikeInBothLateralDirections) {
  for (const double psi : {0.0, 5.0, 30.0}) {
    const auto rows = drive(read(fmt::format(R"([[materials]]
name = "sand"
model = "mohr_coulomb"
density = 1800.0
youngs_modulus = 20.0e6
poisson_ratio = 0.3
cohesion = 10.0e3
friction_angle = 30.0
dilatancy_angle = {}

[test]
type = "triaxial_compression"
confining_pressure = 100e3
axial_strain = 0.05
increments = 500
)",
                                             psi)));
    ASSERT_EQ(rows.size(), 501u);
    for (const auto& r : rows) ASSERT_EQ(r.strain[0], r.strain[2]) << "psi " << psi << ", increment " << r.increment;
    const double s = std::sin(psi * std::numbers::pi / 180.0), N_psi = (1.0 + s) / (1.0 - s);
    const ElementRow &a = rows[300], &b = rows[500];  // both well past the peak (about increment 118)
    ASSERT_EQ(a.mode, YieldMode::Shear);
    const double ratio = (b.strain[0] - a.strain[0]) / (b.strain[1] - a.strain[1]);
    std::printf("psi %4.1f deg: eps_xx = eps_zz = %.6f at 5 %%, d eps_lat / d eps_ax %.9f, -N_psi/2 %.9f\n", psi,
                b.strain[0], ratio, -0.5 * N_psi);
    EXPECT_NEAR(ratio, -0.5 * N_psi, 1e-9 * N_psi) << "psi " << psi;
  }
}

TEST(ElementDriver, PlaneStrainCompressionPeakIsMohrCoulomb) {
  for (double p : {10 * kPa, 50 * kPa, 100 * kPa}) {
    const auto rows = drive(read(compression_test("plane_strain_compression", p)));
    const double peak = peak_deviator(rows), expected = mohr_coulomb_peak(p);
    std::printf("plane strain p = %5.0f kPa: peak deviator %.6f kPa, closed form %.6f kPa, rel. error %.2e\n",
                p / kPa, peak / kPa, expected / kPa, std::abs(peak / expected - 1.0));
    EXPECT_NEAR(peak / expected, 1.0, 0.005) << "p = " << p;
    EXPECT_NEAR(peak / expected, 1.0, 1e-8) << "p = " << p;
    for (const auto& r : rows) {
      ASSERT_LT(std::abs(r.stress[0] + p), 1e-9 * p) << "sig_xx not held, increment " << r.increment;
      ASSERT_EQ(r.strain[2], 0.0) << "eps_zz, increment " << r.increment;
    }
    // sigma_zz is the intermediate principal stress: the deviator is sig_xx - sig_yy.
    EXPECT_NEAR(rows.back().deviator(), rows.back().stress[0] - rows.back().stress[1], 1e-9 * p);
  }
}

// Triaxial extension: the axial stress falls below the held cell pressure until Mohr-Coulomb's
// extension strength, sigma_c = sigma_a N_phi + 2 c sqrt(N_phi) with sigma_c the cell pressure
// (the major principal stress), i.e. q = sigma_c (1 - 1/N_phi) + 2 c / sqrt(N_phi), or its tension
// cut-off, whichever comes first.
TEST(ElementDriver, TriaxialExtensionPeakIsMohrCoulomb) {
  const double phi = 30.5 * std::numbers::pi / 180.0, c = 8.5 * kPa;
  const double N = (1.0 + std::sin(phi)) / (1.0 - std::sin(phi));
  for (double p : {10 * kPa, 100 * kPa}) {
    const auto rows = drive(read(compression_test("triaxial_extension", p)));
    // At 10 kPa the tension cut-off (sigma_t = 0) comes first: the axial stress reaches zero, q = p.
    const double peak = peak_deviator(rows), expected = std::min(p * (1.0 - 1.0 / N) + 2.0 * c / std::sqrt(N), p);
    std::printf("extension p = %5.0f kPa: peak deviator %.6f kPa, closed form %.6f kPa\n", p / kPa, peak / kPa,
                expected / kPa);
    EXPECT_NEAR(peak / expected, 1.0, 1e-8) << "p = " << p;
    for (const auto& r : rows) {
      ASSERT_LT(std::abs(r.stress[0] + p), 1e-9 * p) << "sig_xx not held, increment " << r.increment;
      ASSERT_LE(r.stress[1], 1e-9 * p) << "the axial stress stays compressive, increment " << r.increment;
    }
    EXPECT_NEAR(rows.back().strain[1], 0.15, 1e-14);  // lengthened
    EXPECT_GT(rows.back().stress[1], -p);              // unloaded axially
  }
}

// Undrained (volume held) compression of an elastic point: p stays at its start and q = 3 G eps_a
// in the triaxial test; in plane strain, the mean of the in-plane stresses stays put and
// sig_yy - sig_xx = 4 G eps_a.
TEST(ElementDriver, UndrainedElasticPathsKeepTheVolumeAndTheMeanStress) {
  const double E = 1.0e7, nu = 0.3, G = E / (2.0 * (1.0 + nu)), p0 = 50 * kPa, ea = 0.002;
  for (const char* type : {"triaxial_compression", "triaxial_extension", "plane_strain_compression"}) {
    const auto rows = drive(read(kElastic + fmt::format(R"(
[test]
type = "{}"
drainage = "undrained"
confining_pressure = {}
axial_strain = {}
increments = 10
)",
                                                       type, p0, ea)));
    const ElementRow& end = rows.back();
    EXPECT_NEAR(end.eps_v(), 0.0, 1e-15) << type;
    EXPECT_NEAR(end.p() / p0, 1.0, 1e-12) << type;
    const bool plane = std::string(type) == "plane_strain_compression";
    const double expected = plane ? 4.0 * G * ea : 3.0 * G * ea;
    EXPECT_NEAR(std::abs(end.stress[1] - end.stress[0]) / expected, 1.0, 1e-12) << type;
  }
}

// The model's own state fields reach the row (none for Mohr-Coulomb beyond the fixed columns).
TEST(ElementDriver, RowsCarryEveryStateFieldOfTheModel) {
  const auto rows = drive(read(compression_test("triaxial_compression", 50 * kPa)));
  const ElementRow& end = rows.back();
  ASSERT_EQ(end.state.size(), MohrCoulomb::state_fields.size());
  EXPECT_EQ(end.state_value(field_name::plastic_shear_strain), end.plastic_shear_strain);
  EXPECT_EQ(end.state_value(field_name::cohesion_factor), 1.0);
  EXPECT_TRUE(std::isnan(end.state_value("no_such_field")));
  EXPECT_EQ(element::csv_columns(read(kSoil + "[test]\ntype = \"simple_shear\"\nshear_strain = 0.1\n").material),
            element::csv_columns());
}

// The general segment form of a triaxial test is the preset, row for row.
TEST(ElementDriver, GeneralFormReproducesThePreset) {
  const auto preset = drive(read(compression_test("triaxial_compression", 50 * kPa)));
  const auto general = drive(read(kSoil + R"(
[test]
type = "general"
initial_stress = { isotropic = -50e3 }

[[test.segments]]
increments = 1500
strain = { yy = -0.15, xy = 0.0, yz = 0.0, xz = 0.0 }
stress = { xx = "hold", zz = "hold" }
)"));
  ASSERT_EQ(preset.size(), general.size());
  for (std::size_t i = 0; i < preset.size(); ++i) {
    ASSERT_EQ(preset[i].stress, general[i].stress) << "row " << i;
    ASSERT_EQ(preset[i].strain, general[i].strain) << "row " << i;
  }
}

// ---- linear elastic closed forms ------------------------------------------------------------

TEST(ElementDriver, LinearElasticIsotropicCompressionGivesBulkModulus) {
  const double E = 1e7, nu = 0.3, K = E / (3.0 * (1.0 - 2.0 * nu));
  // Stress-controlled (all three normal stresses iterated) and strain-controlled.
  for (const char* control : {"final_pressure = 200e3", "volumetric_strain = 0.02"}) {
    const auto rows = drive(read(kElastic + fmt::format(R"(
[test]
type = "isotropic_compression"
initial_pressure = 0.0
{}
increments = 50
)",
                                                         control)));
    ASSERT_EQ(rows.size(), 51u);
    for (std::size_t i = 1; i < rows.size(); ++i) {
      const auto& r = rows[i];
      ASSERT_NEAR(r.p() / r.eps_v(), K, 1e-9 * K) << control << ", increment " << r.increment;
      ASSERT_NEAR(r.q(), 0.0, 1e-9 * r.p()) << control << ", increment " << r.increment;
    }
  }
}

TEST(ElementDriver, LinearElasticSimpleShearGivesShearModulus) {
  const double E = 1e7, nu = 0.3, G = E / (2.0 * (1.0 + nu));
  const auto rows = drive(read(kElastic + R"(
[test]
type = "simple_shear"
vertical_stress = 100e3
k0 = 0.5
shear_strain = 0.01
increments = 100
)"));
  for (const auto& r : rows) {
    ASSERT_NEAR(r.stress[3], 2.0 * G * r.strain[3], 1e-9 * std::max(r.stress[3], 1.0)) << "increment " << r.increment;
    ASSERT_LT(std::abs(r.stress[1] + 100 * kPa), 1e-9 * 100 * kPa) << "sig_yy not held, increment " << r.increment;
    ASSERT_EQ(r.stress[0], -50 * kPa) << "sig_xx moved under eps_xx = 0";
  }
  EXPECT_NEAR(rows.back().strain[3], 0.005, 1e-15);  // gamma = 2 eps_xy
}

// ---- stress control beyond the strength -----------------------------------------------------

TEST(ElementDriver, StressTargetBeyondPeakStopsWithTheIncrement) {
  // From 100 kPa the axial stress can reach -335.9 kPa; ask for -400 kPa under stress control.
  const auto in = read(kSoil + R"(
[test]
type = "general"
initial_stress = { isotropic = -100e3 }

[[test.segments]]
increments = 100
stress = { xx = "hold", yy = -400e3, zz = "hold" }
strain = { xy = 0.0, yz = 0.0, xz = 0.0 }
)");
  std::vector<ElementRow> rows;
  try {
    element::drive_element(in.material, in.path, in.iteration, [&](const ElementRow& r) { rows.push_back(r); });
    FAIL() << "a stress beyond the strength was reached";
  } catch (const RunError& e) {
    const std::string msg = e.what();
    // Increment k targets -100 - 3k kPa: k = 78 is the first beyond -335.87 kPa.
    EXPECT_NE(msg.find("increment 79 (segment 0, increment 79 of 100)"), std::string::npos) << msg;
    EXPECT_NE(msg.find("sig_yy loaded to -337000 Pa"), std::string::npos) << msg;
    EXPECT_NE(msg.find("sig_xx held at -100000 Pa"), std::string::npos) << msg;
    EXPECT_NE(msg.find("drive sig_yy by strain"), std::string::npos) << msg;
  }
  ASSERT_EQ(rows.size(), 79u);  // initial state and increments 1 to 78
  EXPECT_NEAR(rows.back().stress[1], -334 * kPa, 1e-6 * kPa);
  EXPECT_LT(peak_deviator(rows), mohr_coulomb_peak(100 * kPa));
}

// ---- input errors ---------------------------------------------------------------------------

std::string input_error(const std::string& text) {
  try {
    read(text);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted an invalid input";
  return {};
}

const std::string kGeneral = kSoil + R"(
[test]
type = "general"
initial_stress = { isotropic = -50e3 }

[[test.segments]]
increments = 100
strain = { yy = -0.1, xy = 0.0, yz = 0.0, xz = 0.0 }
stress = { xx = "hold", zz = "hold" }
)";

TEST(ElementInput, RefusesBadPaths) {
  ASSERT_NO_THROW(read(kGeneral));
  // A friction angle in radians by mistake is warned about, not refused (issue 13).
  const io::ElementInput slip = read(replace(kGeneral, "friction_angle = 30.5", "friction_angle = 0.53"));
  ASSERT_EQ(slip.warnings.size(), 1u);
  expect_message(slip.warnings[0], {"element.toml:", "key 'materials.0.friction_angle'", "0.53 degrees is below 1 degree"});
  // A title with a line break broke the CSV header (issue 13).
  expect_message(input_error("title = \"a\\nb\"\n" + kGeneral),
                 {"element.toml:1:9: key 'title'", "expected a title on one line"});
  // An empty array of segments was accepted as a path of no increment (issue 13).
  try {
    io::read_element_string(kGeneral, "element.toml", {"test.segments=[]"});
    ADD_FAILURE() << "segments = [] accepted";
  } catch (const InputError& e) {
    expect_message(e.what(), {"element.toml: (command-line override): key 'test.segments'",
                              "at least one [[test.segments]] table, got an empty array"});
  }
  expect_message(input_error(replace(kGeneral, "yy = -0.1,", "yy = -0.1, xx = 0.0,")),
                 {"element.toml:", "key 'test.segments.0.stress.xx'", "controlled twice", "test.segments.0.strain"});
  expect_message(input_error(replace(kGeneral, ", xz = 0.0 }", " }")),
                 {"element.toml:", "test.segments.0", "component xz is not controlled"});
  expect_message(input_error(replace(kGeneral, "zz = \"hold\"", "ZZ = \"hold\"")),
                 {"key 'test.segments.0.stress.ZZ'", "lower case: write 'zz'"});
  expect_message(input_error(replace(kGeneral, "increments = 100\n", "")),
                 {"element.toml:", "missing key 'test.segments.0.increments'", "whole number of increments"});
  expect_message(input_error(replace(kGeneral, "zz = \"hold\"", "zz = \"keep\"")),
                 {"key 'test.segments.0.stress.zz'", "or \"hold\"", "got \"keep\""});
  expect_message(input_error(replace(kGeneral, "friction_angle = 30.5", "friction_angle = 95")),
                 {"element.toml:8:", "key 'materials.0.friction_angle'", "[0, 90)", "got 95"});
  expect_message(input_error(replace(kGeneral, "type = \"general\"", "type = \"triaxial\"")),
                 {"key 'test.type'", "\"triaxial_compression\"", "got \"triaxial\""});
  expect_message(input_error(replace(kGeneral, "[[test.segments]]", "[[test.segment]]")),
                 {"missing key 'test.segments'"});
  expect_message(input_error(replace(kGeneral, "{ isotropic = -50e3 }", "{ tensor = [-50e3, -50e3, -50e3] }")),
                 {"key 'test.initial_stress.tensor'", "6 numbers", "3 entries"});
  // Outside the yield surface from the start: 50 kPa of shear with 50 kPa of confinement.
  expect_message(input_error(replace(kGeneral, "{ isotropic = -50e3 }", "{ tensor = [-50e3, -50e3, -50e3, 60e3, 0, 0] }")),
                 {"key 'test.initial_stress'", "inside the Mohr-Coulomb surface", "shear strength"});
}

TEST(ElementInput, RefusesBadPresets) {
  const std::string tx = compression_test("triaxial_compression", 50 * kPa);
  expect_message(input_error(replace(tx, "axial_strain = 0.15", "axial_strain = -0.15")),
                 {"key 'test.axial_strain'", "compression positive", "got -0.15"});
  expect_message(input_error(replace(tx, "increments = 1500", "increments = 1500\nincrement = 10")),
                 {"unknown key 'test.increment'", "did you mean 'increments'"});
  expect_message(input_error(replace(tx, "increments = 1500", "increments = 0")),
                 {"key 'test.increments'", "got 0"});
  expect_message(input_error(kSoil + replace(kElastic, "rubber", "soil") + "[test]\ntype = \"simple_shear\"\nshear_strain = 0.1\n"),
                 {"key 'materials.1.name'", "defined twice"});
  expect_message(input_error(kSoil + kElastic + "[test]\ntype = \"simple_shear\"\nshear_strain = 0.1\n"),
                 {"missing key 'test.material'", "\"soil\", \"rubber\""});
  EXPECT_NO_THROW(read(kSoil + kElastic + "[test]\ntype = \"simple_shear\"\nshear_strain = 0.1\nmaterial = \"rubber\"\n"));
  expect_message(input_error(kSoil + "[test]\ntype = \"simple_shear\"\nshear_strain = 0.1\nvertical_stress = 50e3\nk0 = 5\n"),
                 {"key 'test.k0'", "shear strength"});
  expect_message(input_error(kSoil + "[test]\ntype = \"isotropic_compression\"\nfinal_pressure = 1e5\nvolumetric_strain = 0.01\n"),
                 {"in 'test'", "exactly one of 'final_pressure'"});
}

// ---- the program ----------------------------------------------------------------------------

// The CSV split into its comment lines, header and data rows.
struct Csv {
  std::vector<std::string> comments;
  std::string header;
  std::vector<std::vector<double>> rows;
};

Csv read_csv(const fs::path& p) {
  Csv c;
  std::ifstream in(p);
  for (std::string line; std::getline(in, line);) {
    if (line.starts_with("#")) c.comments.push_back(line);
    else if (c.header.empty()) c.header = line;
    else {
      std::vector<double> v;
      std::stringstream ss(line);
      for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
      c.rows.push_back(v);
    }
  }
  return c;
}

std::string expected_header() {
  std::string h;
  for (const auto& c : element::csv_columns()) h += (h.empty() ? "" : ",") + c;
  return h;
}

TEST(ElementProgram, ExampleWritesTheCsv) {
  TempDir tmp("tsuchi_element");
  const fs::path csv = tmp.path / "sub" / "triaxial.csv";
  const fs::path example = fs::path(TSUCHI_SOURCE_DIR) / "examples" / "element_tests" / "triaxial_compression.toml";
  const ProgramResult r = run_program("element " + quoted(example) + " -o " + quoted(csv) + " --set test.confining_pressure=100e3");
  ASSERT_EQ(r.status, exit_code::ok) << r.output;
  expect_message(r.output, {"material", "\"soil\"", "triaxial compression", "peak", "235.87 kPa", "1501 rows"});
  const Csv c = read_csv(csv);
  EXPECT_EQ(c.header, expected_header());
  ASSERT_EQ(c.rows.size(), 1501u);
  for (const auto& row : c.rows) ASSERT_EQ(row.size(), element::csv_columns().size());
  EXPECT_EQ(c.rows.front()[0], 0.0);
  EXPECT_EQ(c.rows.back()[0], 1500.0);
  double peak = 0.0;  // column "deviator"
  for (const auto& row : c.rows) peak = std::max(peak, row[16]);
  EXPECT_NEAR(peak / mohr_coulomb_peak(100 * kPa), 1.0, 0.005);
  expect_message(c.comments.empty() ? "" : c.comments[0], {"triaxial_compression.toml"});
  for (const auto& e : fs::directory_iterator(csv.parent_path()))
    EXPECT_EQ(e.path().filename(), "triaxial.csv") << "left behind: " << e.path();
}

TEST(ElementProgram, BadInputExitsWithCodeTwoAndWritesNothing) {
  TempDir tmp("tsuchi_element");
  struct Case {
    std::string from, to;
    std::vector<std::string> message;
  };
  const std::vector<Case> cases{
      {"yy = -0.1,", "yy = -0.1, xx = 0.0,", {"test.segments.0.stress.xx", "controlled twice"}},
      {"increments = 100\n", "", {"missing key 'test.segments.0.increments'"}},
      {"friction_angle = 30.5", "friction_angle = 95", {"materials.0.friction_angle", "got 95"}},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const fs::path file = tmp.path / fmt::format("bad{}.toml", i), csv = tmp.path / fmt::format("bad{}.csv", i);
    write_file(file, replace(kGeneral, cases[i].from, cases[i].to));
    const ProgramResult r = run_program("element " + quoted(file) + " -o " + quoted(csv));
    EXPECT_EQ(r.status, exit_code::input) << r.output;
    auto parts = cases[i].message;
    parts.push_back(file.string() + ":");
    parts.push_back("error in input:");
    expect_message(r.output, parts);
    EXPECT_FALSE(fs::exists(csv)) << "a refused input wrote " << csv;
  }
}

TEST(ElementProgram, RunErrorKeepsTheRowsComputed) {
  TempDir tmp("tsuchi_element");
  const fs::path file = tmp.path / "beyond.toml", csv = tmp.path / "beyond.csv";
  write_file(file, kSoil + R"(
[test]
type = "general"
initial_stress = { isotropic = -50e3 }

[[test.segments]]
increments = 100
stress = { xx = "hold", yy = -400e3, zz = "hold" }
strain = { xy = 0.0, yz = 0.0, xz = 0.0 }
)");
  const ProgramResult r = run_program("element " + quoted(file) + " -o " + quoted(csv));
  EXPECT_EQ(r.status, exit_code::run) << r.output;
  expect_message(r.output, {"run stopped:", "increment 38 (segment 0, increment 38 of 100)", "drive sig_yy by strain", csv.string()});
  ASSERT_TRUE(fs::exists(csv));
  const Csv c = read_csv(csv);
  EXPECT_EQ(c.header, expected_header());
  ASSERT_GT(c.rows.size(), 1u);
  EXPECT_EQ(c.rows.back()[0], static_cast<double>(c.rows.size() - 1));
  bool noted = false;
  for (const auto& line : c.comments) noted = noted || line.find("STOPPED") != std::string::npos;
  EXPECT_TRUE(noted) << "the CSV does not say that the path stopped";
}

TEST(ElementProgram, DefaultOutputIsTheInputNameInTheWorkingDirectory) {
  TempDir tmp("tsuchi_element");
  const fs::path file = tmp.path / "my_test.toml";
  write_file(file, kGeneral);
  const ProgramResult same = run_program("element -q " + quoted(file) + " -o " + quoted(file));
  EXPECT_EQ(same.status, exit_code::input) << same.output;
  expect_message(same.output, {"is the input file"});
  const ProgramResult r = run_program("element -q " + quoted(file));
  // Not next to the input: in the working directory of the program, which is the test's.
  const fs::path written = fs::current_path() / "my_test.csv";
  EXPECT_EQ(r.status, exit_code::ok) << r.output;
  EXPECT_TRUE(fs::exists(written));
  EXPECT_FALSE(fs::exists(tmp.path / "my_test.csv"));
  std::error_code ec;
  fs::remove(written, ec);
}

}  // namespace
