#include "tsuchi/io/shape_reader.hpp"

#include "tsuchi/geometry/boolean.hpp"
#include "tsuchi/geometry/box.hpp"
#include "tsuchi/geometry/cylinder.hpp"
#include "tsuchi/geometry/disk.hpp"
#include "tsuchi/geometry/extrusion.hpp"
#include "tsuchi/geometry/half_space.hpp"
#include "tsuchi/geometry/polygon.hpp"
#include "tsuchi/geometry/triangle_mesh.hpp"
#include "tsuchi/io/stl_reader.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <span>

namespace tsuchi::io {

namespace {

using geometry::Point;

struct Context {
  int dim;
  const std::string& directory;
  std::vector<DataFile>* files;  // the data files read, or nullptr
  std::vector<std::string>* warnings;  // what is valid but likely not meant, or nullptr
};

Point point_of(const Triple& t, int dim) {
  Point p = Point::Zero();
  for (int d = 0; d < dim; ++d) p[d] = t[d];
  return p;
}

Point read_point(Section& s, const char* key, int dim) {
  return point_of(s.vector(key, dim, fmt::format("{} coordinates in m", dim), any), dim);
}

geometry::ShapePtr read_box(Section& s, const Context& c) {
  const Triple lo = s.vector("min", c.dim, "m", any);
  const Triple hi = s.vector("max", c.dim, "m", any);
  for (int d = 0; d < c.dim; ++d)
    if (hi[d] <= lo[d])
      s.fail("max", fmt::format("expected max > min along {}, got {} <= {}", axis_name[d], hi[d], lo[d]));
  return std::make_shared<geometry::Box>(point_of(lo, c.dim), point_of(hi, c.dim), c.dim);
}

double read_radius(Section& s) { return s.number("radius", "a radius > 0 in m", positive); }

geometry::ShapePtr read_ball(Section& s, const Context& c) {
  const Point centre = read_point(s, "centre", c.dim);
  return std::make_shared<geometry::Ball>(centre, read_radius(s), c.dim);
}

geometry::ShapePtr read_cylinder(Section& s, const Context&) {
  const Point base = read_point(s, "base", 3), top = read_point(s, "top", 3);
  if (base == top) s.fail("top", "expected the centre of the other end, away from base, got the same point as base");
  return std::make_shared<geometry::Cylinder>(base, top, read_radius(s));
}

geometry::ShapePtr read_half_space(Section& s, const Context& c) {
  const Point p = read_point(s, "point", c.dim);
  const Point n = point_of(s.vector("normal", c.dim, "the components of a direction out of the kept side", any), c.dim);
  if (n.isZero(0.0)) s.fail("normal", "expected a direction out of the kept side, got a zero vector");
  return std::make_shared<geometry::HalfSpace>(p, n, c.dim);
}

// A list of [u, v] vertices; a last vertex equal to the first (a closed list) is dropped.
geometry::Ring read_ring(const Section& s, std::string_view key, const toml::node& n, const std::string& what) {
  auto a = n.as_array();
  if (!a) s.fail(key, fmt::format("expected {} as an array of [x, y] vertices, got {}", what, describe(n)));
  geometry::Ring r;
  for (std::size_t i = 0; i < a->size(); ++i) {
    const Triple t =
        s.vector_of(key, *a->get(i), 2, fmt::format("the two coordinates in m of vertex {} of {}", i, what), any);
    r.emplace_back(t[0], t[1]);
  }
  if (r.size() > 1 && r.front() == r.back()) r.pop_back();
  return r;
}

geometry::PolygonRegion read_region(Section& s) {
  const geometry::Ring outline =
      read_ring(s, "vertices", s.need("vertices", "the outline's vertices [[x, y], ...] in m"), "the outline");
  if (auto why = geometry::PolygonRegion::problem(outline, {}))
    s.fail("vertices", fmt::format("expected a simple polygon (3 vertices or more, no two edges crossing or touching), "
                                   "got a polygon whose {}",
                                   *why));
  std::vector<geometry::Ring> holes;
  if (const toml::node* h = s.get("holes")) {
    auto a = h->as_array();
    if (!a)
      s.fail("holes",
             fmt::format("expected an array of holes, each an array of [x, y] vertices, got {}", describe(*h)));
    for (std::size_t i = 0; i < a->size(); ++i)
      holes.push_back(read_ring(s, "holes", *a->get(i), fmt::format("hole {}", i)));
    if (auto why = geometry::PolygonRegion::problem(outline, holes))
      s.fail("holes",
             fmt::format("expected holes inside the outline, apart from each other and from it, got: {}", *why));
  }
  return {outline, std::move(holes)};
}

geometry::ShapePtr read_polygon(Section& s, const Context&) {
  return std::make_shared<geometry::Polygon>(read_region(s));
}

geometry::ShapePtr read_extrusion(Section& s, const Context&) {
  const int axis = s.choice("axis", {"x", "y", "z"}, -1);
  if (axis < 0) s.need("axis", "the axis of extrusion: \"x\", \"y\" or \"z\"");
  geometry::PolygonRegion region = read_region(s);
  const double from = s.number("from", "the start along the axis in m", any);
  const double to = s.number("to", fmt::format("the end along the axis in m, above from = {}", from),
                             [from](double v) { return v > from; });
  return std::make_shared<geometry::Extrusion>(std::move(region), axis, from, to);
}

geometry::ShapePtr read_stl_shape(Section& s, const Context& c) {
  const std::string file = s.string("file", "the name of an STL file (relative to the input file's folder)");
  const double scale = s.number("scale", "a factor > 0 on the file's coordinates (to m)", positive, 1.0);
  const Point offset = point_of(s.vector("offset", 3, "a shift in m added after scaling", any, Triple{}), 3);
  std::filesystem::path path(file);
  if (path.is_relative() && !c.directory.empty()) path = std::filesystem::path(c.directory) / path;
  StlSurface surface;
  try {
    surface = read_stl(path.string());
  } catch (const StlError& e) {
    s.fail("file", fmt::format("expected a readable STL file, got '{}': {}", printable(path.string(), 200), e.what()));
  }
  if (c.files) {
    const std::string at = s.located("file", "");
    c.files->push_back({path.string(), at.substr(0, at.size() - 2)});
  }
  // A binary file stores float32: a coordinate meant as 0.2 reads 0.20000000298. Its rounding is
  // at most half an ulp, 2^-24 of the largest magnitude (a margin of 2 on that).
  double largest = 0.0;
  for (const auto& t : surface.triangles)
    for (const Point& p : t) largest = std::max(largest, p.cwiseAbs().maxCoeff());
  const double precision = surface.binary ? scale * largest * std::ldexp(1.0, -23) : 0.0;
  for (auto& t : surface.triangles)
    for (Point& p : t) p = scale * p + offset;
  const auto name = [&surface](std::size_t k) { return surface.name(k); };
  if (auto why = geometry::TriangleMesh::problem(surface.triangles, name))
    s.fail("file", fmt::format("expected a closed, consistently oriented surface of triangles, got '{}' where {}",
                               printable(path.string(), 200), *why));
  auto mesh = std::make_shared<geometry::TriangleMesh>(surface.triangles, precision);
  // Two closed surfaces that overlap (or nest, facing the same way) are filled by the even-odd
  // rule, which leaves the overlap out (docs/input.md): valid for a cavity, but not what an author
  // of one solid from two shells meant, and cheap to tell from the winding number (issue 41,
  // defect 11). 256 x 256 columns; a difference under 0.1 % of the volume is not said.
  if (c.warnings) {
    const auto fill = mesh->fill_volumes(256);
    if (fill.nonzero - fill.even_odd > 1e-3 * fill.nonzero)
      c.warnings->push_back(s.located(
          "file", fmt::format("the closed surfaces of '{}' overlap or nest facing the same way: by the even-odd rule "
                              "the body fills {:.4g} m^3 of the {:.4g} m^3 inside any of them, leaving the overlap "
                              "out; for one solid, merge the shells into one surface (a boolean union) or give each "
                              "its own body; for a cavity, nothing is wrong",
                              printable(path.string(), 200), fill.even_odd, fill.nonzero)));
  }
  return mesh;
}

// The kinds of shape, by their input name: a new shape is a new file in geometry/ and one line
// here. `dimensions` is 2, 3, or 0 for both; `instead` names the shape to use in the other one.
struct Kind {
  const char* name;
  int dimensions;
  geometry::ShapePtr (*read)(Section&, const Context&);
  const char* instead;
};

constexpr Kind kinds[] = {
    {"box", 0, read_box, ""},
    {"polygon", 2, read_polygon, "\"extrusion\" (a polygon extruded along an axis)"},
    {"disk", 2, read_ball, "\"cylinder\" (keys base, top, radius) or \"sphere\""},
    {"half_space", 0, read_half_space, ""},
    {"sphere", 3, read_ball, "\"disk\""},
    {"cylinder", 3, read_cylinder, "\"disk\""},
    {"extrusion", 3, read_extrusion, "\"polygon\""},
    {"stl", 3, read_stl_shape, "\"polygon\""},
};

// The shape of one table and its booleans; `fallback` is the kind when `shape` is absent (-1: the
// key is required, as in an operand of a boolean).
geometry::ShapePtr read_any(Section& s, const Context& c, int fallback) {
  std::vector<std::string> names;
  for (const Kind& k : kinds) names.emplace_back(k.name);
  const int i = s.choice("shape", names, fallback);
  if (i < 0) s.need("shape", fmt::format("the kind of shape, one of {}", quoted_list(names)));
  const Kind& kind = kinds[i];
  if (kind.dimensions != 0 && kind.dimensions != c.dim)
    s.fail("shape", fmt::format("expected a shape for a {}D model, got \"{}\", which is {}D only: use {}", c.dim,
                                kind.name, kind.dimensions, kind.instead));
  geometry::ShapePtr base = kind.read(s, c);

  std::vector<geometry::ShapePtr> ops[3];
  const char* op_names[3] = {"add", "intersect", "subtract"};
  for (int o = 0; o < 3; ++o) {
    const auto tables = s.tables(op_names[o]);
    for (std::size_t k = 0; k < tables.size(); ++k) {
      Section sub(*tables[k], fmt::format("{}.{}", s.key_path(op_names[o]), k), s.file());
      ops[o].push_back(read_any(sub, c, -1));
      sub.finish();
    }
  }
  if (ops[0].empty() && ops[1].empty() && ops[2].empty()) return base;
  auto b = std::make_shared<geometry::Boolean>(base, std::move(ops[0]), std::move(ops[1]), std::move(ops[2]));
  b->set_base_fills_bounds(kind.read == read_box);
  return b;
}

}  // namespace

// The kind of shape a table describes, as written ("box" when it has no `shape`), for the summary.
std::string shape_kind(Section& s) {
  const toml::node* n = s.get("shape");
  std::string k = n && n->as_string() ? n->as_string()->get() : "box";
  std::transform(k.begin(), k.end(), k.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  // A boolean (docs/shapes.md) as "box minus 1 shape": what the summary shows of it.
  const std::array<std::pair<const char*, const char*>, 3> ops{{{"add", "plus"}, {"intersect", "within"}, {"subtract", "minus"}}};
  for (const auto& op : ops) {
    const toml::node* operands = s.get(op.first);
    const toml::array* a = operands ? operands->as_array() : nullptr;
    if (a) k += fmt::format(" {} {} shape{}", op.second, a->size(), a->size() == 1 ? "" : "s");
  }
  return k;
}

geometry::ShapePtr read_shape(Section& s, int dim, const std::string& directory, Extent extent,
                              std::vector<DataFile>* files, std::vector<std::string>* warnings) {
  const Context c{dim, directory, files, warnings};
  geometry::ShapePtr shape = read_any(s, c, 0);
  if (extent == Extent::Bounded) {
    const geometry::Bounds b = shape->bounds();
    for (int d = 0; d < dim; ++d) {
      if (!std::isfinite(b.min[d]) || !std::isfinite(b.max[d]))
        s.fail("shape", fmt::format("a body's shape must be bounded, got a shape unbounded along {}: intersect the "
                                    "half-space with a box (shape = \"box\", min, max, intersect = [{{shape = "
                                    "\"half_space\", point = ..., normal = ...}}])",
                                    axis_name[d]));
      if (b.max[d] < b.min[d])
        s.fail("shape", fmt::format("expected a shape with something in it, got one whose intersections leave nothing "
                                    "(empty along {})",
                                    axis_name[d]));
    }
  }
  return shape;
}

}  // namespace tsuchi::io
