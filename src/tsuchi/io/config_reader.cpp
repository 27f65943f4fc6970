#include "tsuchi/io/config_reader.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/core/expression.hpp"
#include "tsuchi/io/particle_fields.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

namespace tsuchi {

const char* to_string(Scheme s) {
  switch (s) {
    case Scheme::USF: return "USF";
    case Scheme::USL: return "USL";
    case Scheme::MUSL: return "MUSL";
  }
  return "?";
}

const char* to_string(ShapeKind s) {
  switch (s) {
    case ShapeKind::Linear: return "linear";
    case ShapeKind::UGimp: return "ugimp";
    case ShapeKind::Gimp: return "gimp";
  }
  return "?";
}

namespace {

constexpr const char* axis_name[3] = {"x", "y", "z"};

std::string describe(const toml::node& n) {
  if (auto v = n.as_integer()) return fmt::format("{}", v->get());
  if (auto v = n.as_floating_point()) {
    // Keep the decimal point: "got 2" for a 2.0 where a whole number is wanted would mislead.
    std::string r = fmt::format("{}", v->get());
    if (r.find_first_of(".eEn") == std::string::npos) r += ".0";
    return r;
  }
  if (auto v = n.as_string()) return fmt::format("\"{}\"", v->get());
  if (auto v = n.as_boolean()) return v->get() ? "true" : "false";
  if (n.is_array()) return "an array";
  if (n.is_table()) return "a table";
  return "a value of another type";
}

std::string where(const std::string& file, const toml::source_region& r) {
  if (r.begin.line == 0) return fmt::format("{}: (command-line override)", file);
  return fmt::format("{}:{}:{}", file, r.begin.line, r.begin.column);
}

// One TOML table being read: hands out typed values, remembers which keys were asked for, and
// on finish() reports any key nobody asked for.
class Section {
 public:
  Section(const toml::table& t, std::string path, const std::string& file)
      : t_(t), path_(std::move(path)), file_(file) {}

  std::string key_path(std::string_view key) const {
    return path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key);
  }

  [[noreturn]] void fail(std::string_view key, const std::string& msg) const {
    const toml::node* n = t_.get(key);
    const auto& region = n ? n->source() : t_.source();
    throw InputError(fmt::format("{}: key '{}': {}", where(file_, region), key_path(key), msg));
  }

  [[noreturn]] void fail_here(const std::string& msg) const {
    throw InputError(fmt::format("{}: {}{}", where(file_, t_.source()),
                                 path_.empty() ? "" : fmt::format("in '{}': ", path_), msg));
  }

  bool has(std::string_view key) const { return t_.get(key) != nullptr; }

  const toml::node* get(std::string_view key) {
    used_.insert(std::string(key));
    return t_.get(key);
  }

  const toml::node& need(std::string_view key, const std::string& expected) {
    const toml::node* n = get(key);
    if (!n) {
      throw InputError(fmt::format("{}: missing key '{}': expected {}", where(file_, t_.source()),
                                   key_path(key), expected));
    }
    return *n;
  }

  double number_of(std::string_view key, const toml::node& n, const std::string& expected) const {
    if (auto i = n.as_integer()) return static_cast<double>(i->get());
    if (auto f = n.as_floating_point()) {
      if (!std::isfinite(f->get())) fail(key, fmt::format("expected {}, got {}", expected, describe(n)));
      return f->get();
    }
    fail(key, fmt::format("expected {}, got {}", expected, describe(n)));
  }

  // A number; `ok` is the range check and `expected` says it in words (with the unit).
  double number(std::string_view key, const std::string& expected,
                const std::function<bool(double)>& ok, std::optional<double> fallback = {}) {
    const toml::node* n = get(key);
    if (!n) {
      if (fallback) return *fallback;
      need(key, expected);
    }
    const double v = number_of(key, *n, expected);
    if (ok && !ok(v)) fail(key, fmt::format("expected {}, got {}", expected, describe(*n)));
    return v;
  }

  std::optional<double> optional_number(std::string_view key, const std::string& expected,
                                        const std::function<bool(double)>& ok) {
    if (!has(key)) {
      get(key);
      return std::nullopt;
    }
    return number(key, expected, ok);
  }

