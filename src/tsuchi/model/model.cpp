#include "tsuchi/model/model.hpp"

#include "tsuchi/core/memory_limit.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/core/expression.hpp"
#include "tsuchi/model/imperfection.hpp"
#include "tsuchi/model/initial_stress.hpp"
#include "tsuchi/model/material_state.hpp"
#include "tsuchi/model/overburden.hpp"
#include "tsuchi/model/particle_fields.hpp"
#include "tsuchi/model/stage_change.hpp"
#include "tsuchi/grid/block_schedule.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

namespace tsuchi {

namespace {

GeostaticFrame geostatic_frame(const Config& c) {
  GeostaticFrame f;
  for (int d = 0; d < c.dimension; ++d)
    if (c.gravity[d] != 0.0) {
      f.up_axis = d;
      f.up_sign = c.gravity[d] < 0.0 ? 1.0 : -1.0;
      f.g = std::abs(c.gravity[d]);
    }
  return f;
}

template <int D>
geometry::Point point(const Vec<D>& x) {
  geometry::Point r = geometry::Point::Zero();
  for (int d = 0; d < D; ++d) r[d] = x[d];
  return r;
}

template <int D>
std::string coordinates(const Vec<D>& x) {
  std::string at;
  for (int d = 0; d < D; ++d) at += fmt::format("{}{:.6g}", d ? ", " : "", x[d]);
  return at;
}

// "FILE:LINE:COL: key 'bodies.N.KEY'": where messages about a body's geometry point.
std::string body_key(const Config& c, int body) {
  const BodyConfig& b = c.bodies[static_cast<std::size_t>(body)];
  return fmt::format("{}: key 'bodies.{}.{}'", b.shape_where.empty() ? c.source : b.shape_where, body, b.shape_key);
}

// Initial stress, values read from a particle file, imperfection factors, and a check that the
// start lies inside the yield surface: a state outside would be returned in the first step, a jolt
// the user did not ask for.
template <int D>
void set_initial_state(const Config& c, int body, std::size_t start, Model<D>& m) {
  const BodyConfig& b = c.bodies[body];
  auto& p = m.particles;
  const GeostaticFrame frame = geostatic_frame(c);
  const bool k0 = b.initial_stress.kind == InitialStressConfig::Kind::K0;
  // The overburden of what is in the model when each particle enters it: one for a body there
  // from the start or added whole, one per stage for a body added by parts (overburden.hpp).
  std::map<int, Overburden> overburden;
  const auto weight_above = [&](const geometry::Point& x) {
    const int k = entry_stage(c, body, x);
    auto it = overburden.find(k);
    if (it == overburden.end())
      it = overburden.emplace(k, Overburden(c, frame.up_axis, frame.up_sign, present_after(c, k))).first;
    return it->second.mass_above(x);
  };
  ImperfectionField field(b.imperfection);
  const bool imperfect = b.imperfection.amplitude > 0.0 && (b.imperfection.cohesion || b.imperfection.friction);
  // The imperfection scales the strength factors of the material's state (the input reader has
  // checked that its model has them).
  std::vector<double>* c_factor = imperfect ? p.state_column(std::string(field_name::cohesion_factor)) : nullptr;
  std::vector<double>* phi_factor = imperfect ? p.state_column(std::string(field_name::friction_factor)) : nullptr;
  for (std::size_t q = start; q < p.size(); ++q) {
    double sigma_v = 0.0;
    if (k0) {
      const double density = c.materials[static_cast<std::size_t>(p.material_p[q])].density;
      const geometry::Point x = point<D>(p.x_p[q]);
      sigma_v = b.initial_stress.surface
                    ? b.initial_stress.surface_stress -
                          density * frame.g * frame.up_sign * (*b.initial_stress.surface - x[frame.up_axis])
                    : column_surcharge(c, body, x) - frame.g * weight_above(x);
    }
    p.sigma_p[q] = initial_stress<D>(b.initial_stress, frame, sigma_v);
    if (imperfect) field.next((*c_factor)[q], (*phi_factor)[q]);
  }
  // Columns of a particle file: velocity components, stress components, material state.
  bool file_stress = false;
  if (b.particles) {
    const ParticleTable& t = *b.particles;
    for (std::size_t k = 0; k < t.columns.size(); ++k) {
      const auto q = find_recorder_quantity(t.columns[k], D);
      const ParticleField& f = *q->first;
      const int comp = q->second;
      std::vector<double>* column = f.quantity == Quantity::State ? p.state_column(f.name) : nullptr;
      file_stress = file_stress || f.quantity == Quantity::Stress;
      for (std::size_t i = 0; i < t.x.size(); ++i) {
        const std::size_t at = start + i;
        const double v = t.values[k][i];
        if (f.quantity == Quantity::Velocity) p.v_p[at][comp] = v;
        else if (f.quantity == Quantity::Stress) p.sigma_p[at][comp] = v;
        else if (column) (*column)[at] = v;
      }
    }
  }
  if (b.initial_stress.subtract)
    for (std::size_t q = start; q < p.size(); ++q) p.sigma0_p[q] = p.sigma_p[q];
  if (b.initial_stress.subtract && b.initial_stress.kind != InitialStressConfig::Kind::None) {
    const auto& t = b.initial_stress.tensor;
    const bool isotropic = b.initial_stress.kind == InitialStressConfig::Kind::Uniform && t[0] == t[1] &&
                           t[1] == t[2] && t[3] == 0.0 && t[4] == 0.0 && t[5] == 0.0 && !file_stress;
    m.rotate_initial_stress = m.rotate_initial_stress || !isotropic;
  }
  const bool check = b.initial_stress.kind != InitialStressConfig::Kind::None || file_stress;
  // Each particle against its own material (a region may give it another one than the body's):
  // the state that depends on the starting stress, then the check that the start is admissible.
  for (std::size_t k = 0; k < c.materials.size(); ++k) {
    const Material& mat = c.materials[k];
    std::visit(
        [&](const auto& model) {
          using M = std::decay_t<decltype(model)>;
          constexpr bool starts = requires(const Eigen::Vector3d& v, StateRef r) { model.start(v, r); };
          if (!starts && !check) return;
          const auto cols = state_columns<M>(p);
          for (std::size_t q = start; q < p.size(); ++q) {
            if (static_cast<std::size_t>(p.material_p[q]) != k) continue;
            const Eigen::Vector3d v = PrincipalFrame<D>(p.sigma_p[q]).values;
            start_state(model, v, StateRef{cols.data(), q});
            if (!check) continue;
            const Inadmissible beyond = model.outside(v, StateRef{cols.data(), q});
            if (!beyond.any()) continue;
            std::string hint;
            if constexpr (requires { M::k0_hint; })
              if (k0) hint = fmt::format("; {}", M::k0_hint);
            const bool from_table = b.initial_stress.kind != InitialStressConfig::Kind::None;
            const std::string key = from_table ? fmt::format("bodies.{}.initial_stress", body)
                                               : fmt::format("bodies.{}.particles", body);
            const std::string& at = from_table && !b.initial_stress.where.empty() ? b.initial_stress.where : c.source;
            throw InputError(fmt::format(
                "{}: key '{}': the initial stress of body \"{}\" lies outside the {} surface of material \"{}\" at "
                "({}): principal stresses {:.6g}, {:.6g}, {:.6g} Pa{}",
                at, key, b.name, beyond.surface, mat.name, coordinates<D>(p.x_p[q]), v[0], v[1], v[2], hint));
          }
        },
        mat.model);
  }
}

// The particle lattice of a body: spacing h / n per axis, aligned with the grid, over the bounds
// of its shape (clipped to the grid).
template <int D>
struct Lattice {
  Vec<D> spacing;
  Vec<D> lo, hi;  // the bounds it covers
  std::array<int, D> first{}, count{};
  double total = 1;  // a double: the product may not fit an integer (refused by the memory check)
  int empty_axis = -1;
};

template <int D>
Lattice<D> lattice(const BodyConfig& b, const Grid<D>& g) {
  Lattice<D> l;
  const geometry::Bounds bounds = b.shape->bounds();
  for (int d = 0; d < D; ++d) {
    l.spacing[d] = g.h / b.particles_per_cell[d];
    l.lo[d] = std::max(bounds.min[d], g.origin[d]);
    l.hi[d] = std::min(bounds.max[d], g.origin[d] + (g.n_nodes[d] - 1) * g.h);
    // Lattice points origin + (j + 1/2) spacing in [min, max) (a box aligned with the lattice
    // holds exactly its share; the 1e-9 keeps rounding from adding or losing a row).
    const double lo = (l.lo[d] - g.origin[d]) / l.spacing[d] - 0.5;
    const double hi = (l.hi[d] - g.origin[d]) / l.spacing[d] - 0.5;
    l.first[d] = static_cast<int>(std::ceil(lo - 1e-9));
    const int last = static_cast<int>(std::floor(hi - 1e-9));
    l.count[d] = std::max(0, last - l.first[d] + 1);
    l.total *= l.count[d];
    if (l.count[d] == 0 && l.empty_axis < 0) l.empty_axis = d;
  }
  return l;
}

// Whether a shaped body would place a particle at x: inside the half-open bounds of its lattice
// ([min, max) per axis, so that boxes touching along a face do not both claim a point on it) and
// inside its shape.
template <int D>
bool claims(const BodyConfig& b, const Lattice<D>& l, const Vec<D>& x) {
  for (int d = 0; d < D; ++d)
    if (x[d] < l.lo[d] || x[d] >= l.hi[d]) return false;
  return b.shape->contains(point<D>(x));
}

// Refuses, before anything is allocated, a model whose memory estimate exceeds what the machine
// has free: a bad_alloc hours into a set-up, or the OOM killer, says nothing about the cause. The
// particles are counted on the lattice over each shape's bounds: an upper bound.
template <int D>
void check_memory(const Config& c, const Grid<D>& g, const Particles<D>& layout) {
  double particles = 0.0;
  for (const auto& b : c.bodies)
    particles += b.shape ? lattice<D>(b, g).total : static_cast<double>(b.particles->x.size());
  double bytes = memory_estimate<D>(static_cast<double>(g.size()), particles, layout, g.keep_acceleration);
  // Contact between bodies adds a velocity field per body of a frictional or rough pair (at most,
  // plus one shared), each with its mass gradient and node-averaged volumetric strain.
  std::vector<int> in_pairs;
  for (const auto& k : c.contacts)
    if (k.law != ContactConfig::Law::Bonded) in_pairs.insert(in_pairs.end(), {k.body_a, k.body_b});
  std::sort(in_pairs.begin(), in_pairs.end());
  in_pairs.erase(std::unique(in_pairs.begin(), in_pairs.end()), in_pairs.end());
  if (!in_pairs.empty()) {
    const double per_field = static_cast<double>(NodalField<D>::bytes_per_slot(g.keep_acceleration) + sizeof(Vec<D>) + 2 * sizeof(double) + 1);
    bytes += 1.25 * static_cast<double>(in_pairs.size() + 1) * per_field * static_cast<double>(g.size());
  }
  const MemoryLimit limit = memory_limit();
  if (limit.bytes > 0.0 && bytes > limit.bytes)
    throw InputError(fmt::format(
        "{}: the model needs about {:.3g} GB ({:.4g} particles, {:.4g} grid nodes), more than the {:.3g} GB {}; "
        "choose a larger grid.cell_size or fewer bodies.N.particles_per_cell, or raise the limit",
        c.source, bytes / 1e9, particles, static_cast<double>(g.node_count()), limit.bytes / 1e9, limit.what));
}

// Where a body's particles go, before any is stored: the lattice points inside its shape less
// those that a body of higher priority claims (model/model.hpp, docs/input.md "Overlaps"), or the
// rows of its particle file.
template <int D>
struct Placement {
  std::vector<Vec<D>> x;
  std::vector<Vec<D>> half;    // GIMP half-widths
  std::vector<double> volume;
};

template <int D>
std::vector<Placement<D>> place_bodies(const Config& c, const Grid<D>& g) {
  const std::size_t n = c.bodies.size();
  std::vector<Lattice<D>> lat(n);
  for (std::size_t b = 0; b < n; ++b)
    if (c.bodies[b].shape) lat[b] = lattice<D>(c.bodies[b], g);
  // Which other bodies' bounds meet body b's: the only ones that can claim its points.
  auto meet = [&](std::size_t a, std::size_t b) {
    for (int d = 0; d < D; ++d)
      if (lat[a].hi[d] <= lat[b].lo[d] || lat[b].hi[d] <= lat[a].lo[d]) return false;
    return true;
  };
  std::vector<Placement<D>> out(n);
  for (std::size_t b = 0; b < n; ++b) {
    const BodyConfig& bc = c.bodies[b];
    Placement<D>& pl = out[b];
    if (!bc.shape) {
      const ParticleTable& t = *bc.particles;
      for (std::size_t i = 0; i < t.x.size(); ++i) {
        Vec<D> x;
        for (int d = 0; d < D; ++d) x[d] = t.x[i][static_cast<std::size_t>(d)];
        pl.x.push_back(x);
        // A cube of the particle's volume: l_p = V^(1/D) / 2 per axis.
        pl.half.push_back(Vec<D>::Constant(0.5 * std::pow(t.volume[i], 1.0 / D)));
        pl.volume.push_back(t.volume[i]);
      }
      continue;
    }
    const Lattice<D>& l = lat[b];
    if (l.total == 0) {
      constexpr const char* axis[3] = {"x", "y", "z"};
      const int d = l.empty_axis;
      throw InputError(fmt::format(
          "{}: body \"{}\" holds no particle: along {} no particle position (grid.origin + "
          "(j + 1/2) * {:.6g} m, the spacing cell_size / particles_per_cell) lies in [{:.6g}, {:.6g}); expected a "
          "{} at least one particle spacing thick",
          body_key(c, static_cast<int>(b)), bc.name, axis[d], l.spacing[d], l.lo[d], l.hi[d],
          bc.shape_kind == "box" ? "box" : "shape"));
    }
    std::vector<std::size_t> rivals;
    for (std::size_t o = 0; o < n; ++o)
      if (o != b && c.bodies[o].shape && meet(b, o)) rivals.push_back(o);
    double volume = 1.0;
    for (int d = 0; d < D; ++d) volume *= l.spacing[d];
    const auto total = static_cast<std::size_t>(l.total);
    std::size_t inside = 0;
    int lost_to = -1;
    std::array<int, D> j{};
    for (std::size_t k = 0; k < total; ++k) {
      std::size_t rest = k;
      for (int d = 0; d < D; ++d) {
        j[d] = l.first[d] + static_cast<int>(rest % static_cast<std::size_t>(l.count[d]));
        rest /= static_cast<std::size_t>(l.count[d]);
      }
      Vec<D> x;
      for (int d = 0; d < D; ++d) x[d] = g.origin[d] + (j[d] + 0.5) * l.spacing[d];
      if (!bc.shape->contains(point<D>(x))) continue;
      ++inside;
      bool keep = true;
      for (const std::size_t o : rivals) {
        const BodyConfig& oc = c.bodies[o];
        if (!claims<D>(oc, lat[o], x)) continue;
        if (oc.priority == bc.priority) {
          // Reported at the later of the two bodies, as the input is read.
          const std::size_t later = std::max(b, o), earlier = std::min(b, o);
          throw InputError(fmt::format(
              "{}: body \"{}\" overlaps body \"{}\" at ({}); expected bodies that share no particle, or a different "
              "'priority' (the higher keeps the particles where they overlap)",
              body_key(c, static_cast<int>(later)), c.bodies[later].name, c.bodies[earlier].name, coordinates<D>(x)));
        }
        if (oc.priority > bc.priority) {
          keep = false;
          lost_to = static_cast<int>(o);
          break;
        }
      }
      if (!keep) continue;
      pl.x.push_back(x);
      pl.half.push_back(0.5 * l.spacing);
      pl.volume.push_back(volume);
    }
    if (pl.x.empty())
      throw InputError(fmt::format(
          "{}: body \"{}\" holds no particle: {}; expected a shape that holds at least one particle position (grid.origin + "
          "(j + 1/2) * cell_size / particles_per_cell along each axis)",
          body_key(c, static_cast<int>(b)), bc.name,
          inside == 0 ? "no particle position lies inside its shape"
                      : fmt::format("every one of its {} particle positions lies in body \"{}\" of higher priority", inside,
                                    c.bodies[static_cast<std::size_t>(lost_to)].name)));
  }
  return out;
}

// Stores a body's particles: each stands for its lattice share of the cell (the paper's
// "requirement 1") or its row of the particle file; its material is the body's, or that of the
// last of the body's regions holding it.
template <int D>
void add_body(const Config& c, int body, const Placement<D>& pl, Model<D>& m) {
  const BodyConfig& b = c.bodies[body];
  const std::size_t total = pl.x.size();
  auto& p = m.particles;
  const std::size_t start = p.size();
  p.resize(start + total);
  Vec<D> v0;
  for (int d = 0; d < D; ++d) v0[d] = b.velocity[d];
  for (std::size_t n = 0; n < total; ++n) {
    const std::size_t k = start + n;
    p.x_p[k] = pl.x[n];
    p.l_p[k] = pl.half[n];
    p.v_p[k] = v0;
    p.V_p[k] = pl.volume[n];
    int material = b.material_index;
    if (!b.regions.empty()) {
      const geometry::Point x = point<D>(pl.x[n]);
      for (const auto& r : b.regions)
        if (r.shape->contains(x)) material = r.material_index;
    }
    p.m_p[k] = c.materials[static_cast<std::size_t>(material)].density * pl.volume[n];
    p.material_p[k] = material;
    p.body_p[k] = body;
    p.id_p[k] = static_cast<std::int64_t>(k);
  }
  for (int d = 0; d < D; ++d) {
    if (b.velocity_formula[d].empty()) continue;
    const Expression f(b.velocity_formula[d]);
    for (std::size_t q = start; q < p.size(); ++q) {
      const auto& x = p.x_p[q];
      p.v_p[q][d] = f(x[0], x[1], D == 3 ? x[D - 1] : 0.0);
      if (!std::isfinite(p.v_p[q][d]))
        throw InputError(fmt::format(
            "{}: key 'bodies.{}.velocity': expected a finite velocity, got {} from its {} component (entry {}) \"{}\" at "
            "particle {} ({}{})",
            b.velocity_where.empty() ? c.source : b.velocity_where, body, p.v_p[q][d], "xyz"[d], d, b.velocity_formula[d], q,
            fmt::format("{}, {}", x[0], x[1]), D == 3 ? fmt::format(", {}", x[D - 1]) : std::string{}));
    }
  }
  m.body_particles.push_back(total);
  double volume = 0.0;
  for (const double v : pl.volume) volume += v;
  m.body_volume.push_back(volume);
  set_initial_state(c, body, start, m);

  const BodyMotion<D> motion = body_motion<D>(c, body);
  // A prescribed component starts at its prescribed value (with APIC, and its gradient), at t = 0.
  const bool apic = c.solver.velocity_transfer == VelocityTransfer::Apic;
  const double f0 = motion.function(0.0);
  for (std::size_t q = start; q < p.size(); ++q)
    for (int d = 0; d < D; ++d)
      if (motion.prescribed[d]) {
        p.v_p[q][d] = f0 * motion.velocity(d, p.x_p[q]);
        if (apic) p.C_p[q].row(d) = f0 * motion.grad.row(d);
      }
  m.motion.push_back(motion);
}

}  // namespace

template <int D>
BodyMotion<D> body_motion(const Config& c, int body) {
  const BodyConfig& b = c.bodies[static_cast<std::size_t>(body)];
  BodyMotion<D> motion;
  for (int d = 0; d < D; ++d) {
    motion.prescribed[d] = b.prescribed[d];
    motion.any = motion.any || b.prescribed[d];
    motion.v0[d] = b.prescribed_velocity[d];
    for (int e = 0; e < D; ++e) motion.grad(d, e) = b.prescribed_gradient[d][e];
  }
  if (b.rigid_mass > 0.0) {
    // The free components are held too, at the body's own velocity, which the solver updates.
    motion.rigid_mass = b.rigid_mass;
    for (int d = 0; d < D; ++d)
      if (!motion.prescribed[d]) {
        motion.free[d] = motion.prescribed[d] = motion.any = true;
        motion.v0[d] = b.velocity[d];
      }
  }
  if (b.prescribed_velocity_function >= 0)
    motion.function = c.functions[static_cast<std::size_t>(b.prescribed_velocity_function)].f;
  return motion;
}

template <int D>
Model<D> build_model(const Config& c) {
  if (c.dimension != D)
    throw InputError(fmt::format("{}: model.dimension is {}, but a {}D model was asked for", c.source,
                                 c.dimension, D));
  Model<D> m;
  m.source = c.source;
  m.fingerprint = c.fingerprint;
  m.materials = c.materials;
  for (const auto& b : c.bodies) m.body_names.push_back(b.name);
  m.step.set_from(c);
  if (c.gravity_function >= 0) m.step.gravity_function = c.functions[static_cast<std::size_t>(c.gravity_function)].f;
  declare_state_columns(m.particles, c.materials);
  m.particles.affine = c.solver.velocity_transfer == VelocityTransfer::Apic;
  m.particles.initial_stress =
      std::any_of(c.bodies.begin(), c.bodies.end(), [](const BodyConfig& b) { return b.initial_stress.subtract; });
  for (int d = 0; d < D; ++d) {
    m.grid.origin[d] = c.grid.origin[d];
    m.grid.n_nodes[d] = c.grid.cells[d] + 1;
  }
  m.grid.h = c.grid.cell_size;
  m.grid.keep_acceleration = c.solver.velocity_transfer == VelocityTransfer::Flip;
  // A model whose strength depends on the cell size (material.hpp, with_cell_size) is set for it.
  for (Material& mat : m.materials)
    std::visit([&](auto& model) {
      if constexpr (requires { model.with_cell_size(1.0); }) model = model.with_cell_size(m.grid.h);
    }, mat.model);
  const double nodes = [&] {
    double n = 1;
    for (int d = 0; d < D; ++d) n *= m.grid.n_nodes[d];
    return n;
  }();
  if (nodes > 2e9)
    throw InputError(fmt::format("{}: the grid has {:.3g} nodes; at most 2e9 are supported", c.source, nodes));
  check_memory<D>(c, m.grid, m.particles);
  m.grid.allocate();
  set_boundary_conditions(c, m.grid, m.node_sets, m.held_nodes);
  const std::vector<Placement<D>> placed = place_bodies<D>(c, m.grid);
  for (int b = 0; b < static_cast<int>(c.bodies.size()); ++b) add_body<D>(c, b, placed[static_cast<std::size_t>(b)], m);

  // Store the particles in the order the block scatter visits them: neighbours in space are then
  // neighbours in memory, which every stage of the step gains from.
  BlockSchedule<D> blocks;
  blocks.build(m.grid, m.particles.x_p);
  m.particles.permute(blocks.order());
  const auto& mp = m.particles.m_p;
  m.step.node_mass_floor = c.solver.mass_threshold * *std::min_element(mp.begin(), mp.end());
  m.id_count = static_cast<std::int64_t>(m.particles.size());
  m.staged = c.staged();
  m.stage_count = c.stages.size();
  // Bodies that a stage adds wait outside the step (model/stage_change.hpp).
  if (std::find(c.body_starts_dormant.begin(), c.body_starts_dormant.end(), true) != c.body_starts_dormant.end()) {
    std::vector<std::int32_t> dormant_bodies;
    for (std::size_t b = 0; b < c.body_starts_dormant.size(); ++b)
      if (c.body_starts_dormant[b]) dormant_bodies.push_back(static_cast<std::int32_t>(b));
    move_bodies(m.particles, m.dormant, dormant_bodies);
  }
  m.loads = build_loads<D>(c, m.particles, m.grid);
  m.contact = build_contact<D>(c, m);
  return m;
}

template BodyMotion<2> body_motion<2>(const Config&, int);
template BodyMotion<3> body_motion<3>(const Config&, int);
template Model<2> build_model<2>(const Config&);
template Model<3> build_model<3>(const Config&);

}  // namespace tsuchi
