#include "tsuchi/io/config_reader.hpp"

#include "tsuchi/io/stage_reader.hpp"
#include "tsuchi/io/csv_table.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/core/expression.hpp"
#include "tsuchi/model/particle_fields.hpp"

#include "tsuchi/io/function_reader.hpp"
#include "tsuchi/io/load_reader.hpp"
#include "tsuchi/io/material_reader.hpp"
#include "tsuchi/io/node_set_reader.hpp"
#include "tsuchi/io/particle_file_reader.hpp"
#include "tsuchi/io/shape_reader.hpp"
#include "tsuchi/io/toml_section.hpp"
#include "tsuchi/solver/grid_projection.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <sstream>
#include <unordered_set>

namespace tsuchi {

namespace {

using namespace io;

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
  c.title = s.one_line("title", "a title", std::string{});
  c.gravity = s.vector("gravity", c.dimension, "m/s^2", any, Triple{});
  c.gravity_function = read_function_ref(s, "gravity_function", c);
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
  double nodes = 1;
  for (int d = 0; d < dim; ++d) nodes *= g.cells[d] + 1.0;
  if (nodes > 2e9)
    s.fail("cell_size", fmt::format("expected a grid of at most 2e9 nodes, got {:.3g} nodes of {} m", nodes, g.cell_size));
  // Positions are doubles: at |x| one unit in the last place is |x| 2^-52, and a step's displacement
  // below it is lost. Far from the coordinate origin (origin 1e12 m: +33 % kinetic energy, the
  // symmetry broken) that is a visible part of a cell; the column of column_self_weight keeps 7
  // digits of its energies up to 1e8 m with 0.05 m cells, so the line is drawn at 1e-7 of a cell.
  double far = 0.0;
  for (int d = 0; d < dim; ++d) far = std::max({far, std::abs(g.origin[d]), std::abs(g.origin[d] + g.extent[d])});
  const double ulp = far * std::numeric_limits<double>::epsilon();
  if (ulp > 1e-7 * g.cell_size)
    c.warnings.push_back(s.located(
        "origin", fmt::format("the grid reaches {:.3g} m from the coordinate origin, where a position is kept to "
                              "{:.2g} m ({:.2g} of a cell): displacements smaller than that in a step are lost; "
                              "place the model near 0 (grid.origin and the bodies shifted by the same offset) and "
                              "add the offset back in post-processing",
                              far, ulp, ulp / g.cell_size)));
  s.finish();
}

// A z key in a 2D model is not a typo of x or y: the user has a 3D model in mind.
void refuse_z_in_2d(const Section& s, std::string_view key, int dim) {
  if (dim == 2 && s.has(key))
    s.fail(key, "expected a key of the x or y axis: model.dimension is 2 (plane strain), which has no z axis");
}

void read_velocity_components(Section& s, std::string_view key, int dim, BodyConfig& b) {
  const toml::table* t = s.table(key);
  if (!t) return;
  Section v(*t, s.key_path(key), s.file());
  refuse_z_in_2d(v, "z", dim);
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
  b.velocity_where = where(s.file(), n->source());
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
        s.fail("velocity", fmt::format("entry {} ({}) \"{}\" is not a valid formula: {}", d, "xyz"[d], f->get(), err.what()));
      }
      b.velocity_formula[d] = f->get();
    } else {
      b.velocity[d] = s.number_of("velocity", e, expected);
    }
  }
}

// Exactly one of: isotropic (a number), tensor (the Voigt components), k0 (geostatic under gravity).
void read_initial_stress(Section& s, const Config& c, BodyConfig& b) {
  auto& is = b.initial_stress;
  is.where = where(s.file(), s.raw().source());
  const int dim = c.dimension;
  const int given = s.has("isotropic") + s.has("tensor") + s.has("k0");
  if (given != 1)
    s.fail_one_of({"isotropic", "tensor", "k0"},
                  "give exactly one of 'isotropic' (Pa), 'tensor' (Pa) and 'k0' (geostatic)");
  if (s.has("isotropic")) {
    is.kind = InitialStressConfig::Kind::Uniform;
    const double v = s.number("isotropic", "a stress in Pa (tension positive: a confining pressure is negative)", any);
    is.tensor = {v, v, v, 0.0, 0.0, 0.0};
  } else if (s.has("tensor")) {
    is.kind = InitialStressConfig::Kind::Uniform;
    const toml::node& n = *s.get("tensor");
    const int nv = dim == 2 ? 4 : 6;
    const std::string expected = dim == 2 ? "[xx, yy, zz, xy] in Pa" : "[xx, yy, zz, xy, yz, xz] in Pa";
    auto a = n.as_array();
    if (!a || static_cast<int>(a->size()) != nv)
      s.fail("tensor", fmt::format("expected an array of {} numbers {}, got {}", nv, expected,
                                   a ? fmt::format("{} entries", a->size()) : describe(n)));
    for (int k = 0; k < nv; ++k) is.tensor[static_cast<std::size_t>(k)] = s.number_of("tensor", *a->get(static_cast<std::size_t>(k)), expected);
  } else {
    is.kind = InitialStressConfig::Kind::K0;
    is.k0 = s.number("k0", "a coefficient of earth pressure at rest > 0", positive);
    int axes = 0;
    for (int d = 0; d < dim; ++d) axes += c.gravity[d] != 0.0;
    if (axes != 1)
      s.fail("k0", "a K0 profile needs model.gravity along one axis (the vertical), with the other components 0");
    if (b.particles)
      s.fail("k0", "a K0 profile needs a body with a shape (the overburden is integrated through the shapes); particles "
                   "read from a file take their stress from the file's stress columns or from 'isotropic' / 'tensor'");
    is.surface = s.optional_number("surface", "the coordinate of the free surface in m", any);
    is.surface_stress = s.number("surface_stress", "the vertical stress at the surface in Pa (tension positive)",
                                 [](double v) { return v <= 0.0; }, 0.0);
  }
  if (is.kind != InitialStressConfig::Kind::K0)
    for (const char* k : {"surface", "surface_stress"})
      if (s.has(k)) s.fail(k, "applies only to a 'k0' profile");
  is.subtract = s.boolean("subtract", false);
  s.finish();
}