  std::int64_t integer(std::string_view key, const std::string& expected,
                       const std::function<bool(std::int64_t)>& ok, std::int64_t fallback) {
    const toml::node* n = get(key);
    if (!n) return fallback;
    auto i = n->as_integer();
    if (!i || (ok && !ok(i->get()))) fail(key, fmt::format("expected {}, got {}", expected, describe(*n)));
    return i->get();
  }

  std::string string(std::string_view key, const std::string& expected,
                     std::optional<std::string> fallback = {}) {
    const toml::node* n = get(key);
    if (!n) {
      if (fallback) return *fallback;
      need(key, expected);
    }
    auto s = n->as_string();
    if (!s) fail(key, fmt::format("expected {}, got {}", expected, describe(*n)));
    return s->get();
  }

  bool boolean(std::string_view key, bool fallback) {
    const toml::node* n = get(key);
    if (!n) return fallback;
    auto b = n->as_boolean();
    if (!b) fail(key, fmt::format("expected true or false, got {}", describe(*n)));
    return b->get();
  }

  // One of `choices` (compared case-insensitively); returns its index.
  int choice(std::string_view key, const std::vector<std::string>& choices, int fallback) {
    const toml::node* n = get(key);
    std::string list;
    for (const auto& c : choices) list += (list.empty() ? "\"" : ", \"") + c + "\"";
    if (!n) return fallback;
    auto s = n->as_string();
    if (s) {
      std::string v = s->get();
      std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
      for (std::size_t i = 0; i < choices.size(); ++i)
        if (v == choices[i]) return static_cast<int>(i);
    }
    fail(key, fmt::format("expected one of {}, got {}", list, describe(*n)));
  }

  // An array of exactly `dim` numbers, each passing `ok`.
  Triple vector(std::string_view key, int dim, const std::string& expected,
                const std::function<bool(double)>& ok, std::optional<Triple> fallback = {}) {
    const toml::node* n = get(key);
    if (!n) {
      if (fallback) return *fallback;
      need(key, expected);
    }
    return vector_of(key, *n, dim, expected, ok);
  }

  Triple vector_of(std::string_view key, const toml::node& n, int dim, const std::string& expected,
                   const std::function<bool(double)>& ok) const {
    auto a = n.as_array();
    if (!a || static_cast<int>(a->size()) != dim)
      fail(key, fmt::format("expected an array of {} numbers ({}), got {}", dim, expected,
                            a ? fmt::format("{} entries", a->size()) : describe(n)));
    Triple r{};
    for (int d = 0; d < dim; ++d) {
      const toml::node& e = *a->get(static_cast<std::size_t>(d));
      r[d] = number_of(key, e, expected);
      if (ok && !ok(r[d]))
        fail(key, fmt::format("expected {} in every entry, got {} in entry {}", expected,
                              describe(e), d + 1));
    }
    return r;
  }

  const toml::table* table(std::string_view key) {
    const toml::node* n = get(key);
    if (!n) return nullptr;
    if (!n->is_table()) fail(key, fmt::format("expected a table, got {}", describe(*n)));
    return n->as_table();
  }

  // [[key]] array of tables; an absent key gives an empty list.
  std::vector<const toml::table*> tables(std::string_view key) {
    std::vector<const toml::table*> r;
    const toml::node* n = get(key);
    if (!n) return r;
    auto a = n->as_array();
    if (!a) fail(key, fmt::format("expected an array of tables ([[{}]]), got {}", key, describe(*n)));
    for (const auto& e : *a) {
      if (!e.is_table()) fail(key, fmt::format("expected an array of tables ([[{}]]), got an entry that is {}", key, describe(e)));
      r.push_back(e.as_table());
    }
    return r;
  }

  void finish() const {
    for (auto&& [k, v] : t_) {
      if (!used_.count(std::string(k.str()))) {
        throw InputError(fmt::format("{}: unknown key '{}'{}", where(file_, k.source()),
                                     key_path(k.str()), hint(k.str())));
      }
    }
  }

  const std::string& path() const { return path_; }
  const std::string& file() const { return file_; }
  const toml::table& raw() const { return t_; }

 private:
  std::string hint(std::string_view k) const {
    // Suggest a known key that differs only slightly (a typo).
    std::string best;
    std::size_t best_d = 3;
    for (const auto& u : used_) {
      const std::size_t d = edit_distance(k, u);
      if (d < best_d) best_d = d, best = u;
    }
    return best.empty() ? std::string{} : fmt::format(" (did you mean '{}'?)", best);
  }

