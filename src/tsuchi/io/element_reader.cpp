#include "tsuchi/io/element_reader.hpp"

#include "tsuchi/core/principal_frame.hpp"
#include "tsuchi/io/material_reader.hpp"
#include "tsuchi/io/toml_section.hpp"

#include <algorithm>
#include <cctype>
#include <iterator>
#include <numbers>
#include <optional>

namespace tsuchi::io {

namespace {

using element::component_name;
using element::Control;
using element::ElementPath;
using element::n_components;
using element::Segment;

enum Component { XX, YY, ZZ, XY, YZ, XZ };

// Beyond this the CSV text alone would run to hundreds of megabytes.
constexpr long max_total_increments = 1'000'000;

Voigt<3> isotropic(double s) {
  Voigt<3> v = Voigt<3>::Zero();
  v[XX] = v[YY] = v[ZZ] = s;
  return v;
}

int read_increments(Section& s, std::optional<int> fallback) {
  const std::string expected = fmt::format("a whole number of increments from 1 to {}", max_total_increments);
  if (!fallback && !s.has("increments")) s.need("increments", expected);
  return static_cast<int>(s.integer(
      "increments", expected, [](std::int64_t v) { return v >= 1 && v <= max_total_increments; }, fallback.value_or(1)));
}

// Presets: every component not set here stays strain-driven with zero change.
Segment preset_segment(int increments) {
  Segment seg;
  seg.increments = increments;
  return seg;
}

void drive(Segment& seg, int c, double change) { seg.control[c] = {Control::Strain, change}; }
void hold(Segment& seg, int c) { seg.control[c] = {Control::StressHold, 0.0}; }
void target(Segment& seg, int c, double value) { seg.control[c] = {Control::StressTarget, value}; }

// Lab engineers give pressures and axial strains compression positive; the path stores the
// solver's tension-positive values.
double read_pressure(Section& s, std::string_view key, std::optional<double> fallback = {}) {
  return s.number(key, "a pressure >= 0 in Pa (compression positive)", non_negative, fallback);
}

double read_axial_strain(Section& s) {
  return s.number("axial_strain", "an axial strain in (0, 1), compression positive",
                  [](double v) { return v > 0.0 && v < 1.0; });
}

// Triaxial compression or extension, or plane-strain compression, from an isotropic state, with
// the axial (y) strain driven. Drained: the cell pressure is held on the sides. Undrained: the
// volume is held (no pore water flows and water and grains are taken as incompressible), so the
// lateral strains are driven too; the stresses are then effective stresses.
ElementPath triaxial(Section& s, bool plane_strain, bool extension) {
  const double p = read_pressure(s, "confining_pressure");
  const double ea = read_axial_strain(s);
  const bool undrained = s.choice("drainage", {"drained", "undrained"}, 0) == 1;
  const int n = read_increments(s, 100);
  ElementPath path;
  path.initial_stress = isotropic(-p);
  Segment seg = preset_segment(n);
  const double eyy = extension ? ea : -ea;  // tension positive: compression shortens y
  drive(seg, YY, eyy);
  if (undrained) {
    drive(seg, XX, plane_strain ? -eyy : -eyy / 2.0);
    drive(seg, ZZ, plane_strain ? 0.0 : -eyy / 2.0);
  } else {
    hold(seg, XX);
    if (plane_strain) drive(seg, ZZ, 0.0);
    else hold(seg, ZZ);
  }
  path.segments.push_back(seg);
  path.kind = plane_strain ? "plane_strain_compression" : extension ? "triaxial_extension" : "triaxial_compression";
  const char* test = plane_strain ? "plane-strain compression" : extension ? "triaxial extension" : "triaxial compression";
  if (undrained)
    path.description = fmt::format("undrained {}: from {:g} Pa isotropic, {} (volume held), eps_yy to {:g} in {} increments",
                                   test, -p, plane_strain ? "eps_xx = -eps_yy, eps_zz = 0" : "eps_xx = eps_zz = -eps_yy/2",
                                   eyy, n);
  else if (plane_strain)
    path.description = fmt::format(
        "plane-strain compression: sig_xx held at {:g} Pa, eps_zz = 0, eps_yy to {:g} in {} increments", -p, eyy, n);
  else
    path.description = fmt::format("drained {}: sig_xx = sig_zz held at {:g} Pa, eps_yy to {:g} in {} increments", test,
                                   -p, eyy, n);
  return path;
}

ElementPath simple_shear(Section& s) {
  const double sv = read_pressure(s, "vertical_stress", 0.0);
  const double k0 = s.number("k0", "a lateral stress ratio K0 > 0", positive, 1.0);
  const double gamma = s.number("shear_strain", "an engineering shear strain gamma_xy, not 0, |gamma| < 1",
                                [](double v) { return v != 0.0 && std::abs(v) < 1.0; });
  const bool constant_height = s.choice("vertical", {"constant_stress", "constant_height"}, 0) == 1;
  const int n = read_increments(s, 100);
  ElementPath path;
  path.initial_stress = isotropic(-k0 * sv);
  path.initial_stress[YY] = -sv;
  Segment seg = preset_segment(n);
  drive(seg, XY, 0.5 * gamma);
  if (!constant_height) hold(seg, YY);
  path.segments.push_back(seg);
  path.kind = "simple_shear";
  path.description = fmt::format("simple shear: gamma_xy to {:g} in {} increments, {}, eps_xx = eps_zz = 0", gamma,
                                 n, constant_height ? "eps_yy = 0 (constant height)"
                                                    : fmt::format("sig_yy held at {:g} Pa", -sv));
  return path;
}

ElementPath isotropic_compression(Section& s) {
  const double p0 = read_pressure(s, "initial_pressure", 0.0);
  const bool by_stress = s.has("final_pressure"), by_strain = s.has("volumetric_strain");
  if (by_stress == by_strain)
    s.fail_one_of({"final_pressure", "volumetric_strain"},
                  "give exactly one of 'final_pressure' (Pa, stress control) and 'volumetric_strain' (strain control)");
  ElementPath path;
  path.initial_stress = isotropic(-p0);
  path.kind = "isotropic_compression";
  Segment seg = preset_segment(1);
  if (by_stress) {
    const double pf = read_pressure(s, "final_pressure");
    for (int c : {XX, YY, ZZ}) target(seg, c, -pf);
    seg.increments = read_increments(s, 100);
    path.description = fmt::format("isotropic compression: p from {:g} to {:g} Pa in {} increments", p0, pf,
                                   seg.increments);
  } else {
    const double ev = s.number("volumetric_strain", "a volumetric strain in (-1, 1), not 0, compression positive",
                               [](double v) { return v != 0.0 && std::abs(v) < 1.0; });
    for (int c : {XX, YY, ZZ}) drive(seg, c, -ev / 3.0);
    seg.increments = read_increments(s, 100);
    path.description = fmt::format("isotropic compression: from p = {:g} Pa, eps_v to {:g} in {} increments", p0, ev,
                                   seg.increments);
  }
  path.segments.push_back(seg);
  return path;
}

// The same shape as a body's initial_stress in a run input (without the gravity-bound k0 form):
// { isotropic = -50e3 } or { tensor = [xx, yy, zz, xy, yz, xz] }.
Voigt<3> read_initial_stress(Section& test) {
  const toml::table* t = test.table("initial_stress");
  if (!t) return Voigt<3>::Zero();
  Section s(*t, test.key_path("initial_stress"), test.file());
  if (s.has("isotropic") == s.has("tensor"))
    s.fail_one_of({"isotropic", "tensor"},
                  "give exactly one of 'isotropic' (Pa) and 'tensor' (Pa, [xx, yy, zz, xy, yz, xz])");
  Voigt<3> v;
  if (s.has("isotropic")) {
    v = isotropic(s.number("isotropic", "a stress in Pa (tension positive: a confining pressure is negative)", any));
  } else {
    const std::string expected = "[xx, yy, zz, xy, yz, xz] in Pa, tension positive";
    const toml::node& n = *s.get("tensor");
    auto a = n.as_array();
    if (!a || a->size() != n_components)
      s.fail("tensor", fmt::format("expected an array of {} numbers {}, got {}", n_components, expected,
                                   a ? fmt::format("{} entries", a->size()) : describe(n)));
    for (int c = 0; c < n_components; ++c)
      v[c] = s.number_of("tensor", *a->get(static_cast<std::size_t>(c)), expected);
  }
  s.finish();
  return v;
}

Segment read_segment(Section& s) {
  Segment seg;
  seg.increments = read_increments(s, std::nullopt);
  const toml::table empty;
  const toml::table* strain_t = s.table("strain");
  const toml::table* stress_t = s.table("stress");
  Section strain(strain_t ? *strain_t : empty, s.key_path("strain"), s.file());
  Section stress(stress_t ? *stress_t : empty, s.key_path("stress"), s.file());
  // Unknown keys first: a misspelt component ("XX", "xy ") is better reported as such than as a
  // component left uncontrolled.
  for (Section* t : {&strain, &stress})
    for (auto&& [k, v] : t->raw()) {
      std::string lower(k.str());
      std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char ch) { return std::tolower(ch); });
      if (lower != k.str() && std::find(std::begin(component_name), std::end(component_name), lower) != std::end(component_name))
        t->fail(k.str(), fmt::format("component names are lower case: write '{}'", lower));
    }
  for (const char* name : component_name) strain.get(name), stress.get(name);
  strain.finish();
  stress.finish();
  for (int c = 0; c < n_components; ++c) {
    const char* name = component_name[c];
    const bool by_strain = strain.has(name), by_stress = stress.has(name);
    if (by_strain && by_stress)
      stress.fail(name, fmt::format("component {} is controlled twice: it is also given in '{}'", name,
                                    strain.path()));
    if (!by_strain && !by_stress)
      s.fail_here(fmt::format("component {} is not controlled: give it in 'strain' (its change over the segment) or "
                              "in 'stress' (a target in Pa, or \"hold\")",
                              name));
    if (by_strain) {
      seg.control[c] = {Control::Strain,
                        strain.number(name, "a strain change (tension positive, tensor component)", any)};
      continue;
    }
    const toml::node& v = *stress.get(name);
    const std::string expected = "a target stress in Pa (tension positive) or \"hold\"";
    if (auto str = v.as_string()) {
      if (str->get() != "hold") stress.fail(name, fmt::format("expected {}, got {}", expected, describe(v)));
      seg.control[c] = {Control::StressHold, 0.0};
    } else {
      seg.control[c] = {Control::StressTarget, stress.number_of(name, v, expected)};
    }
  }
  s.finish();
  return seg;
}