void read_imperfection(Section& s, const Config& c, BodyConfig& b) {
  auto& im = b.imperfection;
  const Material& mat = c.materials[b.material_index];
  // An imperfection scales the strength factors of the material's state.
  if (!has_state_field(mat, field_name::cohesion_factor) || !has_state_field(mat, field_name::friction_factor)) {
    std::string models;
    for (std::string_view m : models_with_state_field(field_name::friction_factor))
      models += fmt::format("{}\"{}\"", models.empty() ? "" : ", ", m);
    s.fail_here(fmt::format("material \"{}\" of body \"{}\" has no strength to perturb; an imperfection needs "
                            "a material with a cohesion and a friction angle ({})", mat.name, b.name, models));
  }
  im.amplitude = s.number("amplitude", "a relative amplitude in [0, 1)", [](double v) { return v >= 0 && v < 1; });
  im.seed = static_cast<std::uint64_t>(s.integer("seed", "a whole number >= 0", [](std::int64_t v) { return v >= 0; }, -1));
  if (!s.has("seed")) s.need("seed", "a whole number >= 0 (the same seed gives the same field)");
  im.cohesion = im.friction = true;
  if (const toml::node* n = s.get("parameters")) {
    im.cohesion = im.friction = false;
    auto a = n->as_array();
    const std::string expected = "a non-empty array of \"cohesion\" and/or \"friction_angle\"";
    if (!a || a->empty()) s.fail("parameters", fmt::format("expected {}, got {}", expected, describe(*n)));
    for (const auto& e : *a) {
      const auto str = e.as_string();
      if (str && str->get() == "cohesion") im.cohesion = true;
      else if (str && str->get() == "friction_angle") im.friction = true;
      else s.fail("parameters", fmt::format("expected {}, got {}", expected, describe(e)));
    }
  }
  const std::string limit = std::visit(
      [&](const auto& m) -> std::string {
        if constexpr (requires { m.imperfection_limit(0.0, true, true); })
          return m.imperfection_limit(im.amplitude, im.cohesion, im.friction);
        else
          return {};
      },
      mat.model);
  if (!limit.empty()) s.fail("amplitude", limit);
  s.finish();
}

int material_index(const Section& s, const Config& c, const std::string& name) {
  auto it = std::find_if(c.materials.begin(), c.materials.end(), [&](const Material& m) { return m.name == name; });
  if (it == c.materials.end()) {
    const std::string names = quoted_list(c.materials, &Material::name);
    s.fail("material", fmt::format("expected one of the materials defined ({}), got \"{}\"",
                                   names.empty() ? "none defined" : names, name));
  }
  return static_cast<int>(it - c.materials.begin());
}


// The region a body fills (io/shape_reader.hpp), which must lie inside the grid.
void read_body_shape(Section& s, Config& c, BodyConfig& b, const std::string& directory) {
  const int dim = c.dimension;
  b.shape_kind = shape_kind(s);
  b.shape_key = s.has("shape") ? "shape" : "min";
  b.shape = read_shape(s, dim, directory, Extent::Bounded, &c.data_files, &c.warnings);
  if (const toml::node* n = s.get(b.shape_key)) b.shape_where = where(s.file(), n->source());
  const geometry::Bounds bb = b.shape->bounds();
  for (int d = 0; d < dim; ++d) {
    const double lo = c.grid.origin[d], hi = c.grid.origin[d] + c.grid.extent[d];
    // A file in single precision (binary STL) is allowed its rounding: a surface meant to end on
    // the grid's face may read a few 1e-9 m beyond it.
    const double precision = b.shape->precision();
    const double tol = std::max(1e-9 * c.grid.extent[d], precision);
    if (bb.min[d] < lo - tol || bb.max[d] > hi + tol) {
      const char* key = b.shape_key == "shape" ? "shape" : bb.min[d] < lo - tol ? "min" : "max";
      s.fail(key, fmt::format("body \"{}\" reaches outside the grid along {}: [{}, {}] is not inside [{}, {}]{}{}", b.name,
                              axis_name[d], bb.min[d], bb.max[d], lo, hi,
                              b.shape_key == "shape" ? " (the bounds of its shape)" : "",
                              precision > 0.0 ? fmt::format(", even allowing {:.3g} m for the single precision of its "
                                                            "file's coordinates", precision)
                                              : std::string{}));
    }
  }
}

// particles = "FILE": a CSV table or a tsuchi .vtu frame (io/particle_file_reader.hpp).
void read_particle_source(Section& s, Config& c, BodyConfig& b, const std::string& directory) {
  for (const char* k : {"shape", "min", "max", "particles_per_cell"})
    if (s.has(k))
      s.fail(k, fmt::format("expected either particles from a file ('particles') or a shape, not both: remove '{}'", k));
  ParticleFileRequest r;
  const std::string file = s.string("particles", "the name of a .csv or .vtu file of particles");
  r.path = data_path(file, directory);
  r.key = s.key_path("particles");
  r.key_where = where(s.file(), s.get("particles")->source());
  r.dimension = c.dimension;
  r.grid = c.grid;
  r.keep_velocity = s.boolean("keep_velocity", false);
  if (s.has("keep_velocity") && std::filesystem::path(r.path).extension() != ".vtu")
    s.fail("keep_velocity", "applies only to particles read from a .vtu frame; a CSV gives velocities in its "
                            "velocity_x, velocity_y(, velocity_z) columns");
  b.particles = read_particle_file(r);
  c.file_digests.push_back(b.particles->digest);  // a restart checks the particles too
  c.data_files.push_back({r.path, fmt::format("{}: key '{}'", r.key_where, r.key)});
  if (const ParticleTable& t = *b.particles; t.small_particles > 0)
    c.warnings.push_back(fmt::format(
        "{}: key '{}': {} particle{} of the file (the first at {}) {} an edge below 1/20 of a cell ({} m; the smallest "
        "{:.3g} m): far more particles per cell than a model needs, or a file in another unit (sizes and coordinates "
        "are read in m)",
        r.key_where, r.key, t.small_particles, t.small_particles == 1 ? "" : "s", t.first_small,
        t.small_particles == 1 ? "has" : "have", c.grid.cell_size, t.smallest_edge));
  b.shape_kind = "file";
  b.shape_key = "particles";
  b.shape_where = r.key_where;
}