  static std::size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
      cur[0] = i;
      for (std::size_t j = 1; j <= b.size(); ++j)
        cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
      std::swap(prev, cur);
    }
    return prev[b.size()];
  }

  const toml::table& t_;
  std::string path_;
  const std::string& file_;
  std::set<std::string> used_;
};

const auto positive = [](double v) { return v > 0.0; };
const auto non_negative = [](double v) { return v >= 0.0; };
const auto any = [](double) { return true; };

int read_axis(const Section& s, std::string_view key, const toml::node& n, int dim) {
  if (auto str = n.as_string())
    for (int d = 0; d < dim; ++d)
      if (str->get().size() == 1 && std::tolower(static_cast<unsigned char>(str->get()[0])) == axis_name[d][0]) return d;
  s.fail(key, fmt::format("expected an axis name ({}), got {}", dim == 2 ? "\"x\" or \"y\"" : "\"x\", \"y\" or \"z\"",
                          describe(n)));
}

void read_model(Section& s, Config& c) {
  c.dimension = static_cast<int>(
      s.integer("dimension", "2 (plane strain) or 3", [](std::int64_t d) { return d == 2 || d == 3; }, 0));
  if (c.dimension == 0) s.need("dimension", "2 (plane strain) or 3");
  c.title = s.string("title", "a string", std::string{});
  c.gravity = s.vector("gravity", c.dimension, "m/s^2", any, Triple{});
  s.finish();
}

void read_grid(Section& s, Config& c) {
  auto& g = c.grid;
  const int dim = c.dimension;
  g.origin = s.vector("origin", dim, "m", any, Triple{});
  g.extent = s.vector("extent", dim, "positive lengths in m", positive);
  g.cell_size = s.number("cell_size", "a positive length in m", positive);
  for (int d = 0; d < dim; ++d) {
    const double n = g.extent[d] / g.cell_size;
    const double rounded = std::round(n);
    if (rounded < 1.0 || std::abs(n - rounded) > 1e-6 * std::max(1.0, n))
      s.fail("extent", fmt::format("expected a whole number of cells of {} m along {}, got {} m ({:.4g} cells)",
                                   g.cell_size, axis_name[d], g.extent[d], n));
    if (rounded > 1e7) s.fail("cell_size", fmt::format("{:.3g} cells along {} is more than this program handles", n, axis_name[d]));
    g.cells[d] = static_cast<int>(rounded);
  }
  s.finish();
}

void read_material(Section& s, Config& c) {
  Material m;
  m.name = s.string("name", "a material name");
  const int model = s.choice("model", {"linear_elastic"}, -1);
  if (model < 0) s.need("model", "a constitutive model name (\"linear_elastic\")");
  m.density = s.number("density", "a positive density in kg/m^3", positive);
  const double nu = s.number("poisson_ratio", "a Poisson's ratio in (-1, 0.5)",
                             [](double v) { return v > -1.0 && v < 0.5; });
  const bool has_E = s.has("youngs_modulus"), has_G = s.has("shear_modulus");
  if (has_E == has_G)
    s.fail_here("give exactly one of 'youngs_modulus' and 'shear_modulus' (Pa)");
  if (has_E)
    m.model = LinearElastic::from_young(s.number("youngs_modulus", "a positive modulus in Pa", positive), nu);
  else
    m.model = LinearElastic::from_shear(s.number("shear_modulus", "a positive modulus in Pa", positive), nu);
  for (const auto& other : c.materials)
    if (other.name == m.name) s.fail("name", fmt::format("material \"{}\" is defined twice", m.name));
  s.finish();
  c.materials.push_back(std::move(m));
}

void read_velocity_components(Section& s, std::string_view key, int dim, BodyConfig& b) {
  const toml::table* t = s.table(key);
  if (!t) return;
  Section v(*t, s.key_path(key), s.file());
  for (int d = 0; d < dim; ++d) {
    if (!v.has(axis_name[d])) continue;
    b.prescribed[d] = true;
    b.prescribed_velocity[d] = v.number(axis_name[d], "a velocity in m/s", any);
  }
  v.finish();
}

