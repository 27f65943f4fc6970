#pragma once
// The stage that adds the input's [[loads]] (model/loads.hpp) to the nodal force, after the p2g
// pass that sums the internal force (USF: p2g<Force>; USL, MUSL: p2g<All>):
//   body forces  f_i += sum_p S_ip m_p a_b(t)      (a_b = f(t) b / rho, per body: V_p0 b f(t))
//   surface      f_i += sum_p S_ip F_p f(t)        (F_p = -p a_p or t |a_p|, over the loaded particles)
//   node sets    f_i += F_i f(t)                   (only where the node carries mass)
// at the particles' start-of-step positions and widths (the step's stencil factors, which USF's
// stress update has not changed), with every function taken at the start of the step, as the
// gravity is (the explicit update of eq 4 uses the force at t_n).
//
// A node without mass has no velocity (velocity_at() gives it 0 and the solve skips it), so a force
// on it would act on nothing: a node-set load there is dropped until material reaches the node.
//
// Same bits on any thread count: body forces go through the colour-by-colour scatter, in which
// every node sums in a fixed order; the loaded boundary particles are few, and are added by one
// thread in the order of their ids, whatever their storage order. Their storage indices are looked
// up again whenever the particles have been reordered (the periodic sort, a restart).
//
// A follower pressure's forces -p a_p then follow the step's deformation (follow(), eq N1 of
// solver/follower_area.hpp), after the step has used them: the force of step n is that of a_n.
#include "tsuchi/grid/block_schedule.hpp"
#include "tsuchi/model/loads.hpp"
#include "tsuchi/shape/stencil.hpp"
#include "tsuchi/solver/follower_area.hpp"

#include <algorithm>
#include <vector>

namespace tsuchi {

template <int D>
class LoadStage {
 public:
  // The factors f(t) of the step starting at t, and the loaded particles' storage indices.
  void begin_step(const Loads<D>& loads, const Particles<D>& p, std::size_t bodies, double t) {
    active_ = !loads.empty();
    follows_ = active_ && loads.any_follower();
    if (!active_) return;
    surface_f_.clear(), nodal_f_.clear();
    for (const auto& l : loads.surface) surface_f_.push_back(l.function(t));
    for (const auto& l : loads.nodal) nodal_f_.push_back(l.function(t));
    body_a_.assign(bodies, Vec<D>::Zero());
    body_force_ = false;
    for (const auto& l : loads.body) {
      const double f = l.function(t);
      for (std::size_t b = 0; b < bodies && b < l.acceleration.size(); ++b) body_a_[b] += f * l.acceleration[b];
    }
    for (const Vec<D>& a : body_a_) body_force_ = body_force_ || a != Vec<D>::Zero();
    if (!indices_valid(loads, p)) find_indices(loads, p);
  }

  // Into the nodal force of the particle's body field (field_of_body; all 0 without contact between
  // bodies). A nodal force is shared among the body fields first..last at its node in proportion to
  // their mass, as a body force acting on what is there.
  template <class Kernel>
  void apply(const Loads<D>& loads, const Grid<D>& g, const Particles<D>& p,
             const std::vector<typename Stencil<D, Kernel>::Axes>& stencils, const BlockSchedule<D>& schedule,
             double mass_floor, std::vector<NodalField<D>>& fields, const std::vector<int>& field_of_body, int first,
             int last) const {
    if (!active_) return;
    const auto f_of = [&](std::size_t i) {
      return fields[static_cast<std::size_t>(field_of_body[static_cast<std::size_t>(p.body_p[i])])].f.data();
    };
    if (body_force_) {
      schedule.scatter([&](std::size_t i) {
        const Vec<D>& a = body_a_[static_cast<std::size_t>(p.body_p[i])];
        if (a != Vec<D>::Zero()) spread<Kernel>(g, stencils[i], Vec<D>(p.m_p[i] * a), f_of(i));
      });
    }
    for (std::size_t l = 0; l < loads.surface.size(); ++l) {
      const auto& load = loads.surface[l];
      const double f = surface_f_[l];
      if (f == 0.0) continue;
      for (std::size_t e = 0; e < load.id.size(); ++e)
        spread<Kernel>(g, stencils[index_[l][e]], f * load.force[e], f_of(index_[l][e]));
    }
    for (std::size_t l = 0; l < loads.nodal.size(); ++l) {
      const auto& load = loads.nodal[l];
      for (std::size_t e = 0; e < load.node.size(); ++e) {
        const std::int64_t k = load.node[e];
        // An inactive tile's slots are stale (p2g clears a tile only when it becomes active).
        if (!schedule.on_active_tile(k)) continue;
        const auto s = static_cast<std::size_t>(k);
        double M = 0.0;
        for (int b = first; b <= last; ++b) M += fields[static_cast<std::size_t>(b)].m[s];
        if (!(M > mass_floor)) continue;
        for (int b = first; b <= last; ++b) {
          auto& n = fields[static_cast<std::size_t>(b)];
          if (n.m[s] > 0.0) n.f[s] += (n.m[s] / M) * (nodal_f_[l] * load.force[e]);
        }
      }
    }
  }

