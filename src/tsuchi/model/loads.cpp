#include "tsuchi/model/loads.hpp"

#include "tsuchi/core/errors.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_set>

namespace tsuchi {

namespace {

// A site of a body's particle lattice: its lattice indices per axis.
struct Site {
  std::array<std::int64_t, 3> j{};
  bool operator==(const Site& o) const { return j == o.j; }
};

struct SiteHash {
  std::size_t operator()(const Site& s) const {
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the three indices
    for (const std::int64_t v : s.j) h = (h ^ static_cast<std::uint64_t>(v)) * 1099511628211ull;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

template <int D>
Site site_of(const Vec<D>& x, const Vec<D>& l, const Grid<D>& g) {
  Site s;
  for (int d = 0; d < D; ++d) s.j[static_cast<std::size_t>(d)] = std::llround((x[d] - g.origin[d]) / (2.0 * l[d]) - 0.5);
  return s;
}

std::string vec_text(const Triple& v, int dim) {
  std::string r = "[";
  for (int d = 0; d < dim; ++d) r += fmt::format("{}{:.6g}", d ? ", " : "", v[static_cast<std::size_t>(d)]);
  return r + "]";
}

// The faces of a particle that lie on a grid face holding their normal (a roller, fixed or
// friction face: a symmetry plane or a wall): against a support, not a free surface. In the whole
// model a symmetry plane stands for, the mirror particle is there and the face is inside; a
// pressure on it would push the body into the plane (p times the particle spacing at the corner
// of a load box that reaches the plane).
template <int D>
std::uint8_t supported_faces(const Vec<D>& x, const Vec<D>& l, const Grid<D>& g, const BoundaryConfig& b) {
  std::uint8_t mask = 0;
  for (int d = 0; d < D; ++d) {
    const auto k = static_cast<std::size_t>(d);
    // Within half a particle spacing: a stage builds its loads on particles that have moved and
    // whose domains have changed since the start (measured: the wall row of examples/staged_load
    // 2.5e-6 m off the wall after its gravity stage), while the next row in lies a spacing further.
    const double tol = l[d];
    if (b.faces[k][0] != FaceCondition::Free && x[d] - l[d] <= g.origin[d] + tol)
      mask = static_cast<std::uint8_t>(mask | (1u << (2 * d)));
    if (b.faces[k][1] != FaceCondition::Free && x[d] + l[d] >= g.upper()[d] - tol)
      mask = static_cast<std::uint8_t>(mask | (1u << (2 * d + 1)));
  }
  return mask;
}

// A traction or pressure on the selected boundary particles of its body.
template <int D>
ParticleLoad<D> surface_load(const Config& c, const LoadConfig& load, const Particles<D>& p, const Grid<D>& g,
                             std::vector<std::uint8_t>& faces, int& faces_of) {
  if (faces_of != load.body) {
    faces = exposed_faces<D>(p, g, load.body), faces_of = load.body;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (faces[i] != 0) faces[i] = static_cast<std::uint8_t>(faces[i] & ~supported_faces<D>(p.x_p[i], p.l_p[i], g, c.boundary));
  }
  const double tol = 1e-9 * g.h;
  ParticleLoad<D> out;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.body_p[i] != load.body || faces[i] == 0) continue;
    const Vec<D>& x = p.x_p[i];
    std::uint8_t chosen = faces[i];
    if (load.by_plane) {
      // Within one particle spacing of the plane, measured along its normal (for a plane normal to
      // an axis, the spacing along that axis), and only the faces that look out across it.
      double dist = 0.0, width = 0.0;
      for (int d = 0; d < D; ++d) {
        dist += (x[d] - load.plane_point[d]) * load.plane_normal[d];
        width += std::abs(load.plane_normal[d]) * 2.0 * p.l_p[i][d];
      }
      if (std::abs(dist) > width + tol) continue;
      chosen = 0;
      for (int d = 0; d < D; ++d)
        for (int side = 0; side < 2; ++side) {
          const std::uint8_t bit = static_cast<std::uint8_t>(1u << (2 * d + side));
          const double along = side == 0 ? -load.plane_normal[d] : load.plane_normal[d];
          if ((faces[i] & bit) && along > 1e-12) chosen = static_cast<std::uint8_t>(chosen | bit);
        }
    } else {
      bool inside = true;
      for (int d = 0; d < D; ++d) inside = inside && x[d] >= load.min[d] - tol && x[d] <= load.max[d] + tol;
      if (!inside) chosen = 0;
    }
    if (chosen == 0) continue;
    const Vec<D> a = area_vector<D>(chosen, p.l_p[i]);
    Vec<D> F;
    if (load.pressure_given) {
      F = -load.pressure * a;
    } else {
      for (int d = 0; d < D; ++d) F[d] = load.vector[d] * a.norm();
    }
    out.id.push_back(p.id_p[i]);
    out.force.push_back(F);
  }
  if (out.id.empty()) {
    const std::string& body = c.bodies[static_cast<std::size_t>(load.body)].name;
    if (load.by_plane)
      throw InputError(fmt::format(
          "{}: selects no boundary particle: no particle of body \"{}\" with a face exposed towards the normal {} lies "
          "within one particle spacing of the plane through {}; expected the plane of a surface of the body, with "
          "the normal pointing out of it (a face on a roller, fixed or friction grid face is held, not loaded)",
          load.where, body, vec_text(load.plane_normal, D), vec_text(load.plane_point, D)));
    throw InputError(fmt::format(
        "{}: selects no boundary particle: the box from {} to {} holds the centre of no particle of body \"{}\" on its "
        "boundary; expected a box around the loaded surface's particles, whose centres lie half a particle spacing "
        "(cell_size / particles_per_cell / 2) inside the surface (a face on a roller, fixed or friction grid face is "
        "held, not loaded)",
        load.where, vec_text(load.min, D), vec_text(load.max, D), body));
  }
  // By id: the solver applies the forces in this order, the same whatever the particles' storage order.
  std::vector<std::size_t> order(out.id.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return out.id[a] < out.id[b]; });
  ParticleLoad<D> sorted;
  for (const std::size_t k : order) sorted.id.push_back(out.id[k]), sorted.force.push_back(out.force[k]);
  if (load.function >= 0) sorted.function = c.functions[static_cast<std::size_t>(load.function)].f;
  sorted.follow = load.follow;
  return sorted;
}

// The total force shared over the nodes of the box by trapezoid weights: along an axis where the
// set spans several nodes, a node at either end counts half (the force of a uniform line or
// surface load over the set's extent, lumped to its nodes).
template <int D>
NodalLoad<D> nodal_load(const Config& c, const LoadConfig& load, const Grid<D>& g) {
  std::array<int, D> lo{}, hi{};
  bool empty = false;
  for (int d = 0; d < D; ++d) {
    lo[d] = std::max(0, static_cast<int>(std::ceil((load.min[d] - g.origin[d]) / g.h - 1e-9)));
    hi[d] = std::min(g.n_nodes[d] - 1, static_cast<int>(std::floor((load.max[d] - g.origin[d]) / g.h + 1e-9)));
    empty = empty || hi[d] < lo[d];
  }
  if (empty)
    throw InputError(fmt::format("{}: the box from {} to {} holds no grid node; grid nodes lie at multiples of "
                                 "cell_size = {} m from grid.origin",
                                 load.where, vec_text(load.min, D), vec_text(load.max, D), g.h));
  NodalLoad<D> out;
  std::vector<double> weight;
  double total = 0.0;
  std::array<int, D> ijk = lo;
  for (;;) {
    double w = 1.0;
    for (int d = 0; d < D; ++d)
      if (hi[d] > lo[d] && (ijk[d] == lo[d] || ijk[d] == hi[d])) w *= 0.5;
    out.node.push_back(g.index(ijk));
    weight.push_back(w);
    total += w;
    int d = 0;
    while (d < D && ++ijk[d] > hi[d]) ijk[d] = lo[d], ++d;
    if (d == D) break;
  }
  Vec<D> F;
  for (int d = 0; d < D; ++d) F[d] = load.vector[d];
  for (const double w : weight) out.force.push_back((w / total) * F);
  if (load.function >= 0) out.function = c.functions[static_cast<std::size_t>(load.function)].f;
  return out;
}

}  // namespace

