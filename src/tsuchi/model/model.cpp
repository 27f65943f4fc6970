#include "tsuchi/model/model.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/core/expression.hpp"
#include "tsuchi/model/imperfection.hpp"
#include "tsuchi/model/initial_stress.hpp"
#include "tsuchi/model/material_state.hpp"
#include "tsuchi/grid/block_schedule.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace tsuchi {

namespace {

GeostaticFrame geostatic_frame(const Config& c, const BodyConfig& b) {
  GeostaticFrame f;
  for (int d = 0; d < c.dimension; ++d)
    if (c.gravity[d] != 0.0) {
      f.up_axis = d;
      f.up_sign = c.gravity[d] < 0.0 ? 1.0 : -1.0;
      f.g = std::abs(c.gravity[d]);
    }
  const double top = f.up_sign > 0 ? b.max[f.up_axis] : b.min[f.up_axis];
  f.surface = b.initial_stress.surface.value_or(top);
  return f;
}

// Initial stress, imperfection factors, and a check that the start lies inside the yield surface:
// a state outside would be returned in the first step, a jolt the user did not ask for.
template <int D>
void set_initial_state(const Config& c, int body, std::size_t start, Model<D>& m) {
  const BodyConfig& b = c.bodies[body];
  const Material& mat = c.materials[b.material_index];
  auto& p = m.particles;
  const GeostaticFrame frame = geostatic_frame(c, b);
  ImperfectionField field(b.imperfection);
  const bool imperfect = b.imperfection.amplitude > 0.0 && (b.imperfection.cohesion || b.imperfection.friction);
  // The imperfection scales the strength factors of the material's state (the input reader has
  // checked that its model has them).
  std::vector<double>* c_factor = imperfect ? p.state_column(std::string(field_name::cohesion_factor)) : nullptr;
  std::vector<double>* phi_factor = imperfect ? p.state_column(std::string(field_name::friction_factor)) : nullptr;
  for (std::size_t q = start; q < p.size(); ++q) {
    p.sigma_p[q] = initial_stress<D>(b.initial_stress, frame, mat.density, p.x_p[q]);
    if (b.initial_stress.subtract) p.sigma0_p[q] = p.sigma_p[q];
    if (imperfect) field.next((*c_factor)[q], (*phi_factor)[q]);
  }
  if (b.initial_stress.subtract && b.initial_stress.kind != InitialStressConfig::Kind::None) {
    const auto& t = b.initial_stress.tensor;
    const bool isotropic = b.initial_stress.kind == InitialStressConfig::Kind::Uniform && t[0] == t[1] &&
                           t[1] == t[2] && t[3] == 0.0 && t[4] == 0.0 && t[5] == 0.0;
    m.rotate_initial_stress = m.rotate_initial_stress || !isotropic;
  }
  if (b.initial_stress.kind == InitialStressConfig::Kind::None) return;
  std::visit(
      [&](const auto& model) {
        using M = std::decay_t<decltype(model)>;
        const auto cols = state_columns<M>(p);
        for (std::size_t q = start; q < p.size(); ++q) {
          const Eigen::Vector3d v = PrincipalFrame<D>(p.sigma_p[q]).values;
          const Inadmissible beyond = model.outside(v, StateRef{cols.data(), q});
          if (!beyond.any()) continue;
          std::string at;
          for (int d = 0; d < D; ++d) at += fmt::format("{}{:.6g}", d ? ", " : "", p.x_p[q][d]);
          std::string hint;
          if constexpr (requires { M::k0_hint; })
            if (b.initial_stress.kind == InitialStressConfig::Kind::K0) hint = fmt::format("; {}", M::k0_hint);
          throw InputError(fmt::format(
              "{}: key 'bodies.{}.initial_stress': the initial stress of body \"{}\" lies outside the {} "
              "surface of material \"{}\" at ({}): principal stresses {:.6g}, {:.6g}, {:.6g} Pa{}",
              c.source, body, b.name, beyond.surface, mat.name, at, v[0], v[1], v[2], hint));
        }
      },
      mat.model);
}

// The particle lattice of a body: spacing h / n per axis, aligned with the grid.
template <int D>
struct Lattice {
  Vec<D> spacing;
  std::array<int, D> first{}, count{};
  double total = 1;  // a double: the product may not fit an integer (refused by the memory check)
  int empty_axis = -1;
};

template <int D>
Lattice<D> lattice(const BodyConfig& b, const Grid<D>& g) {
  Lattice<D> l;
  for (int d = 0; d < D; ++d) {
    l.spacing[d] = g.h / b.particles_per_cell[d];
    // Lattice points origin + (j + 1/2) spacing in [min, max) (a box aligned with the lattice
    // holds exactly its share; the 1e-9 keeps rounding from adding or losing a row).
    const double lo = (b.min[d] - g.origin[d]) / l.spacing[d] - 0.5;
    const double hi = (b.max[d] - g.origin[d]) / l.spacing[d] - 0.5;
    l.first[d] = static_cast<int>(std::ceil(lo - 1e-9));
    const int last = static_cast<int>(std::floor(hi - 1e-9));
    l.count[d] = std::max(0, last - l.first[d] + 1);
    l.total *= l.count[d];
    if (l.count[d] == 0 && l.empty_axis < 0) l.empty_axis = d;
  }
  return l;
}

// Bytes free for this run: MemAvailable, or the cgroup's limit when lower; 0 when unknown.
double available_memory() {
  double avail = 0.0;
  if (std::FILE* f = std::fopen("/proc/meminfo", "r")) {
    char line[256];
    while (std::fgets(line, sizeof line, f))
      if (std::sscanf(line, "MemAvailable: %lf kB", &avail) == 1) {
        avail *= 1024.0;
        break;
      }
    std::fclose(f);
  }
  if (std::FILE* f = std::fopen("/sys/fs/cgroup/memory.max", "r")) {
    double limit = 0.0;
    if (std::fscanf(f, "%lf", &limit) == 1 && limit > 0.0 && (avail == 0.0 || limit < avail)) avail = limit;
    std::fclose(f);
  }
  return avail;
}

// Refuses, before anything is allocated, a model whose memory estimate exceeds what the machine
// has free: a bad_alloc hours into a set-up, or the OOM killer, says nothing about the cause.
template <int D>
void check_memory(const Config& c, const Grid<D>& g) {
  double particles = 0.0;
  for (const auto& b : c.bodies) particles += lattice<D>(b, g).total;
  const bool affine = c.solver.velocity_transfer == VelocityTransfer::Apic;
  const double bytes = memory_estimate<D>(static_cast<double>(g.size()), particles, affine);
  const double avail = available_memory();
  if (avail > 0.0 && bytes > avail)
    throw InputError(fmt::format(
        "{}: the model needs about {:.3g} GB ({:.4g} particles, {:.4g} grid nodes), more than the {:.3g} GB of "
        "memory available; choose a larger grid.cell_size or fewer bodies.N.particles_per_cell",
        c.source, bytes / 1e9, particles, static_cast<double>(g.node_count()), avail / 1e9));
}

// Fills a box with particles on the lattice of spacing h / n per axis, aligned with the grid, so
// that each particle stands for an equal share of the cell (the paper's "requirement 1").
template <int D>
void add_body(const Config& c, int body, Model<D>& m) {
  const BodyConfig& b = c.bodies[body];
  const Material& mat = c.materials[b.material_index];
  const Lattice<D> l = lattice<D>(b, m.grid);
  const Vec<D>& spacing = l.spacing;
  const auto& first = l.first;
  const auto& count = l.count;
  const auto total = static_cast<std::size_t>(l.total);
  const int empty_axis = l.empty_axis;
  if (total == 0) {
    constexpr const char* axis[3] = {"x", "y", "z"};
    const int d = empty_axis;
    throw InputError(fmt::format(
        "{}: key 'bodies.{}': body \"{}\" holds no particle: along {} no particle position (grid.origin + "
        "(j + 1/2) * {:.6g} m, the spacing cell_size / particles_per_cell) lies in [{:.6g}, {:.6g}); expected a "
        "box at least one particle spacing thick",
        c.source, body, b.name, axis[d], spacing[d], b.min[d], b.max[d]));
  }
  double volume = 1.0;
  for (int d = 0; d < D; ++d) volume *= spacing[d];

  auto& p = m.particles;
  const std::size_t start = p.size();
  p.resize(start + total);
  Vec<D> v0;
  for (int d = 0; d < D; ++d) v0[d] = b.velocity[d];
  std::size_t k = start;
  std::array<int, D> j{};
  for (std::size_t n = 0; n < total; ++n, ++k) {
    std::size_t rest = n;
    for (int d = 0; d < D; ++d) {
      j[d] = first[d] + static_cast<int>(rest % static_cast<std::size_t>(count[d]));
      rest /= static_cast<std::size_t>(count[d]);
    }
    for (int d = 0; d < D; ++d) p.x_p[k][d] = m.grid.origin[d] + (j[d] + 0.5) * spacing[d];
    p.l_p[k] = 0.5 * spacing;
    p.v_p[k] = v0;
    p.V_p[k] = volume;
    p.m_p[k] = mat.density * volume;
    p.material_p[k] = b.material_index;
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
            "{}: key 'bodies.{}.velocity': expected a finite velocity, got {} from entry {} \"{}\" at particle {} "
            "({}{})",
            b.velocity_where.empty() ? c.source : b.velocity_where, body, p.v_p[q][d], d + 1, b.velocity_formula[d], q,
            fmt::format("{}, {}", x[0], x[1]), D == 3 ? fmt::format(", {}", x[D - 1]) : std::string{}));
    }
  }
  m.body_particles.push_back(total);
  set_initial_state(c, body, start, m);

  BodyMotion<D> motion;
  for (int d = 0; d < D; ++d) {
    motion.prescribed[d] = b.prescribed[d];
    motion.any = motion.any || b.prescribed[d];
    motion.v0[d] = b.prescribed_velocity[d];
    for (int e = 0; e < D; ++e) motion.grad(d, e) = b.prescribed_gradient[d][e];
  }
  // A prescribed component starts at its prescribed value (with APIC, and its gradient).
  const bool apic = c.solver.velocity_transfer == VelocityTransfer::Apic;
  for (std::size_t q = start; q < p.size(); ++q)
    for (int d = 0; d < D; ++d)
      if (motion.prescribed[d]) {
        p.v_p[q][d] = motion.velocity(d, p.x_p[q]);
        if (apic) p.C_p[q].row(d) = motion.grad.row(d);
      }
  m.motion.push_back(motion);
}

}  // namespace

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
  m.step.scheme = c.solver.scheme;
  m.step.kernel = c.solver.shape;
  m.step.pic_fraction = c.solver.pic_fraction;
  m.step.velocity_transfer = c.solver.velocity_transfer;
  m.step.anti_locking.assign(c.materials.size(), c.solver.anti_locking);
  for (std::size_t k = 0; k < c.material_anti_locking.size() && k < c.materials.size(); ++k)
    if (c.material_anti_locking[k]) m.step.anti_locking[k] = *c.material_anti_locking[k];
  m.step.hold_released_volume = c.solver.hold_released_volume;
  m.step.damping = c.solver.damping;
  for (int d = 0; d < D; ++d) m.step.gravity[d] = c.gravity[d];
  if (c.gravity_function >= 0) m.step.gravity_function = c.functions[static_cast<std::size_t>(c.gravity_function)].f;
  m.step.sort_interval = c.solver.sort_interval;
  declare_state_columns(m.particles);
  m.particles.affine = c.solver.velocity_transfer == VelocityTransfer::Apic;
  for (int d = 0; d < D; ++d) {
    m.grid.origin[d] = c.grid.origin[d];
    m.grid.n_nodes[d] = c.grid.cells[d] + 1;
  }
  m.grid.h = c.grid.cell_size;
  const double nodes = [&] {
    double n = 1;
    for (int d = 0; d < D; ++d) n *= m.grid.n_nodes[d];
    return n;
  }();
  if (nodes > 2e9)
    throw InputError(fmt::format("{}: the grid has {:.3g} nodes; at most 2e9 are supported", c.source, nodes));
  check_memory<D>(c, m.grid);
  m.grid.allocate();
  set_boundary_conditions(c, m.grid, m.node_sets, m.held_nodes);
  for (int b = 0; b < static_cast<int>(c.bodies.size()); ++b) add_body(c, b, m);

  // Store the particles in the order the block scatter visits them: neighbours in space are then
  // neighbours in memory, which every stage of the step gains from.
  BlockSchedule<D> blocks;
  blocks.build(m.grid, m.particles.x_p);
  m.particles.permute(blocks.order());
  const auto& mp = m.particles.m_p;
  m.step.node_mass_floor = c.solver.mass_threshold * *std::min_element(mp.begin(), mp.end());
  return m;
}

template Model<2> build_model<2>(const Config&);
template Model<3> build_model<3>(const Config&);

}  // namespace tsuchi
