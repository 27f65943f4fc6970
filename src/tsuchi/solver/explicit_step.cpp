#include "tsuchi/solver/explicit_step.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/core/reduction.hpp"
#include "tsuchi/shape/gimp.hpp"
#include "tsuchi/shape/linear.hpp"
#include "tsuchi/shape/stencil.hpp"
#include "tsuchi/solver/damping.hpp"
#include "tsuchi/solver/jaumann.hpp"
#include "tsuchi/solver/particle_domain.hpp"
#include "tsuchi/solver/volumetric_strain.hpp"
#include "tsuchi/model/free_faces.hpp"
#include "tsuchi/model/material_state.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <type_traits>

namespace tsuchi {

template <int D>
void ExplicitSolver<D>::step(double dt) {
  if (drives_bodies()) held_impulse_.resize(m_.particles.size(), Vec<D>::Zero());
  if (!stepped_) restore_free_rigid_bodies();  // the first step of this process: a restart's V from the particles
  step_dt_ = dt;
  const auto& contact = m_.contact;
  if (contact.between_bodies()) field_of_body_ = contact.field_of_body;
  else field_of_body_.assign(m_.body_names.size(), 0);
  first_field_ = contact_.first(m_), last_field_ = contact_.last(m_);
  rigid_field_.assign(static_cast<std::size_t>(last_field_ + 1), 0);
  for (int f = 1; f <= last_field_; ++f) {
    const auto& bodies = contact.bodies_of_field[static_cast<std::size_t>(f - 1)];
    const bool free_rigid = bodies.size() == 1 && m_.motion[static_cast<std::size_t>(bodies[0])].rigid_mass > 0.0;
    rigid_field_[static_cast<std::size_t>(f)] = contact.rigid_body[static_cast<std::size_t>(f - 1)] >= 0 || free_rigid;
  }
  switch (m_.step.kernel) {
    case ShapeKind::Linear: step_with<shape::LinearKernel>(dt); break;
    case ShapeKind::UGimp:
    case ShapeKind::Gimp: step_with<shape::GimpKernel>(dt); break;
  }
  stepped_ = true;  // before: eq (R3) reads this step's reaction
  update_free_rigid_bodies(dt);
  time_ += dt;
  ++steps_;
}

// A free rigid body (bodies.N.rigid_mass = M) translates along its free components with
//   M (V_n+1 - V_n) / dt = F_c + M g,   F_c = -R - m g                                        (R3)
// where R is its reaction of eq (R1) in the step (its particles were held at V_n) and m the mass
// of its particles: with them held, -R is every force the model put on them, gravity on m
// included; F_c is what the rest (contact, loads) put on the body. Explicit, and stable while M is
// not much smaller than the mass of the soil at the nodes it touches (within a step the contact
// treats the body as infinitely heavy). V lives in the particles' velocity (all equal), so a
// restart continues from them; motion.v0 is brought up to date from them on a process's first step.
template <int D>
void ExplicitSolver<D>::update_free_rigid_bodies(double dt) {
  auto& p = m_.particles;
  for (std::size_t b = 0; b < m_.motion.size(); ++b) {
    auto& motion = m_.motion[b];
    if (!(motion.rigid_mass > 0.0)) continue;
    double m = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (static_cast<std::size_t>(p.body_p[i]) == b) m += p.m_p[i];
    const Vec<D> F = -reaction(static_cast<int>(b)) - m * gravity_;
    for (int d = 0; d < D; ++d)
      if (motion.free[d]) motion.v0[d] += dt * (F[d] / motion.rigid_mass + gravity_[d]);
    for (std::size_t i = 0; i < p.size(); ++i)
      if (static_cast<std::size_t>(p.body_p[i]) == b)
        for (int d = 0; d < D; ++d)
          if (motion.free[d]) p.v_p[i][d] = motion.v0[d];
  }
}

template <int D>
void ExplicitSolver<D>::restore_free_rigid_bodies() {
  const auto& p = m_.particles;
  for (std::size_t b = 0; b < m_.motion.size(); ++b) {
    auto& motion = m_.motion[b];
    if (!(motion.rigid_mass > 0.0)) continue;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (static_cast<std::size_t>(p.body_p[i]) == b) {
        for (int d = 0; d < D; ++d)
          if (motion.free[d]) motion.v0[d] = p.v_p[i][d];
        break;
      }
  }
}

// L = sum_i v_i G_ip^T at each follower-loaded particle, gathered as update_stress gathers it (the
// same nodal velocities, stencil and order of the sums, so the same bits); a rigid body's particle
// takes its prescribed motion's gradient, as there. O(loaded particles), after the step's loads.
template <int D>
template <class Kernel>
void ExplicitSolver<D>::follow_loads(double dt, FieldArray v_strain) {
  if (!loads_.follows()) return;
  struct Sums {
    Vec<D> w, dw;  // sums along x of wx v and dwx v
  };
  loads_.follow(m_.loads, dt, [&](std::size_t i) -> Mat<D> {
    const auto field = static_cast<std::size_t>(field_of(i));
    if (rigid_field_[field]) {
      const auto body = static_cast<std::size_t>(m_.particles.body_p[i]);
      return motion_scale_[body] * m_.motion[body].grad;
    }
    const Vec<D>* const v_g = (m_.grid.fields[field].*v_strain).data();
    const Stencil<D, Kernel> st = stencil_of<Kernel>(i);
    Mat<D> L = Mat<D>::Zero();
    st.gather(
        Sums{Vec<D>::Zero(), Vec<D>::Zero()},
        [&](Sums& row, std::int64_t k, double w, double dw) {
          row.w += w * v_g[k];
          row.dw += dw * v_g[k];
        },
        [&](const Sums& row, double T, const std::array<double, D - 1>& dT) {
          L.col(0) += T * row.dw;
          for (int d = 1; d < D; ++d) L.col(d) += dT[d - 1] * row.w;
        });
    return L;
  });
}

template <int D>
template <class Kernel>
void ExplicitSolver<D>::step_with(double dt) {
  switch (m_.step.velocity_transfer) {
    case Transfer::Flip: step_with<Kernel, Transfer::Flip>(dt); break;
    case Transfer::Apic: step_with<Kernel, Transfer::Apic>(dt); break;
  }
}

template <int D>
template <class Kernel, VelocityTransfer How>
void ExplicitSolver<D>::step_with(double dt) {
  auto& g = m_.grid;
  // The loads of this step are taken at its start (the explicit update of eq 4 uses f at t_n).
  gravity_ = m_.step.gravity * m_.step.gravity_function(time_);
  watch_free_faces();  // the step's settings may have changed at a stage
  // Blocks coloured for the kernel's reach; every stage below uses the start-of-step positions.
  constexpr auto reach = BlockSchedule<D>::template reach_of<Kernel>();
  schedule_.build(g, m_.particles.x_p, reach);
  const std::int64_t sort = m_.step.sort_interval;
  if (sort > 0 && steps_ > 0 && steps_ % sort == 0) {
    // The order depends on positions only, so every thread count sorts alike, and a restart at
    // the same step sorts alike.
    m_.particles.permute(schedule_.order(), sort_scratch_);
    schedule_.invalidate();
    schedule_.build(g, m_.particles.x_p, reach);
  }
  compute_stencils<Kernel>();
  begin_loads(dt);
  if (contact_on()) contact_.begin_step(m_, schedule_, motion_scale_);
  // Local damping acts on the free motion only: a component a prescribed body drives is held, and
  // a damping force there would only add to the force holding it (its reaction), 5 % of the
  // nodal force with damping 0.05, as a fixed component takes none either.
  held_nodes_.begin_step(m_, time_, dt);  // the base motion of this step
  undamped_driven_ = m_.step.damping > 0.0 && drives_bodies();
  if (undamped_driven_) mark_driven_nodes<Kernel>();
  constexpr FieldArray v = &NodalField<D>::v, vL = &NodalField<D>::vL;
  switch (m_.step.scheme) {
    case Scheme::USF:
      // The stress update changes the GIMP domains in place; the later stages still use the
      // start-of-step weights (the step's stencil factors), as they must: the same weights as the
      // mass p2g, or momentum is not conserved.
      p2g<Kernel, Scatter::MassMomentum, How>();
      nodal_velocity();
      update_stress<Kernel, AfterStress::Stay>(dt, v);
      p2g<Kernel, Scatter::Force, How>();
      apply_loads<Kernel>();
      follow_loads<Kernel>(dt, v);  // after the loads of the step are applied
      solve_grid(dt);
      g2p<Kernel, AfterGather::Move, How>(dt);
      break;
    case Scheme::USL:
      p2g<Kernel, Scatter::All, How>();
      apply_loads<Kernel>();
      nodal_velocity_and_solve<Momentum::Keep>(dt);
      g2p<Kernel, AfterGather::None, How>(dt);
      update_stress<Kernel, AfterStress::Move>(dt, vL);
      follow_loads<Kernel>(dt, vL);
      break;
    case Scheme::MUSL:
      p2g<Kernel, Scatter::All, How>();
      apply_loads<Kernel>();
      nodal_velocity_and_solve<Momentum::Clear>(dt);
      g2p<Kernel, AfterGather::Remap, How>(dt);
      nodal_velocity(At::End);
      update_stress<Kernel, AfterStress::Move>(dt, v);
      follow_loads<Kernel>(dt, v);
      break;
  }
  report_faults();
}

// The factors of the step from t_n to t_n + dt. A prescribed velocity takes the mean of its function
// over the step, (1/dt) int f dt (TimeFunction::integral): the body then moves by exactly
// (v0 + grad . x) int_0^t f over any sequence of steps (a ramp's displacement does not depend on
// the time step). The loads take f(t_n) (solver/load_stage.hpp).
template <int D>
void ExplicitSolver<D>::begin_loads(double dt) {
  motion_scale_.resize(m_.motion.size());
  for (std::size_t b = 0; b < m_.motion.size(); ++b) {
    const TimeFunction& f = m_.motion[b].function;
    motion_scale_[b] = f.is_one() ? 1.0 : f.integral(time_, time_ + dt) / dt;
  }
  loads_.begin_step(m_.loads, m_.particles, m_.body_names.size(), time_);
}

namespace {

// The particle's strain increment with the volumetric part its material's remedy takes
// (solver.anti_locking): the cell centre's, eq (V2), or the nodal average's, eq (V3), from the
// average of the particle's body field. x is the particle's start-of-step position (the cell's).
template <int D, class Kernel>
[[gnu::always_inline]] inline void apply_anti_locking(AntiLocking remedy, const Grid<D>& g, const Stencil<D, Kernel>& st,
                                                      const Vec<D>& x, const Vec<D>* v_g, const NodalAverage<D>& average,
                                                      int field, int material, double dt, Voigt<D>& d_eps) {
  if (remedy == AntiLocking::Cell)
    replace_volumetric_strain<D>(d_eps, dt * cell_centre_divergence<D>(g, v_g, Stencil<D, Kernel>::in_cells(g, x)));
  else if (node_averaged(remedy)) replace_volumetric_strain<D>(d_eps, average.gather(st, field, material));
}

}  // namespace

// Every particle's stencil at its start-of-step position and width, once per step: the stages
// that follow all use these (USF defers the domain update, USL and MUSL move a particle only at
// the end of its own stress update), so computing it once gives the same weights, bit for bit, as
// computing it in each stage.
template <int D>
template <class Kernel>
void ExplicitSolver<D>::compute_stencils() {
  const auto& g = m_.grid;
  const auto& p = m_.particles;
  auto& cache = stencils<Kernel>();
  cache.resize(p.size());
  schedule_.for_each_particle([&](std::size_t i) { Stencil<D, Kernel>::axes(g, p.x_p[i], p.l_p[i], cache[i]); });
}

namespace {

// Zeroes nodal arrays on the active tiles, in one parallel loop: a serial fill of the whole grid
// would be the largest serial part of the step.
template <int D, class... Arrays>
void zero_nodal(const BlockSchedule<D>& schedule, Arrays&... a) {
  schedule.for_active_nodes([&](std::int64_t k) { ((a[k] = zero_of<typename Arrays::value_type>()), ...); });
}

}  // namespace

// Particle to grid, eqs (1)-(3): mass, momentum, and f_int = -sum V_p (sigma_p - sigma0_p) . G,
// f_ext = sum S m_p b.
// What it scatters is a compile-time choice: the node loop is the hottest loop of the step and
// should carry no test that is the same for every node.
// With APIC the momentum is that of the particle's affine velocity field (Jiang et al. 2015, P2G
// for a general w_ip):  m_i v_i = sum_p w_ip m_p (v_p + C_p (x_i - x_p)). With partition of unity
// and sum_i w_ip (x_i - x_p) = 0 the affine term adds no linear momentum; it adds the particle's
// spin m_p eps : (C_p D_p)^T to the angular momentum (D_p below, at g2p).
template <int D>
template <class Kernel, typename ExplicitSolver<D>::Scatter What, VelocityTransfer How>
void ExplicitSolver<D>::p2g() {
  constexpr bool mass_momentum = What != Scatter::Force, force = What != Scatter::MassMomentum;
  constexpr bool affine = How == Transfer::Apic && mass_momentum;
  auto& g = m_.grid;
  const auto& p = m_.particles;
  for_body_fields([&](int, NodalField<D>& n) {
    if constexpr (What == Scatter::All) zero_nodal(schedule_, n.m, n.p, n.f);
    else if constexpr (What == Scatter::MassMomentum) zero_nodal(schedule_, n.m, n.p);
    else zero_nodal(schedule_, n.f);
  });
  if constexpr (mass_momentum)
    if (m_.contact.between_bodies()) scatter_mass_gradient<Kernel>();
  const Vec<D> b = gravity_;
  bool smooth_pressure = false;
  if constexpr (force) smooth_pressure = average_pressure<Kernel>();
  // What a row of the stencil spreads along x (stencil.hpp): with c_d the columns of -V sigma,
  // node (a, r) gets m wx[a] T, mv wx[a] T and
  //   f = S mb + sum_d G_d c_d = wx[a] (T mb + sum_{d>0} dT_d c_d) + dwx[a] T c_0.
  struct Row {
    double m;
    Vec<D> mv, f_w, f_dw;
  };
  schedule_.scatter([&](std::size_t i) {
    // Local copies of the array addresses: Eigen's vector stores may alias anything, and would
    // otherwise make the compiler reload every vector's address after each node's update.
    auto& n = g.fields[static_cast<std::size_t>(field_of(i))];
    double* const m_g = n.m.data();
    Vec<D>* const p_g = n.p.data();
    Vec<D>* const f_g = n.f.data();
    Stencil<D, Kernel> st = stencil_of<Kernel>(i);
    const double m = p.m_p[i];
    Mat3 s = to_matrix<D>(p.stress_above_initial(i));
    if constexpr (force)
      if (smooth_pressure) {
        if (takes_averaged_pressure(i))
          s.diagonal().array() += pressure_average_.gather(st, field_of(i), p.material_p[i]) - s.trace() / 3.0;  // eq (V5)
      }
    // -V sigma, so that the force is S m b + (-V sigma) G with one product per node.
    const Mat<D> minus_V_stress = -p.V_p[i] * s.template topLeftCorner<D, D>();
    const Vec<D> mv = m * p.v_p[i];
    const Vec<D> mb = m * b;
    if constexpr (!affine) {
      st.scatter(
          [&](double T, const std::array<double, D - 1>& dT) {
            Row row{T * m, T * mv, T * mb, {}};
            for (int d = 1; d < D; ++d) row.f_w += dT[d - 1] * minus_V_stress.col(d);
            row.f_dw = T * minus_V_stress.col(0);
            return row;
          },
          [&](std::int64_t k, double w, double dw, const Row& row) {
            if constexpr (mass_momentum) {
              m_g[k] += w * row.m;
              p_g[k] += w * row.mv;
            }
            if constexpr (force) f_g[k] += w * row.f_w + dw * row.f_dw;
          });
    } else {
      // Node (a, r) at x_i - x_p = (rx[a], ry[r]): m (v + C (x_i - x_p)) = row.mv / T + rx[a] m C e_x,
      // with row.mv = T m (v + sum_{d>0} C e_d ry_d) formed once per row.
      struct AffineRow {
        Row base;
        Vec<D> mC_x;  // T m C e_x
      };
      const Mat<D> mC = m * p.C_p[i];
      st.compute_offsets(g, p.x_p[i]);
      st.scatter(
          [&](double T, const std::array<double, D - 1>& dT, const std::array<double, D - 1>& ry) {
            Vec<D> mv_row = mv;
            for (int d = 1; d < D; ++d) mv_row += ry[d - 1] * mC.col(d);
            AffineRow row{{T * m, T * mv_row, T * mb, {}}, T * mC.col(0)};
            for (int d = 1; d < D; ++d) row.base.f_w += dT[d - 1] * minus_V_stress.col(d);
            row.base.f_dw = T * minus_V_stress.col(0);
            return row;
          },
          [&](std::int64_t k, double w, double dw, const AffineRow& row, double rx) {
            m_g[k] += w * row.base.m;
            p_g[k] += w * row.base.mv + (w * rx) * row.mC_x;
            if constexpr (force) f_g[k] += w * row.base.f_w + dw * row.base.f_dw;
          });
    }
  });
}

// The mass gradient of each body field, sum_p m_p grad S_ip, for the contact normals (eq C1 of
// solver/contact_stage.hpp). A pass of its own, run only with contact between bodies, so that the
// p2g of a model without contact carries no extra work.
template <int D>
template <class Kernel>
void ExplicitSolver<D>::scatter_mass_gradient() {
  const auto& p = m_.particles;
  struct Row {
    double Tm;
    std::array<double, D - 1> dTm;
  };
  schedule_.scatter([&](std::size_t i) {
    Vec<D>* const gm = contact_.mass_gradient(field_of(i)).data();
    Stencil<D, Kernel> st = stencil_of<Kernel>(i);
    const double m = p.m_p[i];
    st.scatter(
        [&](double T, const std::array<double, D - 1>& dT) {
          Row row{T * m, {}};
          for (int d = 0; d < D - 1; ++d) row.dTm[static_cast<std::size_t>(d)] = dT[static_cast<std::size_t>(d)] * m;
          return row;
        },
        [&](std::int64_t k, double w, double dw, const Row& row) {
          gm[k][0] += dw * row.Tm;
          for (int d = 1; d < D; ++d) gm[k][d] += w * row.dTm[static_cast<std::size_t>(d - 1)];
        });
  });
}

// v_g = p_g / m_g on a node heavier than the floor, then the velocity boundary conditions.
template <int D>
inline Vec<D> ExplicitSolver<D>::velocity_at(const NodalField<D>& n, std::int64_t k) const {
  const auto& g = m_.grid;
  Vec<D> v = n.m[k] > m_.step.node_mass_floor ? Vec<D>(n.p[k] / n.m[k]) : Vec<D>::Zero();
  for (int d = 0; d < D; ++d)
    if (g.fixed_g[k] & (1u << d)) v[d] = 0.0;
  return v;
}

// Grid momentum balance at a node, eq (4), with local damping and the boundary conditions:
// a_g = (f + f_damp(f, v_g)) / m_g.
template <int D>
inline Vec<D> ExplicitSolver<D>::acceleration_at(const NodalField<D>& n, std::int64_t k, const Vec<D>& v,
                                                 std::size_t driven_offset, bool undamped) const {
  const auto& g = m_.grid;
  Vec<D> a = Vec<D>::Zero();
  if (n.m[k] > m_.step.node_mass_floor) {
    const unsigned driven = undamped ? (1u << D) - 1u : undamped_driven_ ? driven_[driven_offset + static_cast<std::size_t>(k)] : 0u;
    for (int d = 0; d < D; ++d) {
      const double f = n.f[k][d];
      a[d] = ((driven >> d) & 1u ? f : f + local_damping_force(f, v[d], m_.step.damping)) / n.m[k];
      if (g.fixed_g[k] & (1u << d)) a[d] = 0.0;
    }
  }
  return a;
}

// Driven components (base motion) then take their velocity at the start or the end of the step,
// eq (B1) of solver/held_nodes.hpp: the end after MUSL's remap, whose velocities are end-of-step ones.
// contact_node_ on the active nodes: two or more body fields with mass, or a frictional wall's node.
template <int D>
void ExplicitSolver<D>::mark_contact_nodes() {
  const auto& F = m_.grid.fields;
  const double floor = m_.step.node_mass_floor;
  contact_node_.resize(m_.grid.size());
  schedule_.for_active_nodes([&](std::int64_t k) {
    int present = 0;
    for (int f = first_field_; f <= last_field_; ++f) present += F[static_cast<std::size_t>(f)].m[k] > floor;
    contact_node_[static_cast<std::size_t>(k)] = present > 1;
  });
  for (const auto& wall : m_.contact.walls)
    for (const std::int64_t k : wall.nodes) contact_node_[static_cast<std::size_t>(k)] = 1;
}

// With contact, the velocities are then corrected where bodies meet: USF's start-of-step ones,
// for its stress update, and MUSL's remapped ones, for its (solver/contact_stage.hpp).
template <int D>
void ExplicitSolver<D>::nodal_velocity(At driven_at) {
  for_body_fields([&](int, NodalField<D>& n) {
    schedule_.for_active_nodes([&](std::int64_t k) { n.v[k] = velocity_at(n, k); });
    held_nodes_.set_velocity(m_, schedule_, n, driven_at);
  });
  if (!contact_on()) return;
  using Stage = typename ContactStage<D>::Stage;
  if (driven_at == At::End) contact_.correct(m_, schedule_, Stage::Remap, step_dt_);
  else if (m_.step.scheme == Scheme::USF) contact_.correct(m_, schedule_, Stage::Start, step_dt_);
}

// a_g, and v^L = v_g + dt a_g. The held nodes' free momenta are booked first for the support
// reactions (eq R2), and driven components get their motion after, eq (B1).
// With contact, field 0 first takes the sum of the body fields' mass, momentum and force (the
// booking and the unbalanced-force ratio read it), each body field is solved, and the contact
// stage corrects the updated velocities.
template <int D>
void ExplicitSolver<D>::solve_grid(double dt) {
  auto& n0 = nodes();
  if (m_.contact.between_bodies()) {
    const int G = m_.contact.fields;
    auto& F = m_.grid.fields;
    schedule_.for_active_nodes([&](std::int64_t k) {
      double m = 0.0;
      Vec<D> p = Vec<D>::Zero(), f = Vec<D>::Zero();
      for (int b = 1; b <= G; ++b) m += F[b].m[k], p += F[b].p[k], f += F[b].f[k];
      n0.m[k] = m, n0.p[k] = p, n0.f[k] = f;
    });
  }
  held_nodes_.book(m_, schedule_, n0);
  const std::size_t size = m_.grid.size();
  // Local damping leaves the nodes where contact may act (two fields there, or a wall): its force,
  // -alpha |f| sign(v), flips with the sign of a velocity near zero at a body at rest on another,
  // and the contact's reaction took it on, +-alpha of the weight from step to step.
  const bool spare_contact = contact_on() && m_.step.damping > 0.0;
  const bool keep_a = m_.grid.keep_acceleration;
  if (spare_contact) mark_contact_nodes();
  for_body_fields([&](int field, NodalField<D>& n) {
    const std::size_t driven_offset = static_cast<std::size_t>(field) * size;
    schedule_.for_active_nodes([&](std::int64_t k) {
      const bool undamped = spare_contact && contact_node_[static_cast<std::size_t>(k)];
      const Vec<D> a = acceleration_at(n, k, n.v[k], driven_offset, undamped);
      if (keep_a) n.a[k] = a;
      n.vL[k] = n.v[k] + dt * a;
    });
    held_nodes_.set_solve(m_, schedule_, n);
  });
  if (contact_on()) contact_.correct(m_, schedule_, ContactStage<D>::Stage::Solve, dt);
}

// nodal_velocity() then solve_grid() in one pass over the nodes, for USL and MUSL, where nothing
// comes between them. With Momentum::Clear p_g is zeroed once read, ready for the remap.
template <int D>
template <typename ExplicitSolver<D>::Momentum Then>
void ExplicitSolver<D>::nodal_velocity_and_solve(double dt) {
  if (contact_on()) {
    // Two passes: the contact stage comes between the solve and the clearing of p.
    for_body_fields([&](int, NodalField<D>& n) {
      schedule_.for_active_nodes([&](std::int64_t k) { n.v[k] = velocity_at(n, k); });
      held_nodes_.set_velocity(m_, schedule_, n, At::Start);
    });
    solve_grid(dt);
    if constexpr (Then == Momentum::Clear)
      for_body_fields([&](int, NodalField<D>& n) { zero_nodal(schedule_, n.p); });
    return;
  }
  auto& n = nodes();
  held_nodes_.book(m_, schedule_, n);  // before p is cleared: see solve_grid
  const bool keep_a = m_.grid.keep_acceleration;
  schedule_.for_active_nodes([&](std::int64_t k) {
    const Vec<D> v = velocity_at(n, k), a = acceleration_at(n, k, v);
    n.v[k] = v;
    if (keep_a) n.a[k] = a;
    n.vL[k] = v + dt * a;
    if constexpr (Then == Momentum::Clear) n.p[k] = Vec<D>::Zero();
  });
  held_nodes_.set_solve(m_, schedule_, n);
}

// Grid to particle, eqs (7)-(8): FLIP v_p += dt sum S a_g, blended with PIC sum S v^L when asked.
// Prescribed components are then set (their acceleration is zero). With AfterGather::Remap the
// updated particle momenta are projected back to the grid, eq (9) (MUSL), into a p_g cleared by
// nodal_velocity_and_solve<Momentum::Clear>(). With AfterGather::Move, eqs (5)-(6).
//
// With APIC (Jiang et al. 2015, G2P for a general w_ip) the particle takes the PIC velocity and
// the affine matrix fitted to the updated nodal velocities around it:
//   v_p = sum_i w_ip v^L_i,   B_p = sum_i w_ip v^L_i (x_i - x_p)^T,
//   D_p = sum_i w_ip (x_i - x_p)(x_i - x_p)^T,   C_p = B_p D_p^{-1}.
// D_p is summed from this particle's stencil weights and node offsets, not taken from a closed
// form: for the linear and GIMP kernels it depends on where the particle sits in its cell (for
// linear hats D_dd = (x_p - x_0)(x_1 - x_p) along each axis), unlike the quadratic and cubic
// B-splines of the paper (h^2/4 I, h^2/3 I). Inside the grid it is diagonal up to round-off
// (tensor-product weights reproducing linear functions); it is inverted whole all the same. Where
// D_dd vanishes (a linear-kernel particle on a grid line along d) B e_d vanishes too and column d
// of C_p is set to 0. Prescribed components take the prescribed velocity and its gradient.
// Balance: the grid's angular momentum sum_i x_i × m_i v^L_i equals that of the particles after
// g2p, sum_p x_p × m_p v_p + m_p eps : B_p^T (x_p moved with v_p), and the next p2g spreads
// m_p eps : (C_p D_p)^T with D_p at the new position. The two spins agree, and angular momentum is
// kept to round-off, when D_p does not change as the particle moves: uGIMP with l_p = h/2 (one
// particle per cell and axis) has D_p = h^2/4 I everywhere; otherwise it drifts by
// m_p eps : (C_p dD_p)^T (tests/velocity_transfer_test.cpp measures both).
template <int D>
template <class Kernel, typename ExplicitSolver<D>::AfterGather Then, VelocityTransfer How>
void ExplicitSolver<D>::g2p(double dt) {
  if constexpr (How == Transfer::Apic) g2p_affine<Kernel, Then>(dt);
  else g2p_flip<Kernel, Then>(dt);
}

// Runs g2p's per-particle work over every particle: colour by colour when the remap writes nodes,
// else a plain parallel loop (each particle writes only its own arrays).
template <int D>
template <typename ExplicitSolver<D>::AfterGather Then, class F>
void ExplicitSolver<D>::for_each_gathering_particle(F&& particle) {
  if constexpr (Then == AfterGather::Remap) {
    schedule_.scatter(particle);
  } else {
    schedule_.for_each_particle(particle);
  }
}

template <int D>
template <class Kernel, typename ExplicitSolver<D>::AfterGather Then>
void ExplicitSolver<D>::g2p_flip(double dt) {
  auto& g = m_.grid;
  auto& p = m_.particles;
  // The model keeps the nodal acceleration for a FLIP run (model.cpp); a step that reached here
  // without it would read an empty array.
  if (!g.keep_acceleration) throw std::logic_error("g2p_flip: the grid keeps no nodal acceleration");
  const double beta = m_.step.pic_fraction;
  struct Sums {
    Vec<D> a, vL;
  };
  const Sums zero{Vec<D>::Zero(), Vec<D>::Zero()};
  const auto particle = [&](std::size_t i) {
    auto& n = g.fields[static_cast<std::size_t>(field_of(i))];
    const Vec<D>* const a_g = n.a.data();  // local addresses: see p2g
    const Vec<D>* const vL_g = n.vL.data();
    Vec<D>* const p_g = n.p.data();
    Stencil<D, Kernel> st = stencil_of<Kernel>(i);
    Vec<D> a = Vec<D>::Zero(), vL = Vec<D>::Zero();
    st.gather(
        zero,
        [&](Sums& row, std::int64_t k, double w, double) {
          row.a += w * a_g[k];
          row.vL += w * vL_g[k];
        },
        [&](const Sums& row, double T, const std::array<double, D - 1>&) {
          a += T * row.a;
          vL += T * row.vL;
        });
    Vec<D> v = p.v_p[i] + dt * a;
    if (beta > 0.0) v = (1.0 - beta) * v + beta * vL;
    hold_motion(i, v);
    if (!v.allFinite()) note_fault(nonfinite_, i);
    p.v_p[i] = v;
    if constexpr (Then == AfterGather::Remap) {
      const Vec<D> mv = p.m_p[i] * v;
      st.scatter([&](double T, const std::array<double, D - 1>&) -> Vec<D> { return T * mv; },
                 [&](std::int64_t k, double w, double, const Vec<D>& Tmv) { p_g[k] += w * Tmv; });
    }
    if constexpr (Then == AfterGather::Move) move_particle(i, dt, vL);
  };
  for_each_gathering_particle<Then>(particle);
}

// g2p with the APIC transfer (above): v_p, C_p from v^L; the remap projects the momentum of the
// particle's affine field, as p2g does; the particle moves with v^L interpolated, as with FLIP.
template <int D>
template <class Kernel, typename ExplicitSolver<D>::AfterGather Then>
void ExplicitSolver<D>::g2p_affine(double dt) {
  auto& g = m_.grid;
  auto& p = m_.particles;
  const double tiny = 1e-12 * g.h * g.h;
  // Sums along x of w v^L and w rx v^L; with the sums of w, w rx, w rx^2 (the same for every row:
  // they hold the stencil's own factors only, so they are formed once) the row factors T, ry then
  // give v_p, B_p, D_p.
  struct Sums {
    Vec<D> v, v_rx;
  };
  const Sums zero{Vec<D>::Zero(), Vec<D>::Zero()};
  const auto particle = [&](std::size_t i) {
    auto& n = g.fields[static_cast<std::size_t>(field_of(i))];
    const Vec<D>* const vL_g = n.vL.data();  // local addresses: see p2g
    Vec<D>* const p_g = n.p.data();
    Stencil<D, Kernel> st = stencil_of<Kernel>(i);
    st.compute_offsets(g, p.x_p[i]);  // before this particle moves, below
    Vec<D> vL = Vec<D>::Zero();
    Mat<D> B = Mat<D>::Zero(), Dp = Mat<D>::Zero();
    double sum_w = 0.0, sum_w_rx = 0.0, sum_w_rx2 = 0.0;
    for (int a = 0; a < st.K; ++a) {
      const double wrx = st.wx[a] * st.rx[a];
      sum_w += st.wx[a];
      sum_w_rx += wrx;
      sum_w_rx2 += wrx * st.rx[a];
    }
    st.gather(
        zero,
        [&](Sums& row, std::int64_t k, double wa, double, double rx) {
          row.v += wa * vL_g[k];
          row.v_rx += (wa * rx) * vL_g[k];
        },
        [&](const Sums& row, double T, const std::array<double, D - 1>&, const std::array<double, D - 1>& ry) {
          vL += T * row.v;
          B.col(0) += T * row.v_rx;
          Dp(0, 0) += T * sum_w_rx2;
          for (int d = 1; d < D; ++d) {
            const double Ty = T * ry[d - 1];
            B.col(d) += Ty * row.v;
            Dp(0, d) += Ty * sum_w_rx;
            for (int e = 1; e < D; ++e) Dp(d, e) += Ty * ry[e - 1] * sum_w;
          }
        });
    for (int d = 1; d < D; ++d) Dp(d, 0) = Dp(0, d);
    Mat<D> C;
    if (Dp.diagonal().minCoeff() > tiny) {
      C = B * Dp.inverse();
    } else {
      C = Mat<D>::Zero();
      for (int d = 0; d < D; ++d)
        if (Dp(d, d) > tiny) C.col(d) = B.col(d) / Dp(d, d);
    }
    Vec<D> v = vL;
    hold_motion(i, v, C);
    if (!v.allFinite() || !C.allFinite()) note_fault(nonfinite_, i);
    p.v_p[i] = v;
    p.C_p[i] = C;
    if constexpr (Then == AfterGather::Remap) {
      const double m = p.m_p[i];
      const Vec<D> mv = m * v;
      const Mat<D> mC = m * C;
      struct AffineRow {
        Vec<D> mv, mC_x;  // T m (v + sum_{d>0} C e_d ry_d), T m C e_x
      };
      st.scatter(
          [&](double T, const std::array<double, D - 1>&, const std::array<double, D - 1>& ry) {
            Vec<D> mv_row = mv;
            for (int d = 1; d < D; ++d) mv_row += ry[d - 1] * mC.col(d);
            return AffineRow{T * mv_row, T * mC.col(0)};
          },
          [&](std::int64_t k, double w, double, const AffineRow& row, double rx) {
            p_g[k] += w * row.mv + (w * rx) * row.mC_x;
          });
    }
    if constexpr (Then == AfterGather::Move) move_particle(i, dt, vL);
  };
  for_each_gathering_particle<Then>(particle);
}

// solver.anti_locking = "node" and "bbar": the nodal volume-weighted average of the particles'
// volumetric strain increments,
//   e_i = sum_p S_ip V_p tr(d_eps_p) / sum_p S_ip V_p,        tr(d_eps_p)_bar = sum_i S_ip e_i,   (V3)
// over the particles of each material that asks for it (each over its own), which update_stress()
// then gives each such particle in place of its own (eq V1 of solver/volumetric_strain.hpp). This is the volume
// averaging by the particle-grid transfers of Zhao, Jiang and Choo (2023, "Circumventing
// volumetric locking in explicit material point methods", CMAME), in rate form: a smooth field,
// so no cell-by-cell pressure pattern, for any kernel. One more scatter over the particles.
template <int D>
template <class Kernel>
void ExplicitSolver<D>::average_volumetric_strain(double dt, FieldArray v_strain) {
  const auto& g = m_.grid;
  const auto& p = m_.particles;
  const auto& by_material = m_.step.anti_locking;
  // One average per body field and material: bodies in contact do not share their volume change,
  // nor do two materials bonded in one field (solver/nodal_average.hpp).
  volume_strain_average_.begin(schedule_, g.size(), first_field_, last_field_, m_.materials.size(),
                               [&](std::size_t mat) { return mat < by_material.size() && node_averaged(by_material[mat]); });
  struct Sums {
    Vec<D> w, dw;
  };
  const Sums zero{Vec<D>::Zero(), Vec<D>::Zero()};
  schedule_.scatter([&](std::size_t i) {
    const auto mat = static_cast<std::size_t>(p.material_p[i]);
    if (mat >= by_material.size() || !node_averaged(by_material[mat])) return;
    if (rigid_field_[static_cast<std::size_t>(field_of(i))]) return;  // takes no remedy (update_stress)
    const std::size_t field = static_cast<std::size_t>(field_of(i));
    const Vec<D>* const v_g = (g.fields[field].*v_strain).data();
    Stencil<D, Kernel> st = stencil_of<Kernel>(i);
    double div = 0.0;  // tr L = sum_i G_i . v_i
    st.gather(
        zero,
        [&](Sums& row, std::int64_t k, double w, double dw) {
          row.w += w * v_g[k];
          row.dw += dw * v_g[k];
        },
        [&](const Sums& row, double T, const std::array<double, D - 1>& dT) {
          div += T * row.dw[0];
          for (int d = 1; d < D; ++d) div += dT[d - 1] * row.w[d];
        });
    const double V = p.V_p[i];
    volume_strain_average_.add(st, static_cast<int>(field), static_cast<int>(mat), V, V * dt * div);
  });
  volume_strain_average_.finish(schedule_);
}

// solver.anti_locking = "bbar", the force's side of eq (V3): the pressure each such particle puts
// into the internal force is the nodal average of the particles' pressures, gathered back,
//   P_i = sum_p S_ip V_p p_p / sum_p S_ip V_p,        p_p_bar = sum_i S_ip P_i,                  (V5)
// with p_p = tr(sigma_p - sigma0_p) / 3 (zz included in plane strain), and the force
//   f_i = -sum_p V_p (sigma_p - sigma0_p + (p_p_bar - p_p) I) . G_ip.
// This is the transpose of (V3): the virtual work of the averaged volumetric strain,
// sum_p V_p p_p d(e_p_bar), is sum_i dv_i . sum_p V_p p_p_bar G_ip, so the force and the strain
// increment form one symmetric pair, B_bar^T sigma and B_bar v, as in Hughes' (1980) B-bar
// element. With (V3) alone the stiffness is B^T C B_bar: not symmetric, and a velocity mode whose
// divergence averages to zero at the nodes is loaded by the particle's own pressure but does no
// work against it, which lets perfectly plastic, nearly incompressible soil gain energy
// (examples/footing: the 40-cell Tresca footing without a tension cut-off). Returns whether any
// particle takes (V5), and then pressure_average_ holds P_i.
template <int D>
template <class Kernel>
bool ExplicitSolver<D>::average_pressure() {
  const auto& g = m_.grid;
  const auto& p = m_.particles;
  const auto& by_material = m_.step.anti_locking;
  if (std::find(by_material.begin(), by_material.end(), AntiLocking::Bbar) == by_material.end()) return false;
  pressure_average_.begin(schedule_, g.size(), first_field_, last_field_, m_.materials.size(),
                          [&](std::size_t mat) { return mat < by_material.size() && by_material[mat] == AntiLocking::Bbar; });
  schedule_.scatter([&](std::size_t i) {
    if (!takes_averaged_pressure(i)) return;
    const int field = field_of(i);
    Stencil<D, Kernel> st = stencil_of<Kernel>(i);
    const double V = p.V_p[i];
    pressure_average_.add(st, field, p.material_p[i], V, V * trace<D>(p.stress_above_initial(i)) / 3.0);
  });
  pressure_average_.finish(schedule_);
  return true;
}

// Strain and spin increments from the grid velocity, eq (10); Jaumann rotation (22) and the
// constitutive update (11); volume (12), GIMP domain (14); with AfterStress::Move also positions
// (5)-(6).
// The material is chosen once per material group, outside the particle loop.
template <int D>
template <class Kernel, typename ExplicitSolver<D>::AfterStress Then>
void ExplicitSolver<D>::update_stress(double dt, FieldArray v_strain) {
  constexpr bool move = Then == AfterStress::Move;
  auto& g = m_.grid;
  auto& p = m_.particles;
  const bool domain_update = m_.step.domain_update();
  const auto& materials = m_.materials;
  // An anisotropic initial stress held by eq (2) turns with the material, as the stress does.
  const bool rotate_sigma0 = m_.rotate_initial_stress;
  struct Sums {
    Vec<D> w, dw, vL;  // sums along x of wx v, dwx v and wx v^L
  };
  const Sums zero{Vec<D>::Zero(), Vec<D>::Zero(), Vec<D>::Zero()};
  const bool hold_released = m_.step.hold_released_volume;
  std::int64_t released = 0;
  const auto& by_material = m_.step.anti_locking;
  if (std::any_of(by_material.begin(), by_material.end(), node_averaged))
    average_volumetric_strain<Kernel>(dt, v_strain);
  // One parallel region for every material group; a thread goes on to the next group without
  // waiting, as the groups hold different particles.
  schedule_.begin_balanced(materials.size());
#pragma omp parallel reduction(+ : released)
  for (std::size_t mat = 0; mat < materials.size(); ++mat) {
    // Missing entries (a model built by hand) keep the particle's own volumetric strain.
    const AntiLocking remedy = mat < by_material.size() ? by_material[mat] : AntiLocking::None;
    std::visit(
        [&](const auto& model) {
          using M = std::decay_t<decltype(model)>;
          constexpr bool can_release = requires(const M& mm, StateRef s) { mm.released(s); };
          const typename M::Context context = model.context();
          const auto state = state_columns<M>(p);
          // Block by block, each thread first the blocks it scattered, whose particles' data are
          // still in its cache, then what is left of the others' (grid/block_schedule.hpp):
          // yielding points cost several times more than elastic ones, and they gather in the
          // shear bands. Every point's update is its own, so the result does not depend on which
          // thread takes which block.
          schedule_.for_each_particle_balanced(mat, [&](std::size_t i) {
            if (p.material_p[i] != static_cast<std::int32_t>(mat)) return;
            const std::size_t field = static_cast<std::size_t>(field_of(i));
            const auto& n = g.fields[field];
            const Vec<D>* const v_g = (n.*v_strain).data();  // local addresses: see p2g
            const Vec<D>* const vL_g = n.vL.data();
            Stencil<D, Kernel> st = stencil_of<Kernel>(i);
            // L = sum v G^T, column j = sum v G_j; along x first, then the row factors.
            Mat<D> L = Mat<D>::Zero();
            Vec<D> vL = Vec<D>::Zero();
            st.gather(
                zero,
                [&](Sums& row, std::int64_t k, double w, double dw) {
                  row.w += w * v_g[k];
                  row.dw += dw * v_g[k];
                  if constexpr (move) row.vL += w * vL_g[k];
                },
                [&](const Sums& row, double T, const std::array<double, D - 1>& dT) {
                  L.col(0) += T * row.dw;
                  for (int d = 1; d < D; ++d) L.col(d) += dT[d - 1] * row.w;
                  if constexpr (move) vL += T * row.vL;
                });
            // A rigid body in contact deforms only as its prescribed motion says: its field also
            // carries the other bodies' contact impulses (for its reaction), not its strain.
            if (rigid_field_[field]) {
              const auto body = static_cast<std::size_t>(p.body_p[i]);
              L = motion_scale_[body] * m_.motion[body].grad;
            }
            Voigt<D> d_eps = dt * sym_voigt<D>(L);
            // A rigid body's strain is its prescribed motion's: no remedy (its field's velocities
            // carry the contact impulses, which the nodal average would turn into volume change).
            const AntiLocking own = rigid_field_[field] ? AntiLocking::None : remedy;
            apply_anti_locking<D>(own, g, st, p.x_p[i], v_g, volume_strain_average_, static_cast<int>(field),
                                  static_cast<int>(mat), dt, d_eps);
            const Mat<D> d_omega = 0.5 * dt * (L - L.transpose());
            jaumann_rotate(p.sigma_p[i], d_omega);
            if (rotate_sigma0) jaumann_rotate(p.sigma0_p[i], d_omega);
            const StateRef point{state.data(), i};
            model.template update<D>(p.sigma_p[i], d_eps, d_omega, context, point);
            p.eps_p[i] += d_eps;
            double J = 1.0 + trace<D>(d_eps);
            if (!p.sigma_p[i].allFinite() || !std::isfinite(J)) note_fault(nonfinite_, i);
            else if (!(J > 0.0)) note_fault(inverted_, i);
            // A point released in tension keeps its volume (and GIMP domain) when the step would
            // expand it: the opening is a gap between particles, not a looser material, and left
            // to grow it inflated particles 49-fold and cut the stable time step.
            bool held = false;
            if constexpr (can_release)
              if (hold_released && J > 1.0 && model.released(point)) held = true, J = 1.0, ++released;
            p.V_p[i] *= J;
            if (domain_update) {
              if (held) d_eps = Voigt<D>::Zero();
              update_particle_domain<D>(p.l_p[i], d_eps, g.h);
            }
            if constexpr (move) move_particle(i, dt, vL);
          });
        },
        materials[mat].model);
  }
  released_ = released;
}

// Prescribed components take the prescribed value, evaluated at the start-of-step position.
template <int D>
inline void ExplicitSolver<D>::impose_motion(std::size_t i, Vec<D>& v) const {
  const auto body = static_cast<std::size_t>(m_.particles.body_p[i]);
  const auto& motion = m_.motion[body];
  if (!motion.any) return;
  const double f = motion_scale_[body];  // the function of time's factor for this step
  for (int d = 0; d < D; ++d)
    if (motion.prescribed[d]) v[d] = (motion.free[d] ? 1.0 : f) * motion.velocity(d, m_.particles.x_p[i]);
}

// The same for APIC's affine matrix: a prescribed component v_d = v0_d + grad_d . x has the
// gradient grad_d as row d of C_p.
template <int D>
inline void ExplicitSolver<D>::impose_motion(std::size_t i, Vec<D>& v, Mat<D>& C) const {
  const auto body = static_cast<std::size_t>(m_.particles.body_p[i]);
  const auto& motion = m_.motion[body];
  if (!motion.any) return;
  const double f = motion_scale_[body];
  for (int d = 0; d < D; ++d)
    if (motion.prescribed[d]) {
      const double fd = motion.free[d] ? 1.0 : f;  // a free rigid component follows eq (R3), not f(t)
      v[d] = fd * motion.velocity(d, m_.particles.x_p[i]);
      C.row(d) = fd * motion.grad.row(d);
    }
}

// g2p's velocity update of a particle of a prescribed-motion body: the prescribed components
// replace the free ones, and the impulse that took, m_p (v_held - v_free), is booked for
// reaction() (eq R1 there).
template <int D>
inline void ExplicitSolver<D>::hold_motion(std::size_t i, Vec<D>& v) {
  if (!m_.motion[m_.particles.body_p[i]].any) return;
  const Vec<D> free = v;
  impose_motion(i, v);
  held_impulse_[i] = m_.particles.m_p[i] * (v - free);
}

template <int D>
inline void ExplicitSolver<D>::hold_motion(std::size_t i, Vec<D>& v, Mat<D>& C) {
  if (!m_.motion[m_.particles.body_p[i]].any) return;
  const Vec<D> free = v;
  impose_motion(i, v, C);
  held_impulse_[i] = m_.particles.m_p[i] * (v - free);
}

// The force that held body b to its prescribed motion in the latest step:
//   R_b = sum_{p in b} m_p (v_p^held - v_p^free) / dt                                          (R1)
// with v^free the velocity the grid gave the particle (FLIP, PIC blend or APIC). It is the
// reaction of the machine that drives the body: by the momentum balance of the whole model,
// minus the force the rest of the model (soil, gravity) puts on the body, plus the body's own
// m dv/dt (0 at constant velocity). Summed in storage order, one thread: the same bits on any
// thread count.
template <int D>
Vec<D> ExplicitSolver<D>::reaction(int body) const {
  Vec<D> r = Vec<D>::Zero();
  if (!stepped_ || held_impulse_.empty() || !(step_dt_ > 0.0)) r.setConstant(std::numeric_limits<double>::quiet_NaN());
  else
    for (std::size_t i = 0; i < held_impulse_.size(); ++i)
      if (m_.particles.body_p[i] == body) r += held_impulse_[i];
  return r / step_dt_;
}

// Eqs (5)-(6) with the interpolated v^L; a prescribed component moves the particle at exactly the
// prescribed velocity, so a loading platen travels as specified whatever the soil beneath it does.
template <int D>
inline void ExplicitSolver<D>::move_particle(std::size_t i, double dt, Vec<D> vL) {
  auto& p = m_.particles;
  impose_motion(i, vL);
  p.x_p[i] += dt * vL;
  p.u_p[i] += dt * vL;
  const auto& x = p.x_p[i];
  const Vec<D> hi = m_.grid.upper();
  bool inside = true;
  for (int d = 0; d < D; ++d) inside = inside && x[d] >= m_.grid.origin[d] && x[d] <= hi[d];
  if (!inside) note_fault(escaped_, i);
  // A GIMP domain across a free face is held there as by a wall (model/free_faces.hpp). The
  // step's bounds (watch_free_faces) let the particles far from any free face skip the full test.
  else {
    const Vec<D>& l = p.l_p[i];
    bool beyond = false;
    for (int d = 0; d < D; ++d) beyond = beyond || x[d] - l[d] < domain_lo_[d] || x[d] + l[d] > domain_hi_[d];
    if (beyond && free_face_reached(m_, i, free_face_slack(m_)) >= 0) note_fault(escaped_, i);
  }
}

// Where a particle's domain may reach in this step before free_face_reached must look at it: the
// free faces less its slack; no bound at a held face, nor with the linear kernel (no domain).
template <int D>
void ExplicitSolver<D>::watch_free_faces() {
  const double inf = std::numeric_limits<double>::infinity(), slack = free_face_slack(m_);
  const Vec<D> hi = m_.grid.upper();
  const bool gimp = m_.step.kernel != ShapeKind::Linear;
  for (int d = 0; d < D; ++d) {
    domain_lo_[d] = gimp && m_.step.free_face[d][0] ? m_.grid.origin[d] - slack : -inf;
    domain_hi_[d] = gimp && m_.step.free_face[d][1] ? hi[d] + slack : inf;
  }
}


// Several threads may find a fault in one step; the lowest particle index is reported, so the
// message does not depend on the number of threads.
template <int D>
void ExplicitSolver<D>::note_fault(std::int64_t& slot, std::size_t i) {
  const auto idx = static_cast<std::int64_t>(i);
#pragma omp critical(tsuchi_fault)
  if (slot < 0 || idx < slot) slot = idx;
}

// The unbalanced-force ratio of FLAC (Itasca, FLAC3D manual, command "zone ratio", keyword
// maximum; "model solve ratio-maximum"): the largest unbalanced force magnitude over the grid
// points divided by the average applied force magnitude over the grid points,
//   R = max_i |f_i^unb| / ((1/N) sum_i |f_i^app|),
// over the N nodes of the latest step's solve with m_i above solver.node_mass_floor, where
//   f_i^unb = f_i = f_i^ext + f_i^int on the free components (a fixed component is balanced by
//             its reaction: set to 0), the net nodal force of eq (4) before the local damping
//             force is added (with Cundall damping f + f_damp is not the out-of-balance force: the
//             damping force is a numerical device that vanishes with f). A component held by a
//             body (bodies.prescribed_velocity) at a node where one of the body's particles has
//             weight counts as fixed too: the held particles' velocity is reset every step
//             whatever the node's force, so the force there in that component is the reaction of
//             the held motion, as at a FLAC grid point given a fixed velocity (FLAC3D's own advice
//             for a stiff loading platen), not an imbalance that damping could remove;
//   |f_i^app| = (|f_i^ext| + |f_i^int|) / 2, f_i^ext = m_i b (gravity, the only external nodal
//             load), f_i^int = f_i - m_i b, all components. FLAC describes its applied force only
//             as a measure of the total force applied to the grid point; half the sum of the force
//             magnitudes is tsuchi's reading, with the gravity load and the net stress divergence
//             as the two forces (FLAC's zones each add their own force to a grid point; the sum
//             over particles here is taken before the magnitude). At equilibrium
//             |f^int| = |f^ext| and |f^app| is the nodal weight; with gravity just switched on
//             (f^int = 0) it is half of it and R is of order 1 (about 2 max_i m_i / mean_i m_i);
//             under boundary loading alone (b = 0) it is half the net internal force, which at
//             rest is left only where a reaction balances it.
// FLAC3D also offers ratio-average (mean unbalanced over mean applied: its default) and
// ratio-local (the largest of the per-point ratios); R here is the strictest of the two global ones.
// For USF the force is that of the step's updated stress, for USL and MUSL that of the stress at
// the start of the step. R = 0 when no node carries a force (nothing loaded: balanced); NaN before
// the first step of the process (no solve yet: after a restart, until the next step).
// The per-tile partial results are combined in tile order (deterministic for every thread count),
// then across processes through core/reduction.hpp.
template <int D>
double ExplicitSolver<D>::unbalanced_force_ratio() const {
  if (!stepped_) return std::numeric_limits<double>::quiet_NaN();
  if (ratio_step_ == steps_) return ratio_;
  const auto& n = m_.grid.field(0);
  const auto& fixed = m_.grid.fixed_g;
  const auto& tiles = schedule_.active_tiles();
  const double floor = m_.step.node_mass_floor;
  const Vec<D> b = gravity_;
  const bool held = drives_bodies();
  if (held) {
    switch (m_.step.kernel) {
      case ShapeKind::Linear: mark_driven_nodes<shape::LinearKernel>(); break;
      case ShapeKind::UGimp:
      case ShapeKind::Gimp: mark_driven_nodes<shape::GimpKernel>(); break;
    }
  }
  constexpr std::int64_t nodes = Grid<D>::kTileNodes;
  const auto nt = static_cast<std::int64_t>(tiles.size());
  tile_sums_.resize(tiles.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t t = 0; t < nt; ++t) {
    double largest = 0.0, sum = 0.0, count = 0.0;
    const std::int64_t first = tiles[static_cast<std::size_t>(t)] * nodes;
    for (std::int64_t k = first; k < first + nodes; ++k) {
      if (!(n.m[k] > floor)) continue;
      Vec<D> unbalanced = n.f[k];
      const unsigned balanced = held ? fixed[k] | driven_[k] : fixed[k];
      for (int d = 0; d < D; ++d)
        if (balanced & (1u << d)) unbalanced[d] = 0.0;
      const Vec<D> ext = n.m[k] * b;
      largest = std::max(largest, unbalanced.norm());
      sum += 0.5 * (ext.norm() + (n.f[k] - ext).norm());
      count += 1.0;
    }
    tile_sums_[static_cast<std::size_t>(t)] = {largest, sum, count};
  }
  double largest = 0.0, sum = 0.0, count = 0.0;
  for (const auto& [l, s, c] : tile_sums_) largest = std::max(largest, l), sum += s, count += c;
  largest = reduce::max(largest), sum = reduce::sum(sum), count = reduce::sum(count);
  ratio_ = sum > 0.0 ? largest / (sum / count) : 0.0;
  ratio_step_ = steps_;
  return ratio_;
}

// driven_ on the active nodes: bit d set where a particle of a body holding component d has a
// nonzero weight. At the particles' positions after the step (the solve used those before it): a
// node that enters or leaves a held particle's support in one step has a weight near zero from it,
// as GIMP and linear weights vanish continuously at the support's edge. One pass over the held
// particles, in particle order (the same for every thread count), on the first ratio of a step only.
// With local damping, also at the start of every step (the positions the solve uses), where the
// marks exempt the held components from the damping force.
template <int D>
template <class Kernel>
void ExplicitSolver<D>::mark_driven_nodes() const {
  const auto& g = m_.grid;
  const auto& p = m_.particles;
  const std::size_t size = g.fixed_g.size();
  driven_.resize(size * static_cast<std::size_t>(last_field_ + 1));
  for (int f = 0; f <= last_field_; ++f)
    schedule_.for_active_nodes([&](std::int64_t k) { driven_[static_cast<std::size_t>(f) * size + static_cast<std::size_t>(k)] = 0; });
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& motion = m_.motion[static_cast<std::size_t>(p.body_p[i])];
    if (!motion.any) continue;
    std::uint8_t mask = 0;
    for (int d = 0; d < D; ++d)
      if (motion.prescribed[d]) mask = static_cast<std::uint8_t>(mask | (1u << d));
    Stencil<D, Kernel> st;
    st.compute(g, p.x_p[i], p.l_p[i]);
    const std::size_t o = static_cast<std::size_t>(field_of(i)) * size;
    st.scatter([](double T, const std::array<double, D - 1>&) { return T; },
               [&](std::int64_t k, double w, double, double T) {
                 if (w * T > 0.0) {
                   driven_[static_cast<std::size_t>(k)] |= mask;
                   driven_[o + static_cast<std::size_t>(k)] |= mask;
                 }
               });
  }
}