template <int D>
std::vector<std::uint8_t> exposed_faces(const Particles<D>& p, const Grid<D>& g, int body) {
  std::unordered_set<Site, SiteHash> sites;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.body_p[i] == body) sites.insert(site_of<D>(p.x_p[i], p.l_p[i], g));
  std::vector<std::uint8_t> faces(p.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.body_p[i] != body) continue;
    const Site s = site_of<D>(p.x_p[i], p.l_p[i], g);
    std::uint8_t mask = 0;
    for (int d = 0; d < D; ++d)
      for (int side = 0; side < 2; ++side) {
        Site n = s;
        n.j[static_cast<std::size_t>(d)] += side == 0 ? -1 : 1;
        if (!sites.count(n)) mask = static_cast<std::uint8_t>(mask | (1u << (2 * d + side)));
      }
    faces[i] = mask;
  }
  return faces;
}

// The exposed faces of a lattice region are its staircase surface. For a constant pressure the
// net force on any closed surface is zero, -p oint n dA = -p int div(I) dV = 0 (divergence
// theorem), and the staircase's faces satisfy it exactly: along every lattice line the faces
// towards +e_d and -e_d alternate, equal in area. Over an open part of a surface the staircase
// gives the same net force as the true surface it approximates, -p times the projected areas
// (tests/loads_test.cpp checks both).
template <int D>
Vec<D> area_vector(std::uint8_t faces, const Vec<D>& l) {
  Vec<D> a = Vec<D>::Zero();
  for (int d = 0; d < D; ++d) {
    double A = 1.0;  // the other edges' product; times 1 m of thickness in 2D
    for (int e = 0; e < D; ++e)
      if (e != d) A *= 2.0 * l[e];
    if (faces & (1u << (2 * d))) a[d] -= A;
    if (faces & (1u << (2 * d + 1))) a[d] += A;
  }
  return a;
}