void read_body(Section& s, Config& c, std::size_t index) {
  const int dim = c.dimension;
  BodyConfig b;
  b.name = s.string("name", "a body name", fmt::format("body{}", index));
  b.material = s.string("material", "the name of a material");
  for (const auto& other : c.bodies)
    if (other.name == b.name) s.fail("name", fmt::format("body \"{}\" is defined twice", b.name));
  b.material_index = material_index(s, c, b.material);
  b.priority = static_cast<int>(s.integer("priority", "a whole number (where bodies overlap, the higher keeps the particles)",
                                          [](std::int64_t v) { return v >= -1000000 && v <= 1000000; }, 0));
  const std::string directory = input_directory(c.source);
  if (s.has("particles")) {
    read_particle_source(s, c, b, directory);
  } else {
    read_body_shape(s, c, b, directory);
    if (s.has("keep_velocity")) s.fail("keep_velocity", "applies only to particles read from a .vtu frame ('particles')");
  }
  for (const toml::table* t : s.tables("regions")) {
    Section rs(*t, fmt::format("{}.regions.{}", s.path(), b.regions.size()), s.file());
    RegionConfig r;
    r.material = rs.string("material", "the name of a material");
    r.material_index = material_index(rs, c, r.material);
    r.kind = shape_kind(rs);
    r.shape = read_shape(rs, dim, directory, Extent::Bounded, &c.data_files, &c.warnings);
    rs.finish();
    b.regions.push_back(r);
  }
  if (const toml::node* n = s.get("particles_per_cell")) {
    auto valid = [](std::int64_t v) { return v >= 1 && v <= 16; };
    const std::string expected = "a whole number from 1 to 16, or an array of one per axis";
    if (auto i = n->as_integer()) {
      if (!valid(i->get())) s.fail("particles_per_cell", fmt::format("expected {}, got {}", expected, describe(*n)));
      b.particles_per_cell.fill(static_cast<int>(i->get()));
    } else if (auto a = n->as_array(); a && static_cast<int>(a->size()) == dim) {
      for (int d = 0; d < dim; ++d) {
        const toml::node& n_d = *a->get(static_cast<std::size_t>(d));
        auto e = n_d.as_integer();
        if (!e || !valid(e->get()))
          s.fail("particles_per_cell", fmt::format("expected {}, got {} in entry {}", expected, describe(n_d), d));
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
    refuse_z_in_2d(g, "z", dim);
    for (int d = 0; d < dim; ++d) {
      if (!g.has(axis_name[d])) continue;
      if (!b.prescribed[d])
        g.fail(axis_name[d], fmt::format("component {} has a gradient but no prescribed_velocity.{}",
                                         axis_name[d], axis_name[d]));
      b.prescribed_gradient[d] = g.vector(axis_name[d], dim, "velocity gradients in 1/s", any);
    }
    g.finish();
  }
  b.prescribed_velocity_function = read_function_ref(s, "prescribed_velocity_function", c);
  b.rigid_mass = s.number("rigid_mass", "a positive mass in kg (kg per metre of thickness in 2D)", positive, 0.0);
  if (b.rigid_mass > 0.0 && std::any_of(b.velocity_formula.begin(), b.velocity_formula.end(), [](const std::string& f) { return !f.empty(); }))
    s.fail("velocity", "a rigid body (rigid_mass) starts with one velocity; expected numbers, not formulas");
  if (b.prescribed_velocity_function >= 0 && std::none_of(b.prescribed.begin(), b.prescribed.end(), [](bool p) { return p; }))
    s.fail("prescribed_velocity_function", "scales the prescribed velocity, but the body has no prescribed_velocity");
  if (const toml::table* t = s.table("initial_stress")) {
    Section is(*t, s.key_path("initial_stress"), s.file());
    read_initial_stress(is, c, b);
  }
  if (const toml::table* t = s.table("imperfection")) {
    Section im(*t, s.key_path("imperfection"), s.file());
    read_imperfection(im, c, b);
  }
  s.finish();
  c.bodies.push_back(b);
}

// A Coulomb coefficient mu >= 0 or "rough" (no slip: +infinity); with `bonded`, also "bonded"
// (returns -1). The same words for a contact pair and a frictional wall.
double read_friction(Section& s, std::string_view key, bool bonded) {
  const std::string expected = bonded ? "a friction coefficient >= 0, \"rough\" or \"bonded\""
                                      : "a friction coefficient >= 0 or \"rough\"";
  const toml::node& n = s.need(key, expected);
  if (const auto* str = n.as_string()) {
    std::string v = str->get();
    std::transform(v.begin(), v.end(), v.begin(), [](unsigned char ch) { return std::tolower(ch); });
    if (v == "rough") return std::numeric_limits<double>::infinity();
    if (bonded && v == "bonded") return -1.0;
  } else if (n.is_integer() || n.is_floating_point()) {
    const double mu = s.number_of(key, n, expected);
    if (mu >= 0.0) return mu == 0.0 ? 0.0 : mu;  // -0 is 0
  }
  s.fail(key, fmt::format("expected {}, got {}", expected, describe(n)));
}

// A grid face: "free", "roller", "fixed", or { friction = MU } (a rigid wall with Coulomb friction).
void read_face(Section& s, Config& c, int axis, int side) {
  const std::string key = fmt::format("{}_{}", axis_name[axis], side == 0 ? "min" : "max");
  const toml::node* n = s.get(key);
  auto& face = c.boundary.faces[static_cast<std::size_t>(axis)][static_cast<std::size_t>(side)];
  face = FaceCondition::Free;
  if (!n) return;
  if (const auto* t = n->as_table()) {
    Section f(*t, s.key_path(key), s.file());
    f.get("friction");  // an unknown key ({ mu = 0.3 }) is reported before the missing friction
    f.finish();
    face = FaceCondition::Friction;
    c.boundary.face_friction[static_cast<std::size_t>(axis)][static_cast<std::size_t>(side)] =
        read_friction(f, "friction", false);
    return;
  }
  if (const auto* str = n->as_string()) {
    std::string v = str->get();
    std::transform(v.begin(), v.end(), v.begin(), [](unsigned char ch) { return std::tolower(ch); });
    const std::array<std::string_view, 3> kinds{"free", "roller", "fixed"};
    for (std::size_t k = 0; k < kinds.size(); ++k)
      if (v == kinds[k]) {
        face = static_cast<FaceCondition>(k);
        return;
      }
  }
  s.fail(key, fmt::format("expected one of \"free\", \"roller\", \"fixed\" or a table {{ friction = MU }} "
                          "(a frictional wall; MU >= 0 or \"rough\"), got {}", describe(*n)));
}

void read_boundary(Section& s, Config& c) {
  for (const char* k : {"z_min", "z_max"}) refuse_z_in_2d(s, k, c.dimension);
  for (int d = 0; d < c.dimension; ++d)
    for (int side = 0; side < 2; ++side) read_face(s, c, d, side);
  const auto sets = s.tables("nodes");
  std::unordered_set<std::string> names;  // a hash set: 2e4 sets were a quadratic scan
  for (std::size_t i = 0; i < sets.size(); ++i) {
    Section n(*sets[i], fmt::format("{}.nodes.{}", s.path(), i), s.file());
    NodeSetConfig ns;
    ns.min = n.vector("min", c.dimension, "m", any);
    ns.max = n.vector("max", c.dimension, "m", any);
    for (int d = 0; d < c.dimension; ++d)
      if (ns.max[d] < ns.min[d])
        n.fail("max", fmt::format("expected max >= min along {}, got {} < {}", axis_name[d], ns.max[d], ns.min[d]));
    if (const toml::node* fix = n.get("fix")) {
      auto a = fix->as_array();
      if (!a || a->empty()) n.fail("fix", fmt::format("expected a non-empty array of axis names, got {}", describe(*fix)));
      for (const auto& e : *a) ns.fix[read_axis(n, "fix", e, c.dimension)] = true;
    }
    read_node_set_motion(n, c, ns);  // name, velocity / acceleration (base motion)
    if (!ns.name.empty() && !names.insert(ns.name).second)
      n.fail("name", fmt::format("node set \"{}\" is defined twice", printable(ns.name)));
    n.finish();
    c.boundary.node_sets.push_back(ns);
  }
  s.finish();
}

// A volumetric-strain average chosen in the input for a material whose plastic flow dilates: its
// default is "none" (model/config.hpp, anti_locking_of). Valid, and kept, but worth a line.
void warn_averaged_dilatant(const Section& s, std::vector<std::string>& warnings, const Material& m,
                            AntiLocking remedy) {
  const double psi = dilatancy_angle_of(m);
  if (!(psi > 0.0) || remedy == AntiLocking::None) return;
  warnings.push_back(s.located(
      "anti_locking",
      fmt::format("material \"{}\" dilates (dilatancy angle {:.3g} deg) and takes \"{}\": an averaged volumetric "
                  "strain cannot follow the dilation of the points that shear, which overstates the strength (the "
                  "paper's triaxial test at 10 deg: +20 %) and can run away (Mohr-Coulomb, \"node\" in plane strain "
                  "when sin(psi) > (1 - 2 nu) / 3, \"node\" and \"bbar\" in 3D); \"none\" is a dilatant "
                  "material's default (docs/input.md, [solver])",
                  m.name, psi * 180.0 / std::numbers::pi, to_string(remedy))));
}

void read_solver(Section& s, Config& c) {
  auto& v = c.solver;
  v.scheme = static_cast<Scheme>(s.choice("scheme", {"usf", "usl", "musl"}, 2));
  v.shape = static_cast<ShapeKind>(s.choice("shape_function", {"linear", "ugimp", "gimp"}, 2));
  v.pic_fraction = s.number("pic_fraction", "a fraction in [0, 1]", [](double x) { return x >= 0 && x <= 1; }, 0.0);
  // APIC unless the input asks for a FLIP/PIC blend (a pic_fraction alone means FLIP: inputs written
  // when FLIP was the default keep their meaning) or for linear shape functions: a linear-hat node
  // that a particle has just reached takes a sliver of its mass but a full-size force gradient,
  // and APIC's affine fit passes that node's velocity on undamped (a free block collapses within
  // 25 steps, tests/verification_test.cpp), where FLIP weighs it by the sliver.
  const int transfer_default = s.has("pic_fraction") || v.shape == ShapeKind::Linear ? 0 : 1;
  v.velocity_transfer = static_cast<VelocityTransfer>(s.choice("velocity_transfer", {"flip", "apic"}, transfer_default));
  // APIC's particle velocity is the PIC one plus the affine field it carries; a FLIP blend on top
  // would bring back the noise APIC is there to remove (and its angular momentum balance).
  if (v.velocity_transfer == VelocityTransfer::Apic && v.pic_fraction > 0.0)
    s.fail("pic_fraction", fmt::format("expected 0 (or no pic_fraction) with velocity_transfer = \"apic\", got {}: "
                                       "APIC has no FLIP/PIC blend; use velocity_transfer = \"flip\" for a blend",
                                       v.pic_fraction));
  v.anti_locking_given = s.has("anti_locking");
  v.anti_locking = static_cast<AntiLocking>(s.choice("anti_locking", {"none", "cell", "node", "bbar"}, 2));
  // The materials are read before [solver]; those without their own remedy take this one.
  if (v.anti_locking_given)
    for (std::size_t k = 0; k < c.materials.size(); ++k)
      if (!(k < c.material_anti_locking.size() && c.material_anti_locking[k]))
        warn_averaged_dilatant(s, c.warnings, c.materials[k], v.anti_locking);
  v.hold_released_volume = s.boolean("hold_released_volume", true);
  v.damping = s.number("damping", "a coefficient in [0, 1)", [](double x) { return x >= 0 && x < 1; }, 0.0);
  v.mass_threshold = s.number("mass_threshold", "a fraction in (0, 1)", [](double x) { return x > 0 && x < 1; }, 1e-9);
  v.sort_interval = s.integer("sort_interval", "a non-negative whole number of steps", [](std::int64_t n) { return n >= 0; },
                              v.sort_interval);
  s.finish();
}

void read_time(Section& s, Config& c, bool staged) {
  auto& t = c.time;
  if (staged) {
    // Each stage ends by its own end; the run ends with the last stage.
    if (s.has("end"))
      s.fail("end", "a staged run ends with its last stage: give each [[stages]] its end (duration, steps, "
                    "unbalanced_force_ratio, kinetic_energy_ratio or recorder) instead of time.end");
    t.end = std::numeric_limits<double>::infinity();
  } else {
    t.end = s.number("end", "a positive time in s", positive);
  }
  t.courant = s.optional_number("courant", "a Courant number in (0, 1]", [](double x) { return x > 0 && x <= 1; });
  t.dt = s.optional_number("dt", "a positive time step in s", positive);
  if (const toml::node* n = s.get("dt")) t.dt_where = where(s.file(), n->source());
  if (t.courant && t.dt) s.fail("dt", "give either 'courant' or 'dt', not both");
  if (!t.courant && !t.dt) t.courant = 0.5;
  t.max_steps = s.integer("max_steps", "a non-negative whole number", [](std::int64_t n) { return n >= 0; }, 0);
  s.finish();
}

// output.grid_fields: true (the usual set), false, or the names of fields to project to the grid
// (solver/grid_projection.hpp).
void read_grid_fields(Section& s, OutputConfig& o) {
  const toml::node* n = s.get("grid_fields");
  if (!n) return;
  o.grid_fields_where = where(s.file(), n->source());
  const std::string expected = fmt::format("field names from {}", quoted_list(projectable_field_names()));
  if (const auto b = n->as_boolean()) {
    if (b->get()) o.grid_fields = {"velocity", "displacement", "stress", "strain", "max_shear_strain"};
  } else if (const auto a = n->as_array()) {
    for (const auto& e : *a) {
      const auto str = e.as_string();
      const ParticleField* f = str ? find_particle_field(str->get()) : nullptr;
      if (f && (f->quantity == Quantity::Mass || f->quantity == Quantity::Density))
        s.fail("grid_fields", fmt::format("\"{}\" is in every grid frame (the nodal mass m_i and density m_i / V_i); "
                                          "expected {}", str->get(), expected));
      if (!f || !is_projectable_field(*f)) s.fail("grid_fields", fmt::format("expected {}, got {}", expected, describe(e)));
      if (std::find(o.grid_fields.begin(), o.grid_fields.end(), str->get()) != o.grid_fields.end())
        s.fail("grid_fields", fmt::format("field \"{}\" is listed twice", str->get()));
      o.grid_fields.push_back(str->get());
    }
  } else if (const auto one = n->as_string()) {
    s.fail("grid_fields", fmt::format("expected true, false or an array of field names, got {}: one field is an "
                                      "array of one, [\"{}\"]", describe(*n), printable(one->get())));
  } else {
    s.fail("grid_fields", fmt::format("expected true, false or an array of {}, got {}", expected, describe(*n)));
  }
  if (!o.grid_fields.empty() && !o.write_frames)
    s.fail("grid_fields", "grid frames go with the particle frames, and 'frames = false' writes none: set frames = "
                          "true or leave grid_fields out");
}

void read_output(Section& s, Config& c) {
  auto& o = c.output;
  o.directory = s.string("directory", "a directory path", o.directory);
  if (o.directory.empty()) s.fail("directory", "expected a directory path, got an empty string");
  if (const toml::node* n = s.get("directory")) o.directory_where = where(s.file(), n->source());
  o.interval = s.number("interval", "a non-negative time in s", non_negative, 0.0);
  o.global_interval = s.number("global_interval", "a non-negative time in s", non_negative, 0.0);
  o.write_frames = s.boolean("frames", true);
  o.frame_label = s.string("frame_label", "the name of a recorder", std::string{});
  o.label_interval = s.number("label_interval", "a positive step of the frame_label recorder's value", positive, 0.0);
  if (s.has("label_interval") && o.frame_label.empty())
    s.fail("label_interval", "frames by a recorder's value need 'frame_label', the name of that recorder");
  o.fields.clear();
  if (const toml::node* n = s.get("fields")) {
    auto a = n->as_array();
    if (!a) s.fail("fields", fmt::format("expected an array of field names, got {}", describe(*n)));
    for (const auto& e : *a) {
      auto str = e.as_string();
      const ParticleField* f = str ? find_particle_field(str->get()) : nullptr;
      if (!f || !f->frame)
        s.fail("fields", fmt::format("expected field names from {}, got {}", quoted_list(frame_field_names()), describe(e)));
      if (std::find(o.fields.begin(), o.fields.end(), str->get()) != o.fields.end())
        s.fail("fields", fmt::format("field \"{}\" is listed twice", str->get()));
      o.fields.push_back(str->get());
    }
  } else {
    // Every frame field, but a model's state only where some material of the run has that model:
    // a Mohr-Coulomb run's frames carry no preconsolidation pressure.
    for (const std::string& name : frame_field_names()) {
      const ParticleField* f = find_particle_field(name);
      const bool used = f->state < 0 || std::any_of(c.materials.begin(), c.materials.end(),
                                                     [&](const Material& m) { return has_state_field(m, name); });
      if (used) o.fields.push_back(name);
    }
  }
  read_grid_fields(s, o);
  s.finish();
}

void read_checkpoint(Section& s, Config& c) {
  auto& k = c.checkpoint;
  k.every_steps = s.integer("every_steps", "a non-negative whole number of steps", [](std::int64_t n) { return n >= 0; }, 0);
  k.every_minutes = s.number("every_minutes", "a non-negative wall time in minutes", non_negative, 0.0);
  k.file = s.string("file", "a file name", k.file);
  if (const toml::node* n = s.get("file")) k.file_where = where(s.file(), n->source());
  if (k.file.empty() || k.file.back() == '/') s.fail("file", fmt::format("expected a file name, got \"{}\"", k.file));
  s.finish();
}

// [[contact]]: bodies = ["A", "B"], friction = MU, "rough" or "bonded". Whether the pairs can be
// met (a bonded chain joining a frictional pair) is found by build_contact (model/contact.cpp).
void read_contact(Section& s, Config& c) {
  ContactConfig k;
  k.where = fmt::format("{}: key '{}'", where(s.file(), s.raw().source()), s.path());
  const std::string expected = fmt::format("an array of two names of bodies defined ({})",
                                           quoted_list(c.bodies, &BodyConfig::name));
  const toml::node& n = s.need("bodies", expected);
  const auto* a = n.as_array();
  if (!a || a->size() != 2)
    s.fail("bodies", fmt::format("expected {}, got {}", expected, a ? fmt::format("{} entries", a->size()) : describe(n)));
  std::array<int, 2> body{-1, -1};
  for (std::size_t e = 0; e < 2; ++e) {
    const toml::node& entry = *a->get(e);
    const auto* name = entry.as_string();
    if (name) {
      for (std::size_t b = 0; b < c.bodies.size(); ++b)
        if (c.bodies[b].name == name->get()) body[e] = static_cast<int>(b);
    }
    if (body[e] < 0)
      s.fail("bodies", fmt::format("expected the names of bodies defined ({}), got {} in entry {}",
                                   quoted_list(c.bodies, &BodyConfig::name), describe(entry), e));
  }
  if (body[0] == body[1])
    s.fail("bodies", fmt::format("expected two different bodies, got \"{}\" twice: a body does not meet itself",
                                 c.bodies[static_cast<std::size_t>(body[0])].name));
  for (std::size_t j = 0; j < c.contacts.size(); ++j) {
    const auto& o = c.contacts[j];
    if (std::minmax(o.body_a, o.body_b) == std::minmax(body[0], body[1]))
      s.fail("bodies", fmt::format("bodies \"{}\" and \"{}\" are paired already in contact.{}; expected each pair once",
                                   c.bodies[static_cast<std::size_t>(body[0])].name,
                                   c.bodies[static_cast<std::size_t>(body[1])].name, j));
  }
  k.body_a = body[0];
  k.body_b = body[1];
  const double mu = read_friction(s, "friction", true);
  if (std::isinf(mu)) k.law = ContactConfig::Law::Rough;
  else if (mu < 0.0) k.law = ContactConfig::Law::Bonded;
  else k.law = ContactConfig::Law::Frictional, k.friction = mu;
  s.finish();
  c.contacts.push_back(k);
}

// FNV-1a, 64 bit, fed with the input's values themselves rather than a printed form, so the
// fingerprint does not depend on how a toml++ version formats numbers.
struct Fnv {
  std::uint64_t h = 1469598103934665603ull;
  void bytes(const void* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) h = (h ^ static_cast<const unsigned char*>(p)[i]) * 1099511628211ull;
  }
  void text(std::string_view s) {
    const std::uint64_t n = s.size();
    bytes(&n, sizeof n);
    bytes(s.data(), s.size());
  }
  void tag(char c) { bytes(&c, 1); }
  void node(const toml::node& n) {
    if (const auto* t = n.as_table()) {
      tag('t');
      for (const auto& [k, v] : *t) text(k.str()), node(v);  // toml++ keeps keys sorted
      tag('}');
    } else if (const auto* a = n.as_array()) {
      tag('a');
      for (const auto& v : *a) node(v);
      tag(']');
    } else if (const auto* i = n.as_integer()) {
      const std::int64_t v = i->get();
      tag('i'), bytes(&v, sizeof v);
    } else if (const auto* f = n.as_floating_point()) {
      const double v = f->get() == 0.0 ? 0.0 : f->get();  // -0.0 and 0.0 are the same input
      tag('f'), bytes(&v, sizeof v);
    } else if (const auto* b = n.as_boolean()) {
      tag(b->get() ? '1' : '0');
    } else if (const auto* str = n.as_string()) {
      tag('s'), text(str->get());
    } else {
      std::ostringstream o;  // dates and times: not read by tsuchi, hashed as printed
      n.visit([&](const auto& v) { o << v; });
      tag('d'), text(o.str());
    }
  }
};

// The fingerprint of the input without the keys a restart may change.
std::uint64_t fingerprint(const toml::table& root) {
  toml::table t = root;
  t.erase("output");
  t.erase("checkpoint");
  t.erase("fos");  // the factor of safety's search: trials start from the run's state, not part of it
  if (auto* m = t.get_as<toml::table>("model")) m->erase("title");
  if (auto* time = t.get_as<toml::table>("time")) {
    for (const char* k : {"end", "max_steps", "dt", "courant"}) time->erase(k);
    if (time->empty()) t.erase("time");  // a staged input may have none, until --set makes one
  }
  if (auto* recs = t.get_as<toml::array>("recorders"))
    for (auto& r : *recs)
      if (auto* rt = r.as_table()) rt->erase("stop_above"), rt->erase("stop_below");
  Fnv f;
  f.node(t);
  return f.h;
}

// A reaction recorder's grid face (boundary = "y_min") or named node set (nodes = "NAME").
void read_reaction_target(Section& s, const Config& c, RecorderConfig& r) {
  if (s.has("boundary")) {
    const std::string face = s.string("boundary", "a grid face such as \"y_min\"");
    std::vector<std::string> faces;
    for (int d = 0; d < c.dimension; ++d)
      for (const char* side : {"min", "max"}) faces.push_back(fmt::format("{}_{}", axis_name[d], side));
    const auto it = std::find(faces.begin(), faces.end(), face);
    if (it == faces.end())
      s.fail("boundary", fmt::format("expected a grid face ({}), got \"{}\"", quoted_list(faces), printable(face)));
    r.face = static_cast<int>(it - faces.begin());
  } else {
    s.get("boundary");
  }
  if (s.has("nodes")) {
    const std::string name = s.string("nodes", "the name of a [[boundary.nodes]] set");
    const auto& sets = c.boundary.node_sets;
    const auto it = std::find_if(sets.begin(), sets.end(), [&](const NodeSetConfig& n) { return n.name == name; });
    if (name.empty() || it == sets.end()) {
      std::vector<std::string> named;
      for (const auto& n : sets)
        if (!n.name.empty()) named.push_back(n.name);
      s.fail("nodes", fmt::format("expected the name of a [[boundary.nodes]] set ({}), got \"{}\"",
                                  named.empty() ? std::string("none is named: give the set a 'name'") : quoted_list(named),
                                  printable(name)));
    }
    r.node_set = static_cast<int>(it - sets.begin());
  } else {
    s.get("nodes");
  }
}

// `names`: the recorders' names so far, a set so that 1e5 recorders are read in linear time.
void read_recorder(Section& s, Config& c, std::unordered_set<std::string>& names) {
  RecorderConfig r;
  r.where = where(s.file(), s.raw().source());
  const int dim = c.dimension;
  r.name = s.string("name", "a column name (letters, digits, _)");
  const bool valid = !r.name.empty() && !std::isdigit(static_cast<unsigned char>(r.name[0])) &&
                     std::all_of(r.name.begin(), r.name.end(), [](unsigned char ch) { return std::isalnum(ch) || ch == '_'; });
  if (!valid) s.fail("name", fmt::format("expected a column name of letters, digits and _, got \"{}\"", r.name));
  if (r.name == "time" || r.name == "step") s.fail("name", fmt::format("\"{}\" is a column of its own; choose another name", r.name));
  if (!names.insert(r.name).second) s.fail("name", fmt::format("recorder \"{}\" is defined twice", r.name));
  if (s.has("body")) {
    const std::string body = s.string("body", "the name of a body");
    auto it = std::find_if(c.bodies.begin(), c.bodies.end(), [&](const BodyConfig& b) { return b.name == body; });
    if (it == c.bodies.end()) {
      s.fail("body", fmt::format("expected one of the bodies defined ({}), got \"{}\"",
                                 quoted_list(c.bodies, &BodyConfig::name), body));
    }
    r.body = static_cast<int>(it - c.bodies.begin());
  } else {
    s.get("body");
  }
  read_reaction_target(s, c, r);  // boundary = "y_min" or nodes = "NAME"
  if (s.has("min")) r.min = s.vector("min", dim, "m (initial positions)", any);
  else s.get("min");
  if (s.has("max")) r.max = s.vector("max", dim, "m (initial positions)", any);
  else s.get("max");
  if (r.min && r.max)
    for (int d = 0; d < dim; ++d)
      if ((*r.max)[d] < (*r.min)[d])
        s.fail("max", fmt::format("expected max >= min along {}, got {} < {}: the box holds no point",
                                  axis_name[d], (*r.max)[d], (*r.min)[d]));
  r.quantity = s.string("quantity", "a particle quantity, unbalanced_force_ratio or reaction_x/y/z");
  if (const int axis = r.reaction_axis(); axis >= 0) {
    // The force holding one prescribed-motion body, or the supports' force at a grid face or node
    // set: a total, no subset to choose or reduce.
    if (axis >= dim)
      s.fail("quantity", fmt::format("recorder \"{}\": \"{}\" has no axis in a {}D model", r.name, r.quantity, dim));
    const int targets = (r.body >= 0) + (r.face >= 0) + (r.node_set >= 0);
    if (targets > 1)
      s.fail(r.node_set >= 0 ? "nodes" : "boundary",
             fmt::format("recorder \"{}\": quantity \"{}\" is the force on one body, grid face or node set; "
                         "expected only one of 'body', 'boundary' and 'nodes'", r.name, r.quantity));
    if (targets == 0)
      s.fail("quantity", fmt::format("recorder \"{}\": quantity \"{}\" is the force on one body, grid face or node "
                                     "set; add body = \"NAME\" (a body with prescribed_velocity), boundary = \"y_min\" "
                                     "(a held grid face) or nodes = \"NAME\" (a named [[boundary.nodes]] set)",
                                     r.name, r.quantity));
  }
  if (const int axis = r.reaction_axis(); axis >= 0 && r.body >= 0) {
    const BodyConfig& b = c.bodies[static_cast<std::size_t>(r.body)];
    if (!b.prescribed[static_cast<std::size_t>(axis)])
      s.fail("quantity", fmt::format("recorder \"{}\": body \"{}\" has no prescribed_velocity.{}, so nothing holds it "
                                     "along {} and its reaction is 0; expected a prescribed component",
                                     r.name, b.name, "xyz"[axis], "xyz"[axis]));
  }
  if (r.reaction_axis() >= 0) {
    for (const char* key : {"min", "max", "reduction"})
      if (s.has(key))
        s.fail(key, fmt::format("recorder \"{}\": quantity \"{}\" is the force on the whole {}; it takes no '{}' "
                                "(remove it)", r.name, r.quantity,
                                r.body >= 0 ? "body" : r.face >= 0 ? "face" : "node set", key));
  } else if (r.face >= 0 || r.node_set >= 0) {
    const char* key = r.face >= 0 ? "boundary" : "nodes";
    s.fail(key, fmt::format("recorder \"{}\": '{}' selects the nodes of a support force; expected quantity "
                            "reaction_x/y{} with it, got \"{}\"", r.name, key, dim == 3 ? "/z" : "", r.quantity));
  } else if (r.whole_model()) {
    // One number for the whole model: no particle set to choose or reduce.
    for (const char* key : {"body", "min", "max", "reduction"})
      if (s.has(key))
        s.fail(key, fmt::format("recorder \"{}\": quantity \"{}\" is a whole-model number; it takes no '{}' (remove it)",
                                r.name, r.quantity, key));
  } else if (!find_recorder_quantity(r.quantity, dim)) {
    s.fail("quantity", fmt::format("expected one of {}, \"{}\" or reaction_x/y{}, got \"{}\"",
                                   quoted_list(recorder_quantities(dim)), kUnbalancedForceRatio, dim == 3 ? "/z" : "",
                                   r.quantity));
  }
  r.reduction = static_cast<RecorderConfig::Reduction>(s.choice("reduction", {"mean", "sum", "min", "max"}, 0));
  r.scale = s.number("scale", "a finite factor", any, 1.0);
  r.offset = s.number("offset", "a finite offset", any, 0.0);
  r.stop_above = s.optional_number("stop_above", "a value at which the run stops", any);
  r.stop_below = s.optional_number("stop_below", "a value at which the run stops", any);
  s.finish();
  c.recorders.push_back(r);
}

Config read_document(const toml::table& root, const std::string& file, bool staged) {
  Config c;
  c.source = file;
  Section top(root, "", file);
  // Functions first: any table may refer to one by name.
  read_functions(top, c);
  const toml::table* model = top.table("model");
  if (!model) top.need("model", "a [model] table with 'dimension'");
  Section ms(*model, "model", file);
  read_model(ms, c);

  const toml::table* grid = top.table("grid");
  if (!grid) top.need("grid", "a [grid] table");
  Section gs(*grid, "grid", file);
  read_grid(gs, c);

  const auto mats = top.need_tables("materials", "at least one [[materials]] table");
  for (std::size_t i = 0; i < mats.size(); ++i) {
    Section s(*mats[i], fmt::format("materials.{}", i), file);
    // A numerical choice, not a constitutive one, so read here and not by read_material (element
    // tests have no grid to average over).
    const int anti_locking = s.choice("anti_locking", {"none", "cell", "node", "bbar"}, -1);
    c.material_anti_locking.push_back(anti_locking < 0 ? std::nullopt
                                                       : std::optional(static_cast<AntiLocking>(anti_locking)));
    c.materials.push_back(read_material(s, c.materials, &c.warnings));
    if (anti_locking >= 0) warn_averaged_dilatant(s, c.warnings, c.materials.back(), static_cast<AntiLocking>(anti_locking));
  }

  const auto bodies = top.need_tables("bodies", "at least one [[bodies]] table");
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    Section s(*bodies[i], fmt::format("bodies.{}", i), file);
    read_body(s, c, i);  // overlaps are found where the particles are placed (model/model.cpp)
  }

  if (const toml::table* t = top.table("boundary")) {
    Section s(*t, "boundary", file);
    read_boundary(s, c);
  }
  read_loads(top, c);
  const auto contacts = top.tables("contact");
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    Section s(*contacts[i], fmt::format("contact.{}", i), file);
    read_contact(s, c);
  }
  if (const toml::table* t = top.table("solver")) {
    Section s(*t, "solver", file);
    read_solver(s, c);
  }
  toml::table no_time;
  const toml::table* time = top.table("time");
  if (!time && !staged) top.need("time", "a [time] table with 'end'");
  Section ts(time ? *time : no_time, "time", file);
  read_time(ts, c, staged);

  toml::table no_output;
  const toml::table* out = top.table("output");
  Section os(out ? *out : no_output, "output", file);
  read_output(os, c);

  if (const toml::table* t = top.table("checkpoint")) {
    Section s(*t, "checkpoint", file);
    read_checkpoint(s, c);
  }

  const auto recorders = top.tables("recorders");
  std::unordered_set<std::string> recorder_names;
  for (std::size_t i = 0; i < recorders.size(); ++i) {
    Section s(*recorders[i], fmt::format("recorders.{}", i), file);
    read_recorder(s, c, recorder_names);
  }

  if (!c.output.frame_label.empty()) {
    const auto it = std::find_if(c.recorders.begin(), c.recorders.end(),
                                 [&](const RecorderConfig& r) { return r.name == c.output.frame_label; });
    if (it == c.recorders.end())
      os.fail("frame_label", fmt::format("expected the name of a recorder ({}), got \"{}\"",
                                         c.recorders.empty() ? std::string("none defined")
                                                             : quoted_list(c.recorders, &RecorderConfig::name),
                                         printable(c.output.frame_label)));
    if (it->from_solver())
      os.fail("frame_label", fmt::format("recorder \"{}\" records {}, which the solver gives only after the first "
                                         "step; label the frames by a particle quantity's recorder",
                                         it->name, it->quantity));
    c.output.frame_label_recorder = static_cast<int>(it - c.recorders.begin());
  }
  // Read with the stages, by read_staged (it names a stage).
  top.get("fos");
  top.finish();
  c.fingerprint = fingerprint(root);
  for (const std::uint64_t d : c.file_digests) c.fingerprint = (c.fingerprint ^ d) * 1099511628211ull;
  return c;
}

