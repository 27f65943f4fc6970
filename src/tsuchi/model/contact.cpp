// The velocity fields of contact from the input's [[contact]] pairs and frictional faces.
//
// Rules (docs/input.md "[[contact]]"):
// - Bonded pairs join bodies (union-find): a chain of them makes one set.
// - Each set holding a body of a frictional or rough pair is a field of its own; every other body
//   (in no such pair, nor bonded to one) goes to one shared "rest" field, made only when some are
//   left. Fields are numbered 1.. in the order of the lowest body index they hold, so the numbering
//   does not depend on the order of the [[contact]] tables.
// - Fewer than two fields (no pair, or bonded pairs only): fields = 0, the step of a model without
//   contact, bit for bit.
// - A frictional or rough pair inside one set cannot slide: an input error, as are two pairs that
//   give the same two fields different laws. Fields no pair relates stay bonded (kBonded).
// - A field of exactly one body whose velocity is prescribed in every component is rigid.
// - Walls: every face with FaceCondition::Friction, built whether or not bodies are in contact.
#include "tsuchi/model/contact.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/model/model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <numeric>
#include <queue>
#include <string>

namespace tsuchi {

namespace {

struct DisjointSets {
  std::vector<int> parent;
  explicit DisjointSets(int n) : parent(static_cast<std::size_t>(n)) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[static_cast<std::size_t>(x)] != x) {
      auto& p = parent[static_cast<std::size_t>(x)];
      p = parent[static_cast<std::size_t>(p)];
      x = p;
    }
    return x;
  }
  void join(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }
};

bool slides(const ContactConfig& k) { return k.law != ContactConfig::Law::Bonded; }

// The bonded pairs from body `from` to body `to`, as "A" - "B" - "C" (shortest chain).
std::string bonded_chain(const Config& c, int from, int to) {
  const int n = static_cast<int>(c.bodies.size());
  std::vector<int> previous(static_cast<std::size_t>(n), -2);
  std::queue<int> open;
  previous[static_cast<std::size_t>(from)] = -1;
  open.push(from);
  while (!open.empty() && previous[static_cast<std::size_t>(to)] == -2) {
    const int b = open.front();
    open.pop();
    for (const auto& k : c.contacts) {
      if (slides(k) || (k.body_a != b && k.body_b != b)) continue;
      const int other = k.body_a == b ? k.body_b : k.body_a;
      if (previous[static_cast<std::size_t>(other)] != -2) continue;
      previous[static_cast<std::size_t>(other)] = b;
      open.push(other);
    }
  }
  std::string chain;
  for (int b = to; b >= 0; b = previous[static_cast<std::size_t>(b)])
    chain = fmt::format("\"{}\"{}{}", c.bodies[static_cast<std::size_t>(b)].name, chain.empty() ? "" : " - ", chain);
  return chain;
}

double law_of(const ContactConfig& k) {
  return k.law == ContactConfig::Law::Rough ? Contact<2>::kRough : k.friction;
}

std::string describe_law(double mu) {
  return std::isinf(mu) ? std::string("rough") : fmt::format("friction {}", mu);
}

}  // namespace

