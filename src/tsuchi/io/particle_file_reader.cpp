#include "tsuchi/io/particle_file_reader.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/csv_table.hpp"
#include "tsuchi/io/toml_section.hpp"
#include "tsuchi/model/particle_fields.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace tsuchi::io {

namespace {

// "INPUT:LINE:COL: key 'bodies.1.particles': FILE:LINE: msg", as io/csv_table.hpp words its errors.
[[noreturn]] void fail(const ParticleFileRequest& r, const std::string& at, const std::string& msg) {
  throw InputError(fmt::format("{}: key '{}': {}: {}", r.key_where, r.key, at, msg));
}

std::string read_whole(const ParticleFileRequest& r) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(r.path, ec))
    throw InputError(fmt::format("{}: key '{}': expected a particle file (.csv or a tsuchi .vtu frame), got \"{}\", "
                                 "which is not a readable regular file",
                                 r.key_where, r.key, printable(r.path)));
  std::ifstream in(r.path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  if (!in) throw InputError(fmt::format("{}: key '{}': cannot read \"{}\"", r.key_where, r.key, printable(r.path)));
  return s.str();
}

// The particle field component a column names, when a file may set it: velocity, stress and the
// material state (checked against the registry, model/particle_fields.hpp).
bool settable(const std::string& name, int dim) {
  const auto q = find_recorder_quantity(name, dim);
  if (!q) return false;
  const Quantity k = q->first->quantity;
  return k == Quantity::Velocity || k == Quantity::Stress || k == Quantity::State;
}

std::vector<std::string> settable_names(int dim) {
  std::vector<std::string> r;
  for (const auto& n : recorder_quantities(dim))
    if (settable(n, dim)) r.push_back(n);
  return r;
}

// A particle edge below this fraction of a cell is warned of: far more particles per cell than a
// model needs, or a file in another unit (km read as m).
constexpr double small_edge = 1.0 / 20.0;

// Inside the grid, centre and GIMP domain (l_p = V^(1/D) / 2 per axis), and of a size the kernel
// takes: a domain wider than a cell breaks GIMP's three-node support (shape/gimp.hpp), and a size
// read in the wrong unit (a file in mm read as m: size 5 in 0.05 m cells) made the energy grow
// 2.3-fold in four steps with no word (issue 41).
void check_particle(const ParticleFileRequest& r, ParticleTable& t, std::size_t row) {
  const int dim = r.dimension;
  const double h = r.grid.cell_size, V = t.volume[row], edge = std::pow(V, 1.0 / dim);
  for (int d = 0; d < dim; ++d) {
    const double lo = r.grid.origin[d], hi = lo + r.grid.extent[d], x = t.x[row][d];
    if (!(x > lo && x < hi))
      fail(r, t.where[row],
           fmt::format("particle at {} = {} lies {} the grid, which spans [{}, {}] along {} (a particle's centre must lie "
                       "strictly inside: the grid's faces are its edge)",
                       axis_name[d], x, x == lo || x == hi ? "on the edge of" : "outside", lo, hi, axis_name[d]));
  }
  if (!std::isnormal(edge) || edge < 1e-6 * h)  // also a volume that underflowed to 0
    fail(r, t.where[row],
         fmt::format("the particle's edge V^(1/{}) = {:.6g} m is less than a millionth of the cell ({} m): its volume "
                     "and mass are no quantity the grid can resolve; is the file in another unit (sizes and "
                     "coordinates are read in m)?",
                     dim, edge, h));
  if (edge > h * (1.0 + 1e-9))
    fail(r, t.where[row],
         fmt::format("the particle's edge V^(1/{}) = {:.6g} m is larger than a cell ({} m): a GIMP particle spans one "
                     "cell at most; is the file in mm (sizes and coordinates are read in m)?",
                     dim, edge, h));
  // A frame of a run holds particles pressed a little into a held face (their domains cross it, as
  // a wall allows); a quarter of the edge beyond the grid is refused, not such a hair.
  const double slack = 0.25 * edge;
  for (int d = 0; d < dim; ++d) {
    const double lo = r.grid.origin[d], hi = lo + r.grid.extent[d], x = t.x[row][d];
    if (x - 0.5 * edge < lo - slack || x + 0.5 * edge > hi + slack)
      fail(r, t.where[row],
           fmt::format("the particle's domain [{:.6g}, {:.6g}] along {} (its centre {} plus and minus half its edge "
                       "{:.6g} m) reaches outside the grid, which spans [{}, {}]",
                       x - 0.5 * edge, x + 0.5 * edge, axis_name[d], x, edge, lo, hi));
  }
  if (edge < small_edge * h) {
    if (t.small_particles++ == 0) t.first_small = t.where[row];
    t.smallest_edge = t.small_particles == 1 ? edge : std::min(t.smallest_edge, edge);
  }
}

