#include "tsuchi/solver/contact_stage.hpp"

#include <algorithm>
#include <cmath>

namespace tsuchi {

namespace {

// The velocity change of eq (C3) for a field moving at dv relative to its partner, with the
// normal n towards the partner and the friction coefficient mu (Contact::kBonded: always the
// partner's velocity; Contact::kRough: no slip while in contact). Held components are not changed.
template <int D>
Vec<D> correction(const Vec<D>& dv, const Vec<D>& n, double mu, unsigned held) {
  Vec<D> c = Vec<D>::Zero();
  if (mu < 0.0) {
    c = -dv;
  } else {
    const double dn = dv.dot(n);
    if (!(dn > 0.0)) return c;  // separating or sliding along: no contact force
    const Vec<D> t = dv - dn * n;
    const double tn = t.norm();
    if (mu * dn >= tn) c = -dv;  // sticks (mu = +inf: always)
    else c = -(dn * n + (mu * dn / tn) * t);
  }
  for (int d = 0; d < D; ++d)
    if (held & (1u << d)) c[d] = 0.0;
  return c;
}

// The normal of eq (C1) from a towards b, given g_a and g_b (each pointing out of its body): the
// unit vector of whichever is larger, as NairnMPM's "maximum volume gradient" option. The sum
// g_a - g_b tilts at the corner of a body resting on a wider one (the corner's gradient has a
// large sideways part), and a frictionless block then ploughed 14 % slower down a 30 degree slope
// than sin(theta) g; the wider body's gradient there is the surface's normal.
template <int D>
Vec<D> contact_normal(const Vec<D>& g_a, const Vec<D>& g_b) {
  const double la = g_a.squaredNorm(), lb = g_b.squaredNorm();
  if (la >= lb) return la > 0.0 ? Vec<D>(g_a / std::sqrt(la)) : Vec<D>::Zero();
  return Vec<D>(-g_b / std::sqrt(lb));
}

// n / |n|, or zero when n is zero (no surface to speak of: no contact).
template <int D>
Vec<D> unit(const Vec<D>& n) {
  const double l = n.norm();
  return l > 0.0 ? Vec<D>(n / l) : Vec<D>::Zero();
}

template <class T>
void size_to(std::vector<T>& a, std::size_t n) {
  if (a.size() != n) a.assign(n, T{});
}

}  // namespace

template <int D>
void ContactStage<D>::begin_step(Model<D>& m, const BlockSchedule<D>& schedule, const std::vector<double>& motion_scale) {
  const auto& c = m.contact;
  auto& g = m.grid;
  const std::size_t n = g.size();
  if (c.between_bodies())
    while (static_cast<int>(g.fields.size()) < c.fields + 1) g.add_field();
  scale_ = motion_scale;
  const int first_f = first(m), last_f = last(m);
  const bool usf = m.step.scheme == Scheme::USF;
  grad_m_.resize(c.between_bodies() ? static_cast<std::size_t>(c.fields) : 0);
  dv_start_.resize(usf ? static_cast<std::size_t>(last_f - first_f + 1) : 0);
  for (auto& a : grad_m_) size_to(a, n);
  for (auto& a : dv_start_) size_to(a, n);
  size_to(acted_, n);
  size_to(normal_, n);
  size_to(force_, n);
  schedule.for_active_nodes([&](std::int64_t k) {
    const auto s = static_cast<std::size_t>(k);
    for (auto& a : grad_m_) a[s] = Vec<D>::Zero();
    for (auto& a : dv_start_) a[s] = Vec<D>::Zero();
    acted_[s] = 0;
    normal_[s] = Vec<D>::Zero();
    force_[s] = Vec<D>::Zero();
  });
  wall_impulse_.assign(c.walls.size(), Vec<D>::Zero());
  wall_force_.assign(c.walls.size(), Vec<D>::Zero());
}

template <int D>
void ContactStage<D>::correct(Model<D>& m, const BlockSchedule<D>& schedule, Stage stage, double dt) {
  if (stage == Stage::Solve && !dv_start_.empty() && m.grid.keep_acceleration) {
    // USF: the Start stage's velocity changes join the solve's in a (kept for FLIP only).
    auto& F = m.grid.fields;
    const int f0 = first(m), f1 = last(m);
    schedule.for_active_nodes([&](std::int64_t kk) {
      const auto k = static_cast<std::size_t>(kk);
      if (acted_[k] & 4u)
        for (int f = f0; f <= f1; ++f) F[f].a[k] += dv_start_[static_cast<std::size_t>(f - f0)][k] / dt;
    });
  }
  if (m.contact.between_bodies()) between_fields(m, schedule, stage, dt);
  if (!m.contact.walls.empty()) against_walls(m, schedule, stage, dt);
  if (stage != Stage::Solve) return;
  for (std::size_t w = 0; w < wall_force_.size(); ++w) wall_force_[w] = wall_impulse_[w] / dt;
  // Field 0 then holds the sum of the body fields, for the support reactions (eq R2 reads m v^L
  // at held components, the same in every field) and the unbalanced-force ratio.
  if (!m.contact.between_bodies()) return;
  auto& F = m.grid.fields;
  const int G = m.contact.fields;
  schedule.for_active_nodes([&](std::int64_t k) {
    Vec<D> p = Vec<D>::Zero();
    for (int f = 1; f <= G; ++f) p += F[f].m[k] * F[f].vL[k];
    F[0].vL[k] = F[0].m[k] > 0.0 ? Vec<D>(p / F[0].m[k]) : Vec<D>::Zero();
  });
}

template <int D>
Vec<D> ContactStage<D>::rigid_velocity(const Model<D>& m, int body, std::int64_t k) const {
  const auto& motion = m.motion[static_cast<std::size_t>(body)];
  const Vec<D> x = m.grid.position(m.grid.ijk(k));
  Vec<D> v = motion.v0 + motion.grad * x;
  for (int d = 0; d < D; ++d)
    if (!motion.free[d]) v[d] *= scale_[static_cast<std::size_t>(body)];
  return v;
}

template <int D>
void ContactStage<D>::between_fields(Model<D>& m, const BlockSchedule<D>& schedule, Stage stage, double dt) {
  const auto& c = m.contact;
  auto& F = m.grid.fields;
  const int G = c.fields;
  const double floor = m.step.node_mass_floor;
  std::vector<Vec<D>> NodalField<D>::*const vel = stage == Stage::Solve ? &NodalField<D>::vL : &NodalField<D>::v;
  // Books a velocity change of field f at node k: into a (Solve) so that FLIP particles take it,
  // or into dv_start (Start, folded into a at the solve). Without FLIP the grid keeps no a.
  const bool keep_a = m.grid.keep_acceleration;
  const auto book = [&](int f, std::size_t k, const Vec<D>& dv) {
    (F[f].*vel)[k] += dv;
    if (stage == Stage::Solve) {
      if (keep_a) F[f].a[k] += dv / dt;
    }
    else if (stage == Stage::Start) dv_start_[static_cast<std::size_t>(f - 1)][k] += dv;
  };
  schedule.for_active_nodes([&](std::int64_t kk) {
    const auto k = static_cast<std::size_t>(kk);
    int count = 0, first_f = -1, second_f = -1, rigid = -1;
    double M = 0.0;
    Vec<D> P = Vec<D>::Zero(), GM = Vec<D>::Zero();
    for (int f = 1; f <= G; ++f) {
      const double mf = F[f].m[k];
      if (!(mf > floor)) continue;
      ++count;
      if (first_f < 0) first_f = f;
      else if (second_f < 0) second_f = f;
      M += mf;
      P += mf * (F[f].*vel)[k];
      GM += grad_m_[static_cast<std::size_t>(f - 1)][k];
      if (rigid < 0 && c.rigid_body[static_cast<std::size_t>(f - 1)] >= 0) rigid = f;
    }
    if (count < 2) return;
    const unsigned held = m.grid.fixed_g[k];
    const auto gm = [&](int f) -> const Vec<D>& { return grad_m_[static_cast<std::size_t>(f - 1)][k]; };
    Vec<D> on_first = Vec<D>::Zero();  // momentum change of the lowest field present
    if (count == 2 && rigid < 0) {
      // Two deformable fields: field b takes exactly the opposite momentum change of field a.
      const int a = first_f, b = second_f;
      const Vec<D> n = contact_normal<D>(gm(a), gm(b));
      const Vec<D> dv = correction<D>(Vec<D>((F[a].*vel)[k] - P / M), n, c.law(a, b), held);
      if (dv == Vec<D>::Zero()) return;
      on_first = F[a].m[k] * dv;
      book(a, k, dv);
      book(b, k, Vec<D>(-on_first / F[b].m[k]));
    } else {
      const Vec<D> vr = rigid >= 0 ? rigid_velocity(m, c.rigid_body[static_cast<std::size_t>(rigid - 1)], kk) : Vec<D>::Zero();
      const Vec<D> v_cm = P / M;
      Vec<D> to_rigid = Vec<D>::Zero();
      for (int f = 1; f <= G; ++f) {
        const double mf = F[f].m[k];
        if (!(mf > floor) || f == rigid) continue;
        Vec<D> n, partner;
        double mu;
        if (rigid >= 0) {
          n = -unit<D>(gm(rigid));  // a rigid body's surface is the one known exactly
          partner = vr;
          mu = c.law(f, rigid);
        } else {
          n = contact_normal<D>(gm(f), Vec<D>(GM - gm(f)));
          partner = v_cm;
          int heaviest = -1;
          for (int j = 1; j <= G; ++j)
            if (j != f && F[j].m[k] > floor && (heaviest < 0 || F[j].m[k] > F[heaviest].m[k])) heaviest = j;
          mu = c.law(f, heaviest);
        }
        const Vec<D> dv = correction<D>(Vec<D>((F[f].*vel)[k] - partner), n, mu, held);
        if (dv == Vec<D>::Zero()) continue;
        book(f, k, dv);
        to_rigid -= mf * dv;
        if (f == first_f) on_first = mf * dv;
      }
      if (rigid >= 0 && to_rigid != Vec<D>::Zero()) {
        book(rigid, k, Vec<D>(to_rigid / F[rigid].m[k]));
        if (rigid == first_f) on_first = to_rigid;
      }
      if (on_first == Vec<D>::Zero() && to_rigid == Vec<D>::Zero()) return;
    }
    if (stage == Stage::Remap) return;  // MUSL's remap: for the strain only, not a force
    acted_[k] |= stage == Stage::Start ? 5u : 1u;
    normal_[k] = contact_normal<D>(gm(first_f), Vec<D>(GM - gm(first_f)));
    force_[k] += on_first;
  });
}

// Walls after the bodies: a rigid partner at rest (eq C3 with v_cm = 0), for every deformable
// field at the face's nodes. Serial, in node order: a face has few nodes, and the wall's force is
// then summed in one fixed order.
template <int D>
void ContactStage<D>::against_walls(Model<D>& m, const BlockSchedule<D>& schedule, Stage stage, double dt) {
  const auto& c = m.contact;
  auto& F = m.grid.fields;
  const double floor = m.step.node_mass_floor;
  const int f0 = first(m), f1 = last(m);
  std::vector<Vec<D>> NodalField<D>::*const vel = stage == Stage::Solve ? &NodalField<D>::vL : &NodalField<D>::v;
  for (std::size_t w = 0; w < c.walls.size(); ++w) {
    const auto& wall = c.walls[w];
    for (const std::int64_t kk : wall.nodes) {
      if (!schedule.on_active_tile(kk)) continue;
      const auto k = static_cast<std::size_t>(kk);
      const unsigned held = m.grid.fixed_g[k];
      for (int f = f0; f <= f1; ++f) {
        const double mf = F[f].m[k];
        if (!(mf > floor)) continue;
        if (f > 0 && c.rigid_body[static_cast<std::size_t>(f - 1)] >= 0) continue;  // moves as prescribed
        const Vec<D> dv = correction<D>((F[f].*vel)[k], wall.normal, wall.friction, held);
        if (dv == Vec<D>::Zero()) continue;
        (F[f].*vel)[k] += dv;
        if (stage == Stage::Remap) continue;
        if (stage == Stage::Solve) {
          if (m.grid.keep_acceleration) F[f].a[k] += dv / dt;
        } else
          dv_start_[static_cast<std::size_t>(f - f0)][k] += dv;
        wall_impulse_[w] += mf * dv;
        if (!(acted_[k] & 1u)) {
          normal_[k] = wall.normal;
          if (f == f0 || F[f0].m[k] <= floor) force_[k] += mf * dv;
        }
        acted_[k] |= stage == Stage::Start ? 6u : 2u;
      }
    }
  }
}

template class ContactStage<2>;
template class ContactStage<3>;

}  // namespace tsuchi