// Each component a number (m/s) or a formula of x, y, z in quotes, e.g. "0.1 * sin(pi * x / 2)".
void read_initial_velocity(Section& s, int dim, BodyConfig& b) {
  const toml::node* n = s.get("velocity");
  if (!n) return;
  const std::string expected = "numbers (m/s) or formulas of x, y, z in quotes";
  auto a = n->as_array();
  if (!a || static_cast<int>(a->size()) != dim)
    s.fail("velocity", fmt::format("expected an array of {} {}, got {}", dim, expected,
                                   a ? fmt::format("{} entries", a->size()) : describe(*n)));
  for (int d = 0; d < dim; ++d) {
    const toml::node& e = *a->get(static_cast<std::size_t>(d));
    if (auto f = e.as_string()) {
      try {
        Expression{f->get()};
      } catch (const std::invalid_argument& err) {
        s.fail("velocity", fmt::format("entry {} \"{}\" is not a valid formula: {}", d + 1, f->get(), err.what()));
      }
      b.velocity_formula[d] = f->get();
    } else {
      b.velocity[d] = s.number_of("velocity", e, expected);
    }
  }
}

void read_body(Section& s, Config& c, std::size_t index) {
  const int dim = c.dimension;
  BodyConfig b;
  b.name = s.string("name", "a body name", fmt::format("body{}", index));
  b.material = s.string("material", "the name of a material");
  for (const auto& other : c.bodies)
    if (other.name == b.name) s.fail("name", fmt::format("body \"{}\" is defined twice", b.name));
  auto it = std::find_if(c.materials.begin(), c.materials.end(),
                         [&](const Material& m) { return m.name == b.material; });
  if (it == c.materials.end()) {
    std::string names;
    for (const auto& m : c.materials) names += (names.empty() ? "\"" : ", \"") + m.name + "\"";
    s.fail("material", fmt::format("expected one of the materials defined ({}), got \"{}\"",
                                   names.empty() ? "none defined" : names, b.material));
  }
  b.material_index = static_cast<int>(it - c.materials.begin());
  s.choice("shape", {"box"}, 0);
  b.min = s.vector("min", dim, "m", any);
  b.max = s.vector("max", dim, "m", any);
  for (int d = 0; d < dim; ++d) {
    if (b.max[d] <= b.min[d])
      s.fail("max", fmt::format("expected max > min along {}, got {} <= {}", axis_name[d], b.max[d], b.min[d]));
    const double lo = c.grid.origin[d], hi = c.grid.origin[d] + c.grid.extent[d];
    const double tol = 1e-9 * c.grid.extent[d];
    if (b.min[d] < lo - tol || b.max[d] > hi + tol)
      s.fail(b.min[d] < lo - tol ? "min" : "max",
             fmt::format("body \"{}\" reaches outside the grid along {}: [{}, {}] is not inside [{}, {}]",
                         b.name, axis_name[d], b.min[d], b.max[d], lo, hi));
  }
  if (const toml::node* n = s.get("particles_per_cell")) {
    auto valid = [](std::int64_t v) { return v >= 1 && v <= 16; };
    const std::string expected = "a whole number from 1 to 16, or an array of one per axis";
    if (auto i = n->as_integer()) {
      if (!valid(i->get())) s.fail("particles_per_cell", fmt::format("expected {}, got {}", expected, describe(*n)));
      b.particles_per_cell.fill(static_cast<int>(i->get()));
    } else if (auto a = n->as_array(); a && static_cast<int>(a->size()) == dim) {
      for (int d = 0; d < dim; ++d) {
        auto e = a->get(static_cast<std::size_t>(d))->as_integer();
        if (!e || !valid(e->get())) s.fail("particles_per_cell", fmt::format("expected {}", expected));
        b.particles_per_cell[d] = static_cast<int>(e->get());
      }
    } else {
      s.fail("particles_per_cell", fmt::format("expected {}, got {}", expected, describe(*n)));
    }
  }
  read_initial_velocity(s, dim, b);
  read_velocity_components(s, "prescribed_velocity", dim, b);
  if (const toml::table* t = s.table("prescribed_velocity_gradient")) {
    Section g(*t, s.key_path("prescribed_velocity_gradient"), s.file());
    for (int d = 0; d < dim; ++d) {
      if (!g.has(axis_name[d])) continue;
      if (!b.prescribed[d])
        g.fail(axis_name[d], fmt::format("component {} has a gradient but no prescribed_velocity.{}",
                                         axis_name[d], axis_name[d]));
      b.prescribed_gradient[d] = g.vector(axis_name[d], dim, "velocity gradients in 1/s", any);
    }
    g.finish();
  }
  s.finish();
  c.bodies.push_back(b);
}