// CSV (io/csv_table.hpp): a header row naming the columns, then one particle per row.
std::shared_ptr<const ParticleTable> read_csv(const ParticleFileRequest& r) {
  const CsvTable csv = read_csv_table(r.path, "", fmt::format("{}: key '{}'", r.key_where, r.key));
  auto t = std::make_shared<ParticleTable>();
  t->file = r.path;
  t->digest = csv.digest;
  const int dim = r.dimension;
  const std::string header = fmt::format("{}: header", csv.file);
  std::array<int, 3> xi{-1, -1, -1};
  std::vector<int> field_col;
  for (std::size_t k = 0; k < csv.names.size(); ++k) {
    const std::string& h = csv.names[k];
    if (h == "x" || h == "y" || (h == "z" && dim == 3)) xi[static_cast<std::size_t>(h[0] - 'x')] = static_cast<int>(k);
    else if (h == "volume" || h == "size") continue;
    else if (settable(h, dim)) {
      t->columns.push_back(h);
      field_col.push_back(static_cast<int>(k));
    } else {
      fail(r, header, fmt::format("unknown column \"{}\"; expected x, y{}, volume or size, and optionally particle "
                                  "fields: {}",
                                  printable(h), dim == 3 ? ", z" : "", quoted_list(settable_names(dim))));
    }
  }
  for (int d = 0; d < dim; ++d)
    if (xi[static_cast<std::size_t>(d)] < 0)
      fail(r, header, fmt::format("no column \"{}\": expected the columns x, y{} and volume (or size)", axis_name[d],
                                  dim == 3 ? ", z" : ""));
  const int volume = csv.column("volume"), size = csv.column("size");
  if (volume < 0 && size < 0)
    fail(r, header, "no column \"volume\" (m^3, m^2 per metre in 2D) or \"size\" (the particle's edge, m)");
  if (volume >= 0 && size >= 0) fail(r, header, "both \"volume\" and \"size\"; give one");
  t->values.assign(t->columns.size(), {});
  for (std::size_t row = 0; row < csv.rows.size(); ++row) {
    const std::vector<double>& v = csv.rows[row];
    Triple x{};
    for (int d = 0; d < dim; ++d) x[static_cast<std::size_t>(d)] = v[static_cast<std::size_t>(xi[static_cast<std::size_t>(d)])];
    const double given = v[static_cast<std::size_t>(volume >= 0 ? volume : size)];
    if (!(given > 0.0))
      fail(r, csv.at(row), fmt::format("column \"{}\": expected a positive value, got {}", volume >= 0 ? "volume" : "size",
                                       given));
    t->x.push_back(x);
    t->volume.push_back(volume >= 0 ? given : std::pow(given, dim));
    t->where.push_back(csv.at(row));
    for (std::size_t k = 0; k < field_col.size(); ++k) t->values[k].push_back(v[static_cast<std::size_t>(field_col[k])]);
    check_particle(r, *t, row);
  }
  return t;
}

// The value of attribute `name` in the XML tag `tag`, or "".
std::string attribute(std::string_view tag, std::string_view name) {
  const std::string key = fmt::format(" {}=\"", name);
  const std::size_t a = tag.find(key);
  if (a == std::string_view::npos) return {};
  const std::size_t b = tag.find('"', a + key.size());
  return std::string(tag.substr(a + key.size(), b - a - key.size()));
}