ElementPath general(Section& s) {
  ElementPath path;
  path.kind = "general";
  path.initial_stress = read_initial_stress(s);
  const auto tables = s.need_tables("segments", "at least one [[test.segments]] table");
  for (std::size_t i = 0; i < tables.size(); ++i) {
    Section seg(*tables[i], s.key_path(fmt::format("segments.{}", i)), s.file());
    path.segments.push_back(read_segment(seg));
  }
  if (path.total_increments() > max_total_increments)
    s.fail("segments", fmt::format("expected at most {} increments in all, got {}", max_total_increments,
                                   path.total_increments()));
  path.description = fmt::format("general path: {} segment{}, {} increments", path.segments.size(),
                                 path.segments.size() == 1 ? "" : "s", path.total_increments());
  return path;
}

// A point cannot start outside its yield surface: the first increment would jump to it.
void check_inside_yield_surface(const Material& m, const Voigt<3>& sigma, Section& s, std::string_view key) {
  const Eigen::Vector3d v = PrincipalFrame<3>(sigma).values;
  const Inadmissible beyond = std::visit(
      [&](const auto& model) {
        PointStateOf<std::decay_t<decltype(model)>> start;  // a point that starts: every field at its initial value
        start_state(model, v, start.ref());                  // and what depends on the starting stress
        return model.outside(v, start.ref());
      },
      m.model);
  if (!beyond.any()) return;
  s.fail(key, fmt::format("expected an initial stress inside the {} surface of material \"{}\", got one {} "
                          "(principal stresses {:.6g}, {:.6g}, {:.6g} Pa)",
                          beyond.yield_surface, m.name, beyond.detail, v[0], v[1], v[2]));
}