void read_boundary(Section& s, Config& c) {
  const std::vector<std::string> kinds{"free", "roller", "fixed"};
  for (int d = 0; d < c.dimension; ++d)
    for (int side = 0; side < 2; ++side) {
      const std::string key = fmt::format("{}_{}", axis_name[d], side == 0 ? "min" : "max");
      c.boundary.faces[d][side] = static_cast<FaceCondition>(s.choice(key, kinds, 0));
    }
  const auto sets = s.tables("nodes");
  for (std::size_t i = 0; i < sets.size(); ++i) {
    Section n(*sets[i], fmt::format("{}.nodes.{}", s.path(), i), s.file());
    NodeSetConfig ns;
    ns.min = n.vector("min", c.dimension, "m", any);
    ns.max = n.vector("max", c.dimension, "m", any);
    for (int d = 0; d < c.dimension; ++d)
      if (ns.max[d] < ns.min[d])
        n.fail("max", fmt::format("expected max >= min along {}, got {} < {}", axis_name[d], ns.max[d], ns.min[d]));
    const toml::node& fix = n.need("fix", "an array of axis names, e.g. [\"x\", \"y\"]");
    auto a = fix.as_array();
    if (!a || a->empty()) n.fail("fix", fmt::format("expected a non-empty array of axis names, got {}", describe(fix)));
    for (const auto& e : *a) ns.fix[read_axis(n, "fix", e, c.dimension)] = true;
    n.finish();
    c.boundary.node_sets.push_back(ns);
  }
  s.finish();
}

void read_solver(Section& s, Config& c) {
  auto& v = c.solver;
  v.scheme = static_cast<Scheme>(s.choice("scheme", {"usf", "usl", "musl"}, 2));
  v.shape = static_cast<ShapeKind>(s.choice("shape_function", {"linear", "ugimp", "gimp"}, 2));
  v.pic_fraction = s.number("pic_fraction", "a fraction in [0, 1]", [](double x) { return x >= 0 && x <= 1; }, 0.0);
  v.damping = s.number("damping", "a coefficient in [0, 1)", [](double x) { return x >= 0 && x < 1; }, 0.0);
  v.mass_threshold = s.number("mass_threshold", "a fraction in (0, 1)", [](double x) { return x > 0 && x < 1; }, 1e-9);
  s.finish();
}

void read_time(Section& s, Config& c) {
  auto& t = c.time;
  t.end = s.number("end", "a positive time in s", positive);
  t.courant = s.optional_number("courant", "a Courant number in (0, 1]", [](double x) { return x > 0 && x <= 1; });
  t.dt = s.optional_number("dt", "a positive time step in s", positive);
  if (t.courant && t.dt) s.fail("dt", "give either 'courant' or 'dt', not both");
  if (!t.courant && !t.dt) t.courant = 0.5;
  t.max_steps = s.integer("max_steps", "a non-negative whole number", [](std::int64_t n) { return n >= 0; }, 0);
  s.finish();
}

void read_output(Section& s, Config& c) {
  auto& o = c.output;
  o.directory = s.string("directory", "a directory path", o.directory);
  if (o.directory.empty()) s.fail("directory", "expected a directory path, got an empty string");
  o.interval = s.number("interval", "a non-negative time in s", non_negative, 0.0);
  o.global_interval = s.number("global_interval", "a non-negative time in s", non_negative, 0.0);
  o.write_frames = s.boolean("frames", true);
  o.fields.clear();
  if (const toml::node* n = s.get("fields")) {
    auto a = n->as_array();
    if (!a) s.fail("fields", fmt::format("expected an array of field names, got {}", describe(*n)));
    for (const auto& e : *a) {
      auto str = e.as_string();
      if (!str || !is_particle_field(str->get()))
        s.fail("fields", fmt::format("expected field names from {}, got {}", particle_field_list(), describe(e)));
      if (std::find(o.fields.begin(), o.fields.end(), str->get()) != o.fields.end())
        s.fail("fields", fmt::format("field \"{}\" is listed twice", str->get()));
      o.fields.push_back(str->get());
    }
  } else {
    o.fields = all_particle_fields();
  }
  s.finish();
}

