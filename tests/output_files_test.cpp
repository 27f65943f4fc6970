// The files a run writes: binary .vtu frames that parse and hold the model's values bit for bit,
// a .pvd listing exactly the frames written, a rectangular global.csv, no temporary files left.
#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/atomic_file.hpp"
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/io/vtu_writer.hpp"
#include "tsuchi/run/simulation.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cmath>
#include <cstring>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

namespace {

using namespace tsuchi;
namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("tsuchi_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Minimal reader of our appended-raw .vtu: name -> (components, bytes). Fails the test on any
// inconsistency (offsets out of range, sizes not matching NumberOfPoints).
struct Vtu {
  std::size_t points = 0;
  std::map<std::string, std::pair<int, std::string>> arrays;
};

Vtu parse_vtu(const std::string& doc) {
  Vtu v;
  std::smatch m;
  EXPECT_TRUE(std::regex_search(doc, m, std::regex("NumberOfPoints=\"(\\d+)\"")));
  v.points = std::stoul(m[1]);
  const auto mark = doc.find("<AppendedData encoding=\"raw\">");
  EXPECT_NE(mark, std::string::npos);
  const auto blob = doc.find('_', mark) + 1;
  const std::string head = doc.substr(0, mark);
  const std::regex array_re(
      "<DataArray type=\"(\\w+)\"(?: Name=\"(\\w+)\")? NumberOfComponents=\"(\\d+)\" format=\"appended\" offset=\"(\\d+)\"/>");
  for (auto it = std::sregex_iterator(head.begin(), head.end(), array_re); it != std::sregex_iterator(); ++it) {
    const auto& a = *it;
    const std::size_t off = blob + std::stoul(a[4]);
    std::uint64_t bytes = 0;
    EXPECT_LE(off + 8, doc.size());
    std::memcpy(&bytes, doc.data() + off, 8);
    EXPECT_LE(off + 8 + bytes, doc.size());
    const std::string name = a[2].matched ? std::string(a[2]) : std::string("points");
    v.arrays[name] = {std::stoi(a[3]), doc.substr(off + 8, bytes)};
  }
  EXPECT_NE(doc.find("</AppendedData>\n</VTKFile>"), std::string::npos);
  return v;
}

TEST(Output, RunWritesCompleteFramesSeriesAndCsv) {
  const fs::path dir = fresh_dir("run");
  const Config c = read_config_file(std::string(TSUCHI_SOURCE_DIR) + "/examples/bar_vibration/bar.toml",
                                    {"time.end=0.01", "output.interval=0.004"});
  Model<2> m = build_model<2>(c);
  RunOptions o;
  o.output_directory = dir.string();
  const RunSummary s = run_simulation<2>(m, c, o);
  // Frames at 0, 0.004, 0.008 and the end 0.01.
  ASSERT_EQ(s.frames, 4u);
  const std::string pvd = slurp(dir / "particles.pvd");
  const std::regex ds("timestep=\"([0-9.e+-]+)\" part=\"0\" file=\"([^\"]+)\"");
  std::vector<double> times;
  std::vector<std::string> files;
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), ds); it != std::sregex_iterator(); ++it) {
    times.push_back(std::stod((*it)[1]));
    files.push_back((*it)[2]);
  }
  ASSERT_EQ(times.size(), 4u);
  EXPECT_NEAR(times[1], 0.004, 1e-12);
  EXPECT_NEAR(times[3], 0.01, 1e-12);
  for (const auto& f : files) {
    const Vtu v = parse_vtu(slurp(dir / f));
    EXPECT_EQ(v.points, m.particles.size());
    EXPECT_EQ(v.arrays.at("points").second.size(), v.points * 3 * sizeof(double));
    EXPECT_EQ(v.arrays.at("stress").first, 6);
    EXPECT_EQ(v.arrays.at("id").second.size(), v.points * sizeof(std::int64_t));  // 64-bit ids (checkpoint format 3)
  }
  // The last frame holds the final state bit for bit.
  const std::string last_doc = slurp(dir / files.back());
  const Vtu last = parse_vtu(last_doc);
  // What a ParaView user needs first (issue 13): the particle size for Point Gaussian, p and q per
  // particle, and max_shear_strain as the active scalar.
  EXPECT_NE(last_doc.find("<PointData Scalars=\"max_shear_strain\">"), std::string::npos);
  EXPECT_NE(last_doc.find("<!-- written by tsuchi 0."), std::string::npos);
  EXPECT_NE(pvd.find("<!-- written by tsuchi 0."), std::string::npos);
  // Frames list the particles by id (FramesListParticlesInIdOrder): point k is particle by_id[k].
  std::vector<std::size_t> by_id(m.particles.size());
  for (std::size_t i = 0; i < by_id.size(); ++i) by_id[static_cast<std::size_t>(m.particles.id_p[i])] = i;
  for (std::size_t k = 0; k < m.particles.size(); ++k) {
    const std::size_t i = by_id[k];
    const auto value = [&](const char* name) {
      double v = 0;
      std::memcpy(&v, last.arrays.at(name).second.data() + k * sizeof(double), sizeof(double));
      return v;
    };
    const auto& sg = m.particles.sigma_p[i];
    const double p = (sg[0] + sg[1] + sg[2]) / 3.0;
    const double q = std::sqrt(0.5 * ((sg[0] - sg[1]) * (sg[0] - sg[1]) + (sg[1] - sg[2]) * (sg[1] - sg[2]) +
                                      (sg[2] - sg[0]) * (sg[2] - sg[0])) + 3.0 * sg[3] * sg[3]);
    ASSERT_NEAR(value("mean_stress"), p, 1e-12 * (std::abs(p) + q + 1.0)) << "particle " << i;
    ASSERT_NEAR(value("deviator_stress"), q, 1e-9 * (std::abs(p) + q + 1.0)) << "particle " << i;
    ASSERT_EQ(value("radius"), 0.5 * (m.particles.l_p[i][0] + m.particles.l_p[i][1])) << "particle " << i;
    ASSERT_GT(value("radius"), 0.0);
  }
  const std::string& vel = last.arrays.at("velocity").second;
  for (std::size_t k = 0; k < m.particles.size(); ++k) {
    const std::size_t i = by_id[k];
    double vx = 0;
    std::memcpy(&vx, vel.data() + 3 * k * sizeof(double), sizeof(double));
    ASSERT_EQ(vx, m.particles.v_p[i][0]) << "particle " << i;
  }
  // global.csv: a header and one row per step, all with the header's column count.
  std::istringstream csv(slurp(dir / "global.csv"));
  std::string line;
  std::getline(csv, line);
  const auto columns = std::count(line.begin(), line.end(), ',');
  std::size_t rows = 0;
  while (std::getline(csv, line)) {
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), columns);
    ++rows;
  }
  EXPECT_EQ(rows, static_cast<std::size_t>(s.steps) + 1);
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
  fs::remove_all(dir);
}