// f(k, kind) for every node where contact acted in the latest step, serially in storage order.
template <int D>
template <class F>
void ExplicitSolver<D>::for_each_contact_node(F&& f) const {
  if (!contact_on() || !stepped_) return;
  const auto& acted = contact_.acted();
  constexpr std::int64_t nodes = Grid<D>::kTileNodes;
  for (const std::int32_t t : schedule_.active_tiles())
    for (std::int64_t k = t * nodes; k < (t + 1) * nodes; ++k)
      if (const unsigned kind = acted[static_cast<std::size_t>(k)] & 3u) f(k, static_cast<int>(kind));
}

template <int D>
std::vector<typename ExplicitSolver<D>::ContactNode> ExplicitSolver<D>::contact_nodes() const {
  std::vector<ContactNode> r;
  const auto& g = m_.grid;
  for_each_contact_node([&](std::int64_t k, int kind) {
    r.push_back({g.position(g.ijk(k)), contact_.normal()[static_cast<std::size_t>(k)],
                 contact_.force()[static_cast<std::size_t>(k)] / step_dt_, kind});
  });
  return r;
}

template <int D>
std::int64_t ExplicitSolver<D>::contact_node_count() const {
  if (!contact_on()) return -1;
  std::int64_t n = 0;
  for_each_contact_node([&](std::int64_t, int) { ++n; });
  return static_cast<std::int64_t>(reduce::sum(static_cast<double>(n)));
}