// Axis-aligned boxes that share a positive volume.
bool overlap(const BodyConfig& a, const BodyConfig& b, int dim) {
  for (int d = 0; d < dim; ++d)
    if (a.max[d] <= b.min[d] || b.max[d] <= a.min[d]) return false;
  return true;
}

Config read_document(const toml::table& root, const std::string& file) {
  Config c;
  c.source = file;
  Section top(root, "", file);
  const toml::table* model = top.table("model");
  if (!model) top.need("model", "a [model] table with 'dimension'");
  Section ms(*model, "model", file);
  read_model(ms, c);

  const toml::table* grid = top.table("grid");
  if (!grid) top.need("grid", "a [grid] table");
  Section gs(*grid, "grid", file);
  read_grid(gs, c);

  const auto mats = top.tables("materials");
  if (mats.empty()) top.need("materials", "at least one [[materials]] table");
  for (std::size_t i = 0; i < mats.size(); ++i) {
    Section s(*mats[i], fmt::format("materials.{}", i), file);
    read_material(s, c);
  }

  const auto bodies = top.tables("bodies");
  if (bodies.empty()) top.need("bodies", "at least one [[bodies]] table");
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    Section s(*bodies[i], fmt::format("bodies.{}", i), file);
    read_body(s, c, i);
    for (std::size_t j = 0; j < i; ++j)
      if (overlap(c.bodies[i], c.bodies[j], c.dimension))
        s.fail("min", fmt::format("body \"{}\" overlaps body \"{}\"", c.bodies[i].name, c.bodies[j].name));
  }

  if (const toml::table* t = top.table("boundary")) {
    Section s(*t, "boundary", file);
    read_boundary(s, c);
  }
  if (const toml::table* t = top.table("solver")) {
    Section s(*t, "solver", file);
    read_solver(s, c);
  }
  const toml::table* time = top.table("time");
  if (!time) top.need("time", "a [time] table with 'end'");
  Section ts(*time, "time", file);
  read_time(ts, c);

  toml::table no_output;
  const toml::table* out = top.table("output");
  Section os(out ? *out : no_output, "output", file);
  read_output(os, c);

  top.finish();
  return c;
}

// Puts `value` (TOML syntax) at a dotted path; numeric parts index arrays of tables.
void apply_override(toml::table& root, const std::string& assignment, const std::string& file) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(fmt::format("{}: override '{}': expected key=value", file, assignment));
  std::string path = assignment.substr(0, eq);
  path.erase(path.find_last_not_of(" \t") + 1);
  const std::string value = assignment.substr(eq + 1);
  toml::table parsed;
  try {
    parsed = toml::parse(std::string_view(std::string("v = ") + value), std::string_view("override"));
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}: override '{}': the value is not valid TOML ({})", file,
                                 assignment, e.description()));
  }
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string p; std::getline(ss, p, '.');) parts.push_back(p);
  toml::node* here = &root;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    toml::node* next = nullptr;
    if (auto t = here->as_table()) {
      next = t->get(parts[i]);
      if (!next) next = &t->insert_or_assign(parts[i], toml::table{}).first->second;
    } else if (auto a = here->as_array()) {
      char* end = nullptr;
      const long k = std::strtol(parts[i].c_str(), &end, 10);
      if (*end == '\0' && k >= 0 && static_cast<std::size_t>(k) < a->size()) next = a->get(static_cast<std::size_t>(k));
    }
    if (!next || !(next->is_table() || next->is_array()))
      throw InputError(fmt::format("{}: override '{}': '{}' does not name a table", file, assignment, parts[i]));
    here = next;
  }
  auto t = here->as_table();
  if (!t) throw InputError(fmt::format("{}: override '{}': cannot set an array entry", file, assignment));
  t->insert_or_assign(parts.back(), *parsed.get("v"));
}

Config parse(const std::string& text, const std::string& file, const std::vector<std::string>& overrides) {
  toml::table root;
  try {
    root = toml::parse(std::string_view(text), std::string_view(file));
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}:{}:{}: {}", file, e.source().begin.line, e.source().begin.column,
                                 e.description()));
  }
  for (const auto& o : overrides) apply_override(root, o, file);
  return read_document(root, file);
}

}  // namespace

Config read_config_string(const std::string& text, const std::string& source_name,
                          const std::vector<std::string>& overrides) {
  return parse(text, source_name, overrides);
}

Config read_config_file(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open the input file", path));
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse(ss.str(), path, overrides);
}

}  // namespace tsuchi