// A frame of our own writer (io/vtu_writer.cpp): an XML header whose DataArrays point by offset
// into one appended raw block, each array a UInt64 byte count followed by the little-endian data.
std::shared_ptr<const ParticleTable> read_vtu(const ParticleFileRequest& r, const std::string& text) {
  auto refuse = [&](const std::string& why) {
    fail(r, r.path, fmt::format("not a particle frame written by tsuchi ({}); expected a .vtu of its output directory", why));
  };
  const std::size_t appended = text.find("<AppendedData encoding=\"raw\">");
  if (text.find("type=\"UnstructuredGrid\"") == std::string::npos || appended == std::string::npos ||
      text.find("header_type=\"UInt64\"") == std::string::npos || text.find("byte_order=\"LittleEndian\"") == std::string::npos)
    refuse("an UnstructuredGrid with UInt64 headers and raw appended data");
  const std::size_t base = text.find('_', appended);
  if (base == std::string::npos) refuse("no '_' opening the appended data");
  const std::string_view head(text.data(), appended);
  const std::size_t npos = head.find("NumberOfPoints=\"");
  if (npos == std::string::npos) refuse("no NumberOfPoints");
  // Counts and offsets are checked against the file's size before any product is formed: a
  // NumberOfPoints chosen so that n x components x width wraps around 2^64 to the array's byte count
  // passed the size check and ended in bad_alloc (issue 41, defect 11).
  char* n_end = nullptr;
  const char* n_text = text.c_str() + npos + 16;
  const std::size_t n = std::isdigit(static_cast<unsigned char>(*n_text)) ? std::strtoull(n_text, &n_end, 10) : 0;
  if (!n_end || *n_end != '"' || n > text.size() / (3 * 8))
    refuse(fmt::format("NumberOfPoints=\"{}\" is not a count of points the file's {} bytes can hold",
                       printable(std::string_view(n_text, std::min<std::size_t>(40, std::strcspn(n_text, "\""))), 40),
                       text.size()));

  struct Array {
    std::string name, type;
    int components = 1;
    const char* data = nullptr;
  };
  std::vector<Array> arrays;
  const Array* points = nullptr;
  const std::size_t points_at = head.find("<Points>");
  for (std::size_t at = head.find("<DataArray"); at != std::string::npos; at = head.find("<DataArray", at + 1)) {
    const std::size_t end = head.find('>', at);
    const std::string_view tag = head.substr(at, end - at);
    if (attribute(tag, "format") != "appended") continue;  // the body names (FieldData, ascii)
    Array a;
    a.name = attribute(tag, "Name");
    a.type = attribute(tag, "type");
    a.components = std::atoi(attribute(tag, "NumberOfComponents").c_str());
    const std::size_t offset = std::strtoull(attribute(tag, "offset").c_str(), nullptr, 10);
    std::uint64_t bytes = 0;
    if (offset > text.size() || base + 1 + offset + sizeof bytes > text.size())
      refuse(fmt::format("array \"{}\" points past the end", a.name));
    const std::size_t bytes_at = base + 1 + offset;
    std::memcpy(&bytes, text.data() + bytes_at, sizeof bytes);
    const std::size_t width = a.type == "Float64" || a.type == "Int64" ? 8 : a.type == "Int32" ? 4 : 1;
    // n <= size / 24 and components <= 64 keep the product far below 2^64.
    if (a.components < 1 || a.components > 64 || bytes > text.size() - bytes_at - sizeof bytes ||
        bytes != n * static_cast<std::size_t>(a.components) * width)
      refuse(fmt::format("array \"{}\" has {} bytes, not {} points of {} components", a.name, bytes, n, a.components));
    a.data = text.data() + bytes_at + sizeof bytes;
    arrays.push_back(a);
    if (points_at != std::string::npos && at > points_at && a.name.empty()) points = &arrays.back();
    if (points_at != std::string::npos && at > points_at) break;  // the cells follow
  }
  if (!points || points->type != "Float64" || points->components != 3) refuse("no Float64 Points of 3 components");
  auto value = [](const Array& a, std::size_t i, int c) {
    double v = 0.0;
    const std::size_t k = i * static_cast<std::size_t>(a.components) + static_cast<std::size_t>(c);
    if (a.type == "Float64") std::memcpy(&v, a.data + 8 * k, 8);
    else if (a.type == "Int64") {
      std::int64_t w;
      std::memcpy(&w, a.data + 8 * k, 8);
      v = static_cast<double>(w);
    } else if (a.type == "Int32") {
      std::int32_t w;
      std::memcpy(&w, a.data + 4 * k, 4);
      v = w;
    } else {
      v = static_cast<unsigned char>(a.data[k]);
    }
    return v;
  };
  const Array* volume = nullptr;
  for (const auto& a : arrays)
    if (a.name == "volume") volume = &a;
  if (!volume)
    fail(r, r.path, "the frame has no \"volume\" field, which a particle needs; write frames with output.fields "
                    "holding \"volume\" (with \"stress\", \"velocity\" and the material state to carry them over)");
  auto t = std::make_shared<ParticleTable>();
  t->file = r.path;
  t->digest = 1469598103934665603ull;  // FNV-1a of the bytes, as io/csv_table.cpp
  for (const unsigned char ch : text) t->digest = (t->digest ^ ch) * 1099511628211ull;
  const int dim = r.dimension;
  // Columns: every frame field a file may set, by component (velocity only when asked for).
  std::vector<std::pair<const Array*, int>> source;
  for (const auto& a : arrays) {
    const ParticleField* f = a.name.empty() ? nullptr : find_particle_field(a.name);
    if (!f) continue;
    if (f->quantity == Quantity::Stress) {
      const char* voigt[6] = {"xx", "yy", "zz", "xy", "yz", "xz"};  // the frame's order, ours too
      for (int c = 0; c < (dim == 2 ? 4 : 6); ++c) {
        t->columns.push_back(fmt::format("stress_{}", voigt[c]));
        source.emplace_back(&a, c);
      }
    } else if (f->quantity == Quantity::Velocity && r.keep_velocity) {
      for (int c = 0; c < dim; ++c) {
        t->columns.push_back(fmt::format("velocity_{}", axis_name[c]));
        source.emplace_back(&a, c);
      }
    } else if (f->quantity == Quantity::State) {
      t->columns.push_back(a.name);
      source.emplace_back(&a, 0);
    }
  }
  t->values.assign(t->columns.size(), std::vector<double>(n));
  for (std::size_t i = 0; i < n; ++i) {
    Triple x{};
    for (int d = 0; d < dim; ++d) x[static_cast<std::size_t>(d)] = value(*points, i, d);
    t->x.push_back(x);
    t->volume.push_back(value(*volume, i, 0));
    t->where.push_back(fmt::format("{}: point {}", r.path, i));
    if (!(t->volume.back() > 0.0) || !std::isfinite(t->volume.back()))
      fail(r, t->where.back(), fmt::format("expected a positive volume, got {}", t->volume.back()));
    for (std::size_t k = 0; k < source.size(); ++k) t->values[k][i] = value(*source[k].first, i, source[k].second);
    check_particle(r, *t, i);
  }
  if (n == 0) fail(r, r.path, "the frame holds no particle");
  return t;
}

}  // namespace

std::shared_ptr<const ParticleTable> read_particle_file(const ParticleFileRequest& r) {
  const std::string ext = std::filesystem::path(r.path).extension().string();
  if (ext == ".vtu") return read_vtu(r, read_whole(r));
  if (ext == ".csv") return read_csv(r);
  throw InputError(fmt::format("{}: key '{}': expected a file ending in .csv or .vtu, got \"{}\"", r.key_where, r.key,
                               printable(r.path)));
}

}  // namespace tsuchi::io
