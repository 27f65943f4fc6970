#include "tsuchi/model/stage_change.hpp"

#include "tsuchi/core/principal_frame.hpp"
#include "tsuchi/model/material_state.hpp"
#include "tsuchi/core/errors.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <string_view>
#include <type_traits>

namespace tsuchi {

namespace {

// Moves the particles i of `from` with chosen(i) to the end of `to` (its state columns declared like
// `from`'s when it has none), keeping the order of both; returns how many moved.
template <int D, class Chosen>
std::size_t move_particles(Particles<D>& from, Particles<D>& to, Chosen chosen) {
  if (to.size() == 0 && to.state_name.empty()) to.same_arrays_as(from);
  std::vector<std::size_t> keep, move;
  for (std::size_t i = 0; i < from.size(); ++i) (chosen(i) ? move : keep).push_back(i);
  if (move.empty()) return 0;
  const std::size_t base = to.size();
  to.resize(base + move.size());
  // Each array of `from` with its namesake in `to` (the same list, for_each_array).
  from.for_each_array([&](const char* name, auto& a) {
    using A = std::decay_t<decltype(a)>;
    to.for_each_array([&](const char* other, auto& b) {
      if constexpr (std::is_same_v<A, std::decay_t<decltype(b)>>) {
        if (std::strcmp(name, other) != 0) return;
        for (std::size_t k = 0; k < move.size(); ++k) b[base + k] = a[move[k]];
        for (std::size_t k = 0; k < keep.size(); ++k) a[k] = a[keep[k]];  // keep[k] >= k: in place
        a.resize(keep.size());
      }
    });
  });
  return move.size();
}

geometry::Point point_of(const Vec<2>& x) { return {x[0], x[1], 0.0}; }
geometry::Point point_of(const Vec<3>& x) { return {x[0], x[1], x[2]}; }

// Whether a region of `bodies` takes body b's particles: a region that names no body cuts every
// deformable body (a free rigid body is removed whole or not at all).
bool names(const Config& run, const std::vector<int>& bodies, int b) {
  if (bodies.empty()) return run.bodies[static_cast<std::size_t>(b)].rigid_mass <= 0.0;
  return std::find(bodies.begin(), bodies.end(), b) != bodies.end();
}

// The particles of a stage region: those of its bodies whose centre it holds. A region that holds
// none is an input error (a cut drawn beside the ground, a lift above the fill's shape).
template <int D>
void move_region(Particles<D>& from, Particles<D>& to, const StageRegionConfig& r, const Config& run,
                 const StageConfig& st, const char* key) {
  const std::size_t moved = move_particles(from, to, [&](std::size_t i) {
    return names(run, r.bodies, from.body_p[i]) && r.shape->contains(point_of(from.x_p[i]));
  });
  if (moved > 0) return;
  std::string which;
  for (const int b : r.bodies) which += fmt::format("{}\"{}\"", which.empty() ? "" : ", ", run.bodies[static_cast<std::size_t>(b)].name);
  const bool adding = std::string_view(key) == "add";
  const std::string whose = which.empty() ? std::string("of any body there")
                                          : fmt::format("{} body {}", adding ? "waiting in" : "of", which);
  throw InputError(fmt::format("{}: key '{}': the {} region holds no particle {} at the start of stage \"{}\"; "
                               "expected a shape over the particles it {}",
                               r.where, r.key_path, r.kind, whose, st.name, adding ? "adds" : "removes"));
}

}  // namespace

template <int D>
void move_bodies(Particles<D>& from, Particles<D>& to, const std::vector<std::int32_t>& bodies) {
  move_particles(from, to, [&](std::size_t i) {
    return std::find(bodies.begin(), bodies.end(), from.body_p[i]) != bodies.end();
  });
}

template <int D>
void change_particles(Model<D>& m, const Config& run, std::size_t k) {
  const StageConfig& st = run.stages[k];
  if (!st.remove.empty() || !st.remove_regions.empty()) {
    Particles<D> gone;
    for (const auto& r : st.remove_regions) move_region(m.particles, gone, r, run, st, "remove");
    move_bodies(m.particles, gone, st.remove);
    if (m.particles.size() == 0)
      throw InputError(fmt::format("{}: key 'stages.{}.remove': stage \"{}\" removes every particle there is: it "
                                   "would run on an empty model; expected at least one particle left",
                                   st.where, k, st.name));
    // A surface load keeps the particles that are still there; the new faces are free.
    std::vector<std::uint8_t> present(static_cast<std::size_t>(m.id_count), 0);
    for (const std::int64_t id : m.particles.id_p) present[static_cast<std::size_t>(id)] = 1;
    for (auto& load : m.loads.surface) {
      std::size_t kept = 0;
      for (std::size_t e = 0; e < load.id.size(); ++e)
        if (present[static_cast<std::size_t>(load.id[e])]) load.id[kept] = load.id[e], load.force[kept++] = load.force[e];
      load.id.resize(kept), load.force.resize(kept);
    }
  }
  if (!st.add.empty()) move_bodies(m.dormant, m.particles, st.add);
  for (const auto& r : st.add_regions) move_region(m.dormant, m.particles, r, run, st, "add");
  if (st.reset_displacements) {
    std::fill(m.particles.u_p.begin(), m.particles.u_p.end(), Vec<D>::Zero());
    std::fill(m.particles.eps_p.begin(), m.particles.eps_p.end(), Voigt<D>::Zero());
  }
}

namespace {

// Particles (active and dormant) of material `from` that a stage gives another material, or whose
// material the stage changes: masses follow a new density; a new model's state starts at the
// particle's stress (its start hook, material.hpp), as at the start of a run.
template <int D>
void restate(Particles<D>& p, int material, const Material& before, const Material& after, int only_body = -1) {
  const auto chosen = [&](std::size_t q) {
    return p.material_p[q] == material && (only_body < 0 || p.body_p[q] == only_body);
  };
  const double scale = after.density / before.density;
  for (std::size_t q = 0; q < p.size(); ++q)
    if (chosen(q)) p.m_p[q] *= scale;
  if (after.model.index() == before.model.index()) return;
  std::visit(
      [&](const auto& model) {
        using M = std::decay_t<decltype(model)>;
        const auto cols = state_columns<M>(p);
        for (std::size_t q = 0; q < p.size(); ++q)
          if (chosen(q)) start_state(model, PrincipalFrame<D>(p.sigma_p[q]).values, StateRef{cols.data(), q});
      },
      after.model);
}

}  // namespace

template <int D>
void reconfigure(Model<D>& m, const Config& run, std::size_t k, double t0) {
  const StageConfig& st = run.stages[k];
  const Config& c = *st.config;
  const Config& before = k > 0 ? *run.stages[k - 1].config : c;
  if (st.changes_materials) {
    for (std::size_t j = 0; j < c.materials.size(); ++j) {
      Material mat = c.materials[j];
      std::visit([&](auto& model) {
        if constexpr (requires { model.with_cell_size(1.0); }) model = model.with_cell_size(m.grid.h);
      }, mat.model);
      const auto index = static_cast<int>(j);
      restate(m.particles, index, m.materials[j], mat);
      restate(m.dormant, index, m.materials[j], mat);
      m.materials[j] = mat;
    }
  }
  // A body given another material: its particles of the old one (not those of its regions).
  for (const int b : st.changes_body_material) {
    const auto ub = static_cast<std::size_t>(b);
    const int from = before.bodies[ub].material_index, to = c.bodies[ub].material_index;
    if (from == to) continue;
    for (Particles<D>* p : {&m.particles, &m.dormant}) {
      restate(*p, from, m.materials[static_cast<std::size_t>(from)], m.materials[static_cast<std::size_t>(to)], b);
      for (std::size_t q = 0; q < p->size(); ++q)
        if (p->body_p[q] == b && p->material_p[q] == from) p->material_p[q] = to;
    }
  }
  // The step's settings: cheap, so always from the stage's input.
  m.step.set_from(c);
  if (c.solver.mass_threshold != before.solver.mass_threshold) {
    double lightest = std::numeric_limits<double>::infinity();
    for (const Particles<D>* p : {&m.particles, &m.dormant})
      for (const double mass : p->m_p) lightest = std::min(lightest, mass);
    m.step.node_mass_floor = c.solver.mass_threshold * lightest;
  }
  if (st.sets_gravity_function)
    m.step.gravity_function = c.gravity_function >= 0
                                  ? c.functions[static_cast<std::size_t>(c.gravity_function)].f.starting_at(t0)
                                  : TimeFunction{};
  if (st.changes_boundary) {
    // Node sets the stage does not give keep their clocks.
    std::vector<double> starts;
    for (const auto& set : m.node_sets) starts.push_back(set.f.start());
    set_boundary_conditions(c, m.grid, m.node_sets, m.held_nodes);
    for (std::size_t k2 = 0; k2 < m.node_sets.size(); ++k2)
      m.node_sets[k2].f = m.node_sets[k2].f.starting_at(st.sets_node_sets ? t0 : starts[k2]);
  }
  for (const int b : st.changes_motion) {
    BodyMotion<D> motion = body_motion<D>(c, b);
    motion.function = motion.function.starting_at(t0);
    m.motion[static_cast<std::size_t>(b)] = motion;
  }
  // The pairs as the stage gives them; frictional walls and rigid bodies follow the boundary and the
  // motions. The step's velocity fields follow (a new ExplicitSolver for each stage; ContactStage
  // adds grid fields as a stage needs more).
  if (st.changes_boundary || !st.changes_motion.empty() || st.changes_contact) m.contact = build_contact<D>(c, m);
  if (st.changes_loads) {
    m.loads = build_loads<D>(c, m.particles, m.grid);
    for (auto& l : m.loads.surface) l.function = l.function.starting_at(t0);
    for (auto& l : m.loads.nodal) l.function = l.function.starting_at(t0);
    for (auto& l : m.loads.body) l.function = l.function.starting_at(t0);
  }
}

template <int D>
void restore_stage(Model<D>& m, const Config& run, std::size_t k, const std::vector<double>& starts) {
  for (std::size_t j = 1; j <= k; ++j) {
    begin_stage(m, run, j, starts[j]);
  }
}

template <int D>
void check_stages(const Model<D>& m, const Config& run) {
  if (run.stages.size() < 2) return;
  Model<D> copy = m;
  for (std::size_t k = 1; k < run.stages.size(); ++k) {
    try {
      begin_stage(copy, run, k, 0.0);
    } catch (const InputError& e) {
      throw InputError(fmt::format("stage {} \"{}\": {}", k + 1, run.stages[k].name, e.what()));
    }
  }
}

template <int D>
bool contact_in_some_stage(const Model<D>& m, const Config& run) {
  if (m.contact.active()) return true;
  for (std::size_t k = 1; k < run.stages.size(); ++k)
    if (build_contact<D>(*run.stages[k].config, m).active()) return true;
  return false;
}

template bool contact_in_some_stage<2>(const Model<2>&, const Config&);
template bool contact_in_some_stage<3>(const Model<3>&, const Config&);
template void check_stages<2>(const Model<2>&, const Config&);
template void check_stages<3>(const Model<3>&, const Config&);
template void move_bodies<2>(Particles<2>&, Particles<2>&, const std::vector<std::int32_t>&);
template void move_bodies<3>(Particles<3>&, Particles<3>&, const std::vector<std::int32_t>&);
template void change_particles<2>(Model<2>&, const Config&, std::size_t);
template void change_particles<3>(Model<3>&, const Config&, std::size_t);
template void reconfigure<2>(Model<2>&, const Config&, std::size_t, double);
template void reconfigure<3>(Model<3>&, const Config&, std::size_t, double);
template void restore_stage<2>(Model<2>&, const Config&, std::size_t, const std::vector<double>&);
template void restore_stage<3>(Model<3>&, const Config&, std::size_t, const std::vector<double>&);

}  // namespace tsuchi