// The input, and for [[stages]] the input as it stands during each stage (io/stage_reader.hpp):
// the returned Config is the first stage's, stages[k].config stage k's. The file is parsed again for
// each stage so that every value keeps its place in the file for messages.
Config read_input(const std::string& text, const std::string& file, const std::vector<std::string>& overrides) {
  const toml::table root = io::parse_toml(text, file, overrides);
  const std::size_t count = io::stage_count(root, file);
  auto fos = [&](Config& c) {
    if (const toml::table* t = root.get_as<toml::table>("fos")) {
      Section s(*t, "fos", file);
      io::read_fos(s, c);
    }
  };
  // A function no key names in any stage: a warning (defect 6 of issue 41).
  auto warn_unnamed_functions = [](Config& c, const std::vector<const Config*>& inputs) {
    for (std::size_t k = 0; k < c.functions.size(); ++k)
      if (std::none_of(inputs.begin(), inputs.end(), [&](const Config* in) { return in->functions[k].named; }))
        c.warnings.push_back(c.functions[k].unused_warning);
  };
  if (count == 0) {
    Config c = read_document(root, file, false);
    fos(c);
    warn_unnamed_functions(c, {&c});
    return c;
  }
  std::vector<StageConfig> stages;
  for (std::size_t k = 0; k < count; ++k) {
    auto during = std::make_shared<Config>();
    try {
      *during = read_document(io::merge_stages(io::parse_toml(text, file, overrides), k, file), file, true);
    } catch (const InputError& e) {
      // Only a stage's change can make a later stage's input invalid: say which stage it is in. In
      // the first stage, so when the file without its stages reads well.
      if (k == 0) {
        toml::table base = io::parse_toml(text, file, overrides);
        base.erase("stages");
        try {
          read_document(base, file, true);
        } catch (const InputError&) {
          throw e;
        }
      }
      const auto* name = root.get_as<toml::array>("stages")->get(k)->as_table()->get_as<std::string>("name");
      throw InputError(fmt::format("{} (in stage {}{}, with the changes of the stages up to it)", e.what(), k + 1,
                                   name ? fmt::format(" \"{}\"", printable(name->get())) : std::string{}));
    }
    StageConfig st = io::read_stage(root, k, *during, file);
    st.config = during;
    stages.push_back(std::move(st));
  }
  Config c = *stages.front().config;
  // The warnings of every stage's input, each once (a stage's value that looks like a slip of units).
  for (std::size_t k = 1; k < stages.size(); ++k)
    for (const auto& w : stages[k].config->warnings)
      if (std::find(c.warnings.begin(), c.warnings.end(), w) == c.warnings.end()) c.warnings.push_back(w);
  // And every file they read (a region's STL surface), which the output must not overwrite.
  for (std::size_t k = 1; k < stages.size(); ++k)
    for (const DataFile& f : stages[k].config->data_files)
      if (std::none_of(c.data_files.begin(), c.data_files.end(),
                       [&](const DataFile& g) { return g.path == f.path && g.where == f.where; }))
        c.data_files.push_back(f);
  c.stages = std::move(stages);
  c.fingerprint = fingerprint(root);
  for (const std::uint64_t d : c.file_digests) c.fingerprint = (c.fingerprint ^ d) * 1099511628211ull;
  io::check_stage_sequence(c, root);
  fos(c);
  std::vector<const Config*> inputs;
  for (const auto& st : c.stages) inputs.push_back(st.config.get());
  warn_unnamed_functions(c, inputs);
  for (auto& st : c.stages) {
    // Each stage's input carries the run's identity and sequence, for whoever is handed one alone.
    auto during = std::make_shared<Config>(*st.config);
    during->fingerprint = c.fingerprint;
    during->body_starts_dormant = c.body_starts_dormant;
    during->fos = c.fos;
    st.config = during;
  }
  return c;
}

}  // namespace

Config read_config_string(const std::string& text, const std::string& source_name,
                          const std::vector<std::string>& overrides) {
  return read_input(text, source_name, overrides);
}

Config read_config_file(const std::string& path, const std::vector<std::string>& overrides) {
  return read_input(io::read_input_file(path), path, overrides);
}

}  // namespace tsuchi