template <int D>
Contact<D> build_contact(const Config& c, const Model<D>& model) {
  Contact<D> r;
  const int bodies = static_cast<int>(c.bodies.size());
  r.field_of_body.assign(static_cast<std::size_t>(bodies), 0);

  DisjointSets sets(bodies);
  for (const auto& k : c.contacts)
    if (!slides(k)) sets.join(k.body_a, k.body_b);
  for (const auto& k : c.contacts) {
    if (!slides(k) || sets.find(k.body_a) != sets.find(k.body_b)) continue;
    throw InputError(fmt::format(
        "{}: bodies \"{}\" and \"{}\" are joined by bonded pairs ({}), so they share one velocity field and cannot "
        "slide on each other; remove a bonded pair of the chain or this contact",
        k.where, c.bodies[static_cast<std::size_t>(k.body_a)].name, c.bodies[static_cast<std::size_t>(k.body_b)].name,
        bonded_chain(c, k.body_a, k.body_b)));
  }

  std::vector<bool> in_contact(static_cast<std::size_t>(bodies), false);  // per set root
  for (const auto& k : c.contacts)
    if (slides(k))
      in_contact[static_cast<std::size_t>(sets.find(k.body_a))] = in_contact[static_cast<std::size_t>(sets.find(k.body_b))] = true;

  // Bodies in increasing order: a field is numbered when its lowest body is met.
  std::vector<int> field_of_root(static_cast<std::size_t>(bodies), 0);
  int rest = 0, fields = 0;
  std::vector<int> field(static_cast<std::size_t>(bodies), 0);
  for (int b = 0; b < bodies; ++b) {
    const auto root = static_cast<std::size_t>(sets.find(b));
    int& f = in_contact[root] ? field_of_root[root] : rest;
    if (f == 0) f = ++fields;
    field[static_cast<std::size_t>(b)] = f;
  }

  if (fields >= 2) {
    r.fields = fields;
    r.field_of_body = field;
    r.bodies_of_field.assign(static_cast<std::size_t>(fields), {});
    for (int b = 0; b < bodies; ++b) r.bodies_of_field[static_cast<std::size_t>(field[static_cast<std::size_t>(b)] - 1)].push_back(b);
    const auto n = static_cast<std::size_t>(fields);
    r.friction.assign(n * n, Contact<D>::kBonded);
    std::vector<int> set_by(n * n, -1);  // the [[contact]] entry that gave each pair of fields its law
    for (std::size_t e = 0; e < c.contacts.size(); ++e) {
      const auto& k = c.contacts[e];
      if (!slides(k)) continue;
      const auto i = static_cast<std::size_t>(field[static_cast<std::size_t>(k.body_a)] - 1);
      const auto j = static_cast<std::size_t>(field[static_cast<std::size_t>(k.body_b)] - 1);
      const double mu = law_of(k);
      const int before = set_by[i * n + j];
      if (before >= 0 && r.friction[i * n + j] != mu) {
        const auto& o = c.contacts[static_cast<std::size_t>(before)];
        throw InputError(fmt::format(
            "{}: {} between \"{}\" and \"{}\", but contact.{} ({} between \"{}\" and \"{}\") relates the same two "
            "velocity fields (bodies joined by bonded pairs share one); expected one law for them",
            k.where, describe_law(mu), c.bodies[static_cast<std::size_t>(k.body_a)].name,
            c.bodies[static_cast<std::size_t>(k.body_b)].name, before, describe_law(law_of(o)),
            c.bodies[static_cast<std::size_t>(o.body_a)].name, c.bodies[static_cast<std::size_t>(o.body_b)].name));
      }
      r.friction[i * n + j] = r.friction[j * n + i] = mu;
      set_by[i * n + j] = set_by[j * n + i] = static_cast<int>(e);
    }
    r.rigid_body.assign(n, -1);
    for (std::size_t f = 0; f < n; ++f) {
      if (r.bodies_of_field[f].size() != 1) continue;
      const int b = r.bodies_of_field[f][0];
      const auto& motion = model.motion[static_cast<std::size_t>(b)];
      // A free rigid body (rigid_mass) is an ordinary partner of its nodal mass in the contact
      // correction: it responds to the impulses, and within a step the correction must not treat
      // it as infinitely heavy (the explicit update of its velocity then rang without decay).
      if (motion.rigid_mass == 0.0 && motion.fully_prescribed())
        r.rigid_body[f] = b;
    }
  }

  const Grid<D>& g = model.grid;
  for (int axis = 0; axis < D; ++axis)
    for (int side = 0; side < 2; ++side) {
      if (c.boundary.faces[static_cast<std::size_t>(axis)][static_cast<std::size_t>(side)] != FaceCondition::Friction)
        continue;
      typename Contact<D>::Wall w;
      w.face = axis * 2 + side;
      w.normal[axis] = side == 0 ? -1.0 : 1.0;
      w.friction = c.boundary.face_friction[static_cast<std::size_t>(axis)][static_cast<std::size_t>(side)];
      // Every ijk of the face: an odometer over the other axes.
      std::array<int, D> ijk{};
      ijk[static_cast<std::size_t>(axis)] = side == 0 ? 0 : g.n_nodes[static_cast<std::size_t>(axis)] - 1;
      for (;;) {
        w.nodes.push_back(g.index(ijk));
        int d = 0;
        for (; d < D; ++d) {
          if (d == axis) continue;
          auto& i = ijk[static_cast<std::size_t>(d)];
          if (++i < g.n_nodes[static_cast<std::size_t>(d)]) break;
          i = 0;
        }
        if (d == D) break;
      }
      std::sort(w.nodes.begin(), w.nodes.end());
      r.walls.push_back(std::move(w));
    }
  return r;
}

template Contact<2> build_contact<2>(const Config&, const Model<2>&);
template Contact<3> build_contact<3>(const Config&, const Model<3>&);

}  // namespace tsuchi