TEST(Output, AtomicWriteReplacesWholeFileOrNothing) {
  const fs::path dir = fresh_dir("atomic");
  fs::create_directories(dir);
  const std::string target = (dir / "a.txt").string();
  write_file_atomically(target, "first");
  write_file_atomically(target, "second, longer");
  EXPECT_EQ(slurp(target), "second, longer");
  // A target that cannot be replaced (a non-empty directory): error, and nothing else changes.
  fs::create_directories(dir / "blocker" / "inside");
  EXPECT_THROW(write_file_atomically((dir / "blocker").string(), "x"), OutputError);
  EXPECT_TRUE(fs::is_directory(dir / "blocker" / "inside"));
  // A missing parent directory: a clear error naming the path.
  try {
    write_file_atomically((dir / "missing" / "b.txt").string(), "x");
    FAIL() << "expected OutputError";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing/b.txt"), std::string::npos) << e.what();
  }
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 2u);  // a.txt and blocker: no temporary left behind
  fs::remove_all(dir);
}

}  // namespace

// Every frame lists the particles by increasing id, whatever their storage order (issue 41): the
// step re-stores them in block order (here every 5 steps, as a block slides across 8 cells), and
// frames in storage order had ParaView match different particles by point index from frame to
// frame (in the main job's last frame only 472 of 5,500 points sat at their first-frame index).
TEST(Output, FramesListParticlesInIdOrder) {
  const fs::path dir = fresh_dir("id_order");
  const Config c = read_config_string(R"toml(
[model]
dimension = 2

[grid]
cell_size = 0.05
extent = [1.0, 0.4]

[[materials]]
name = "soil"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e6
poisson_ratio = 0.3

[[bodies]]
name = "block"
material = "soil"
min = [0.1, 0.1]
max = [0.4, 0.3]
velocity = [4.0, 0.0]

[solver]
sort_interval = 5

[time]
end = 0.1

[output]
interval = 0.05
fields = ["id", "displacement"]
)toml",
                                      "slide.toml");
  Model<2> m = build_model<2>(c);
  RunOptions o;
  o.output_directory = dir.string();
  const RunSummary s = run_simulation<2>(m, c, o);
  ASSERT_EQ(s.frames, 3u);
  // The run did reorder its particles: storage order is not id order at the end.
  ASSERT_FALSE(std::is_sorted(m.particles.id_p.begin(), m.particles.id_p.end()));
  std::map<std::int64_t, std::size_t> slot;
  for (std::size_t i = 0; i < m.particles.size(); ++i) slot[m.particles.id_p[i]] = i;
  for (const char* f : {"particles_000000.vtu", "particles_000001.vtu", "particles_000002.vtu"}) {
    const Vtu v = parse_vtu(slurp(dir / f));
    ASSERT_EQ(v.points, m.particles.size());
    std::vector<std::int64_t> ids(v.points);
    std::memcpy(ids.data(), v.arrays.at("id").second.data(), ids.size() * sizeof(std::int64_t));
    for (std::size_t k = 0; k < ids.size(); ++k) ASSERT_EQ(ids[k], static_cast<std::int64_t>(k)) << f;
  }
  // The last frame's point k is particle k, position and displacement alike, bit for bit.
  const Vtu last = parse_vtu(slurp(dir / "particles_000002.vtu"));
  for (std::size_t k = 0; k < last.points; ++k) {
    double x = 0, u = 0;
    std::memcpy(&x, last.arrays.at("points").second.data() + 3 * k * sizeof(double), sizeof(double));
    std::memcpy(&u, last.arrays.at("displacement").second.data() + 3 * k * sizeof(double), sizeof(double));
    const std::size_t i = slot.at(static_cast<std::int64_t>(k));
    ASSERT_EQ(x, m.particles.x_p[i][0]) << k;
    ASSERT_EQ(u, m.particles.u_p[i][0]) << k;
  }
  fs::remove_all(dir);
}