template <int D>
std::string ExplicitSolver<D>::describe_particle(std::size_t i) const {
  const auto& p = m_.particles;
  std::string pos;
  for (int d = 0; d < D; ++d) pos += fmt::format("{}{:.6g}", d ? ", " : "", p.x_p[i][d]);
  return fmt::format("particle {} of body \"{}\" at ({})", p.id_p[i], m_.body_names[static_cast<std::size_t>(p.body_p[i])], pos);
}

// A step with a fault is thrown away whole; the first kind found (in this order) is reported.
template <int D>
void ExplicitSolver<D>::report_faults() const {
  const std::string when = fmt::format("step {} (t = {:.6g} s)", steps_ + 1, time_);
  const std::int64_t nonfinite = reduce::first(nonfinite_), inverted = reduce::first(inverted_),
                     escaped = reduce::first(escaped_);
  if (nonfinite >= 0)
    throw RunError(fmt::format("{}: {} got a non-finite stress, velocity or volume; the run is unstable there: "
                               "reduce time.courant, add solver.damping, or check the material parameters",
                               when, describe_particle(static_cast<std::size_t>(nonfinite))),
                   Fault::NonFinite);
  if (inverted >= 0)
    throw RunError(fmt::format("{}: {} was compressed to zero or negative volume in one step; reduce the time "
                               "step (time.courant) or the loading speed",
                               when, describe_particle(static_cast<std::size_t>(inverted))),
                   Fault::VolumeCollapse);
  if (escaped >= 0) {
    const auto i = static_cast<std::size_t>(escaped);
    const int face = m_.step.kernel != ShapeKind::Linear ? free_face_reached(m_, i, free_face_slack(m_)) : -1;
    if (face >= 0) {
      const int d = face / 2;
      const std::string name = face_name(face);
      throw RunError(fmt::format("{}: {} left the grid across the free face {}: its GIMP domain (half-width "
                                 "{:.4g} m) reaches past the last row of nodes, and a free face holds nothing; "
                                 "give the face a condition ([boundary] {} = \"fixed\" or \"roller\") if the "
                                 "body rests on it, or enlarge grid.extent",
                                 when, describe_particle(i), name, m_.particles.l_p[i][d], name),
                     Fault::LeftGrid);
    }
    throw RunError(fmt::format("{}: {} left the grid; enlarge grid.extent or fix the boundary it crossed", when,
                               describe_particle(i)),
                   Fault::LeftGrid);
  }
}

template class ExplicitSolver<2>;
template class ExplicitSolver<3>;

}  // namespace tsuchi