const Material& select_material(Section& test, const std::vector<Material>& materials) {
  const std::string expected =
      fmt::format("the name of the material to test, one of {}", quoted_list(materials, &Material::name));
  if (!test.has("material")) {
    if (materials.size() == 1) {
      test.get("material");
      return materials.front();
    }
    test.need("material", expected);
  }
  const std::string name = test.string("material", expected);
  for (const auto& m : materials)
    if (m.name == name) return m;
  test.fail("material", fmt::format("expected {}, got \"{}\"", expected, name));
}

const std::vector<std::string> kTypes{"triaxial_compression", "plane_strain_compression", "simple_shear",
                                      "isotropic_compression", "general", "triaxial_extension"};

}  // namespace

ElementInput read_element_string(const std::string& text, const std::string& file,
                                 const std::vector<std::string>& overrides) {
  const toml::table root = parse_toml(text, file, overrides);
  Section top(root, "", file);
  ElementInput in;
  in.source = file;
  in.title = top.one_line("title", "a title", std::string{});

  std::vector<Material> materials;
  const auto mats = top.need_tables("materials", "at least one [[materials]] table");
  for (std::size_t i = 0; i < mats.size(); ++i) {
    Section s(*mats[i], fmt::format("materials.{}", i), file);
    materials.push_back(read_material(s, materials, &in.warnings));
  }

  const toml::table* test_t = top.table("test");
  if (!test_t) top.need("test", "a [test] table with the loading path");
  Section test(*test_t, "test", file);
  in.material = select_material(test, materials);
  const int type = test.choice("type", kTypes, -1);
  if (type < 0) test.need("type", fmt::format("the kind of test, one of {}", quoted_list(kTypes)));
  std::string_view stress_key;  // the key an inadmissible initial stress is blamed on
  switch (type) {
    case 0:
    case 1:
    case 5:
      in.path = triaxial(test, type == 1, type == 5);
      stress_key = "confining_pressure";
      break;
    case 2:
      in.path = simple_shear(test);
      stress_key = test.has("k0") ? "k0" : "vertical_stress";
      break;
    case 3:
      in.path = isotropic_compression(test);
      stress_key = "initial_pressure";
      break;
    case 4:
      in.path = general(test);
      stress_key = "initial_stress";
      break;
  }
  test.finish();
  check_inside_yield_surface(in.material, in.path.initial_stress, test, stress_key);

  if (const toml::table* it_t = top.table("iteration")) {
    Section it(*it_t, "iteration", file);
    in.iteration.tolerance = it.number("tolerance", "a relative tolerance from 1e-14 to 1e-3",
                                       [](double v) { return v >= 1e-14 && v <= 1e-3; }, in.iteration.tolerance);
    in.iteration.max_iterations = static_cast<int>(it.integer(
        "max_iterations", "a whole number of iterations from 1 to 1000", [](std::int64_t v) { return v >= 1 && v <= 1000; },
        in.iteration.max_iterations));
    it.finish();
  }
  top.finish();
  return in;
}

ElementInput read_element_file(const std::string& path, const std::vector<std::string>& overrides) {
  return read_element_string(read_input_file(path), path, overrides);
}

std::string describe_material(const Material& m) {
  return std::visit(
      [&](const auto& model) {
        using M = std::decay_t<decltype(model)>;
        // A model with its own elasticity (moduli that follow the stress) describes it itself.
        if constexpr (requires { M::reads_own_elasticity; })
          if (M::reads_own_elasticity)
            return fmt::format("\"{}\": {}, density {:g} kg/m^3{}", m.name, M::name, m.density, model.describe());
        PointStateOf<M> start;
        const LinearElastic& e = model.stiffness(start.ref());
        const double nu = (3.0 * e.K - 2.0 * e.G) / (2.0 * (3.0 * e.K + e.G));
        return fmt::format("\"{}\": {}, density {:g} kg/m^3, G = {:.6g} Pa, nu = {:.6g}{}", m.name, M::name, m.density,
                           e.G, nu, model.describe());
      },
      m.model);
}

}  // namespace tsuchi::io