template <int D>
Loads<D> build_loads(const Config& c, const Particles<D>& p, const Grid<D>& g) {
  Loads<D> loads;
  std::vector<std::uint8_t> faces;
  int faces_of = -1;
  for (const LoadConfig& load : c.loads) {
    switch (load.kind) {
      case LoadConfig::Kind::Traction: loads.surface.push_back(surface_load<D>(c, load, p, g, faces, faces_of)); break;
      case LoadConfig::Kind::NodalForce: loads.nodal.push_back(nodal_load<D>(c, load, g)); break;
      case LoadConfig::Kind::BodyForce: {
        BodyForceLoad<D> b;
        b.acceleration.assign(c.bodies.size(), Vec<D>::Zero());
        for (std::size_t k = 0; k < c.bodies.size(); ++k) {
          if (load.body >= 0 && static_cast<std::size_t>(load.body) != k) continue;
          const double rho = c.materials[static_cast<std::size_t>(c.bodies[k].material_index)].density;
          for (int d = 0; d < D; ++d) b.acceleration[k][d] = load.vector[d] / rho;
        }
        if (load.function >= 0) b.function = c.functions[static_cast<std::size_t>(load.function)].f;
        loads.body.push_back(b);
        break;
      }
    }
  }
  return loads;
}

template std::vector<std::uint8_t> exposed_faces<2>(const Particles<2>&, const Grid<2>&, int);
template std::vector<std::uint8_t> exposed_faces<3>(const Particles<3>&, const Grid<3>&, int);
template Vec<2> area_vector<2>(std::uint8_t, const Vec<2>&);
template Vec<3> area_vector<3>(std::uint8_t, const Vec<3>&);
template Loads<2> build_loads<2>(const Config&, const Particles<2>&, const Grid<2>&);
template Loads<3> build_loads<3>(const Config&, const Particles<3>&, const Grid<3>&);

}  // namespace tsuchi