  // Whether some surface load of this step follows the deformation.
  bool follows() const { return follows_; }

  // Each follower pressure's force on each of its particles i through the step: -p a_p turned and
  // stretched by dF = I + dt L (eq N1), L = L_at(i) the velocity gradient at the particle. One
  // thread over the loaded particles only (each entry updated from its own particle's L, so the
  // order does not matter); nothing when no load follows.
  template <class Gradient>
  void follow(Loads<D>& loads, double dt, Gradient&& L_at) const {
    if (!follows_) return;
    for (std::size_t l = 0; l < loads.surface.size(); ++l) {
      auto& load = loads.surface[l];
      if (!load.follow) continue;
      for (std::size_t e = 0; e < load.id.size(); ++e)
        load.force[e] = follow_area<D>(load.force[e], L_at(index_[l][e]), dt);
    }
  }

 private:
  template <class Kernel>
  static void spread(const Grid<D>& g, const typename Stencil<D, Kernel>::Axes& axes, const Vec<D>& F, Vec<D>* f_g) {
    Stencil<D, Kernel> st;
    st.assemble(g, axes);
    st.scatter([&](double T, const std::array<double, D - 1>&) -> Vec<D> { return T * F; },
               [&](std::int64_t k, double w, double, const Vec<D>& TF) { f_g[k] += w * TF; });
  }

  bool indices_valid(const Loads<D>& loads, const Particles<D>& p) const {
    if (index_.size() != loads.surface.size()) return false;
    for (std::size_t l = 0; l < loads.surface.size(); ++l)
      for (std::size_t e = 0; e < loads.surface[l].id.size(); ++e) {
        const std::size_t i = index_[l][e];
        if (i >= p.size() || p.id_p[i] != loads.surface[l].id[e]) return false;
      }
    return true;
  }

  // One pass over the particles, each id looked up among the loaded ones (sorted).
  void find_indices(const Loads<D>& loads, const Particles<D>& p) {
    std::vector<std::int64_t> ids;
    for (const auto& l : loads.surface) ids.insert(ids.end(), l.id.begin(), l.id.end());
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    std::vector<std::size_t> where(ids.size(), p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      const auto it = std::lower_bound(ids.begin(), ids.end(), p.id_p[i]);
      if (it != ids.end() && *it == p.id_p[i]) where[static_cast<std::size_t>(it - ids.begin())] = i;
    }
    index_.assign(loads.surface.size(), {});
    for (std::size_t l = 0; l < loads.surface.size(); ++l)
      for (const std::int64_t id : loads.surface[l].id) {
        const std::size_t i = where[static_cast<std::size_t>(std::lower_bound(ids.begin(), ids.end(), id) - ids.begin())];
        if (i >= p.size()) throw std::logic_error("a loaded particle is missing from the particles");
        index_[l].push_back(i);
      }
  }

  bool active_ = false;
  bool follows_ = false;  // some surface load follows the deformation
  bool body_force_ = false;
  std::vector<double> surface_f_, nodal_f_;   // f(t) of each load this step
  std::vector<Vec<D>> body_a_;                // per body: sum of f(t) b / rho
  std::vector<std::vector<std::size_t>> index_;  // per surface load, per loaded particle: its storage index
};

}  // namespace tsuchi
