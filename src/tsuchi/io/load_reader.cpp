#include "tsuchi/io/load_reader.hpp"

#include "tsuchi/io/function_reader.hpp"

#include <algorithm>
#include <cmath>

namespace tsuchi::io {

namespace {

// "FILE:LINE:COL: key 'loads.N.KEY'" for the messages of the model builder, which finds out only
// later whether a selection holds a boundary particle or a node.
std::string prefix(const Section& s, std::string_view key) {
  const std::string at = s.located(key, "");
  return at.substr(0, at.size() - 2);
}

int read_body_ref(Section& s, const Config& c) {
  const std::string name = s.string("body", "the name of a body");
  for (std::size_t k = 0; k < c.bodies.size(); ++k)
    if (c.bodies[k].name == name) return static_cast<int>(k);
  s.fail("body", fmt::format("expected one of the bodies defined ({}), got \"{}\"", quoted_list(c.bodies, &BodyConfig::name),
                             printable(name)));
}

void read_box(Section& s, int dim, LoadConfig& l, const std::string& what) {
  l.min = s.vector("min", dim, what, any);
  l.max = s.vector("max", dim, what, any);
  for (int d = 0; d < dim; ++d)
    if (l.max[d] < l.min[d])
      s.fail("max", fmt::format("expected max >= min along {}, got {} < {}", axis_name[d], l.max[d], l.min[d]));
}

void read_traction(Section& s, const Config& c, LoadConfig& l) {
  const int dim = c.dimension;
  l.body = read_body_ref(s, c);
  const bool box = s.has("min") || s.has("max");
  if (box == s.has("plane"))
    s.fail_here("select the loaded boundary particles by exactly one of a box of initial positions ('min' and "
                "'max') and 'plane' ({point = [...], normal = [...]})");
  if (box) {
    read_box(s, dim, l, "m (initial positions of the loaded boundary particles)");
    l.where = prefix(s, "min");
  } else {
    l.by_plane = true;
    l.where = prefix(s, "plane");
    Section p(*s.table("plane"), s.key_path("plane"), s.file());
    l.plane_point = p.vector("point", dim, "a point of the plane in m", any);
    l.plane_normal = p.vector("normal", dim, "the plane's normal, pointing out of the body", any);
    double norm = 0.0;
    for (int d = 0; d < dim; ++d) norm += l.plane_normal[d] * l.plane_normal[d];
    if (!(norm > 0.0)) p.fail("normal", "expected a nonzero normal vector, got zeros");
    for (int d = 0; d < dim; ++d) l.plane_normal[d] /= std::sqrt(norm);
    p.finish();
  }
  if (s.has("traction") == s.has("pressure"))
    s.fail_one_of({"traction", "pressure"}, "give exactly one of 'traction' (a force per unit area in Pa, global axes) "
                                            "and 'pressure' (Pa, positive pushing into the body)");
  if (s.has("traction")) {
    l.vector = s.vector("traction", dim, "a traction in Pa", any);
    // A traction in global axes has no surface to follow: it stays dead (`follow = false` is allowed).
    if (s.boolean("follow", false))
      s.fail("follow", "a 'traction' is given in global axes and stays a dead load; expected 'follow' only with "
                       "'pressure' (a pressure that follows the deformed surface's normal and area)");
  } else {
    l.pressure_given = true;
    l.pressure = s.number("pressure", "a pressure in Pa (positive pushes into the body)", any);
    l.follow = s.boolean("follow", false);
  }
}

void read_nodal_force(Section& s, const Config& c, LoadConfig& l) {
  const int dim = c.dimension;
  read_box(s, dim, l, "m, a box holding grid nodes");
  l.where = prefix(s, "min");
  l.vector = s.vector("force", dim, dim == 2 ? "the total force in N/m (per metre of thickness)" : "the total force in N",
                      any);
}

void read_body_force(Section& s, const Config& c, LoadConfig& l) {
  if (s.has("body")) l.body = read_body_ref(s, c);
  l.vector = s.vector("force_density", c.dimension, "a force per unit volume in N/m^3", any);
}

}  // namespace

void read_loads(Section& top, Config& c) {
  const auto tables = top.tables("loads");
  for (std::size_t i = 0; i < tables.size(); ++i) {
    Section s(*tables[i], fmt::format("loads.{}", i), top.file());
    LoadConfig l;
    l.kind = static_cast<LoadConfig::Kind>(s.choice("kind", {"traction", "nodal_force", "body_force"}, -1));
    if (!s.has("kind")) s.need("kind", "one of \"traction\", \"nodal_force\" and \"body_force\"");
    l.where = prefix(s, "kind");
    if (l.kind != LoadConfig::Kind::Traction && s.has("follow"))
      s.fail("follow", "expected 'follow' only on a pressure (kind = \"traction\" with 'pressure'): a node-set or "
                       "body force has no surface to follow");
    switch (l.kind) {
      case LoadConfig::Kind::Traction: read_traction(s, c, l); break;
      case LoadConfig::Kind::NodalForce: read_nodal_force(s, c, l); break;
      case LoadConfig::Kind::BodyForce: read_body_force(s, c, l); break;
    }
    l.function = read_function_ref(s, "function", c);
    s.finish();
    c.loads.push_back(l);
  }
}

}  // namespace tsuchi::io
