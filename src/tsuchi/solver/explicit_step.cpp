#include "tsuchi/solver/explicit_step.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/core/reduction.hpp"
#include "tsuchi/shape/gimp.hpp"
#include "tsuchi/shape/linear.hpp"
#include "tsuchi/shape/stencil.hpp"
#include "tsuchi/solver/damping.hpp"
#include "tsuchi/solver/jaumann.hpp"
#include "tsuchi/solver/particle_domain.hpp"
#include "tsuchi/model/material_state.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <type_traits>

namespace tsuchi {

template <int D>
void ExplicitSolver<D>::step(double dt) {
  switch (m_.step.kernel) {
    case ShapeKind::Linear: step_with<shape::LinearKernel>(dt); break;
    case ShapeKind::UGimp:
    case ShapeKind::Gimp: step_with<shape::GimpKernel>(dt); break;
  }
  time_ += dt;
  ++steps_;
}

template <int D>
template <class Kernel>
void ExplicitSolver<D>::step_with(double dt) {
  auto& g = m_.grid;
  schedule_.build(g, m_.particles.x_p);  // every stage below uses the start-of-step positions
  const std::int64_t sort = m_.step.sort_interval;
  if (sort > 0 && steps_ > 0 && steps_ % sort == 0) {
    // The order depends on positions only, so every thread count sorts alike, and a restart at
    // the same step sorts alike.
    m_.particles.permute(schedule_.order(), sort_scratch_);
    schedule_.invalidate();
    schedule_.build(g, m_.particles.x_p);
  }
  switch (m_.step.scheme) {
    case Scheme::USF:
      // The GIMP domain update waits until the end of the step: the later stages must use the
      // same weights as the mass p2g, or momentum is not conserved.
      p2g<Kernel, true, false>();
      nodal_velocity();
      update_stress<Kernel, false>(dt, g.v_g);
      p2g<Kernel, false, true>();
      solve_grid(dt);
      g2p<Kernel>(dt, false, true);
      apply_deferred_domain_update();
      break;
    case Scheme::USL:
      p2g<Kernel, true, true>();
      nodal_velocity_and_solve(dt, false);
      g2p<Kernel>(dt, false, false);
      update_stress<Kernel, true>(dt, g.vL_g);
      break;
    case Scheme::MUSL:
      p2g<Kernel, true, true>();
      nodal_velocity_and_solve(dt, true);
      g2p<Kernel>(dt, true, false);
      nodal_velocity();
      update_stress<Kernel, true>(dt, g.v_g);
      break;
  }
  report_faults();
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
// The stages are compile-time flags: the node loop is the hottest loop of the step and should
// carry no test that is the same for every node.
template <int D>
template <class Kernel, bool MassMomentum, bool Force>
void ExplicitSolver<D>::p2g() {
  auto& g = m_.grid;
  const auto& p = m_.particles;
  if constexpr (MassMomentum && Force) zero_nodal(schedule_, g.m_g, g.p_g, g.f_g);
  else if constexpr (MassMomentum) zero_nodal(schedule_, g.m_g, g.p_g);
  else zero_nodal(schedule_, g.f_g);
  const Vec<D> b = m_.step.gravity;
  schedule_.scatter([&](std::size_t i) {
    // Local copies of the array addresses: Eigen's vector stores may alias anything, and would
    // otherwise make the compiler reload every vector's address after each node's update.
    double* const m_g = g.m_g.data();
    Vec<D>* const p_g = g.p_g.data();
    Vec<D>* const f_g = g.f_g.data();
    Stencil<D, Kernel> st;
    st.compute(g, p.x_p[i], p.l_p[i]);
    const double m = p.m_p[i];
    const Mat3 s = to_matrix<D>(Voigt<D>(p.sigma_p[i] - p.sigma0_p[i]));
    // -V sigma, so that the force is S m b + (-V sigma) G with one product per node.
    const Mat<D> minus_V_stress = -p.V_p[i] * s.template topLeftCorner<D, D>();
    const Vec<D> mv = m * p.v_p[i];
    const Vec<D> mb = m * b;
    // Row by row (stencil.hpp): with c_d the columns of -V sigma, node (a, r) gets
    //   f = S mb + sum_d G_d c_d = wx[a] (T mb + sum_{d>0} dT_d c_d) + dwx[a] T c_0.
    for (int r = 0; r < st.R; ++r) {
      const double Tm = st.T[r] * m;
      const Vec<D> Tmv = st.T[r] * mv;
      Vec<D> f_w = st.T[r] * mb;
      for (int d = 1; d < D; ++d) f_w += st.dT[r][d - 1] * minus_V_stress.col(d);
      const Vec<D> f_dw = st.T[r] * minus_V_stress.col(0);
      for (int a = 0; a < st.K; ++a) {
        const auto k = st.offx[a] + st.row[r];
        if constexpr (MassMomentum) {
          m_g[k] += st.wx[a] * Tm;
          p_g[k] += st.wx[a] * Tmv;
        }
        if constexpr (Force) f_g[k] += st.wx[a] * f_w + st.dwx[a] * f_dw;
      }
    }
  });
}

// v_g = p_g / m_g on a node heavier than the floor, then the velocity boundary conditions.
template <int D>
inline Vec<D> ExplicitSolver<D>::velocity_at(std::int64_t k) const {
  const auto& g = m_.grid;
  Vec<D> v = g.m_g[k] > m_.step.node_mass_floor ? Vec<D>(g.p_g[k] / g.m_g[k]) : Vec<D>::Zero();
  for (int d = 0; d < D; ++d)
    if (g.fixed_g[k] & (1u << d)) v[d] = 0.0;
  return v;
}

// Grid momentum balance at a node, eq (4), with local damping and the boundary conditions:
// a_g = (f + f_damp(f, v_g)) / m_g.
template <int D>
inline Vec<D> ExplicitSolver<D>::acceleration_at(std::int64_t k, const Vec<D>& v) const {
  const auto& g = m_.grid;
  Vec<D> a = Vec<D>::Zero();
  if (g.m_g[k] > m_.step.node_mass_floor) {
    for (int d = 0; d < D; ++d) {
      const double f = g.f_g[k][d];
      a[d] = (f + local_damping_force(f, v[d], m_.step.damping)) / g.m_g[k];
      if (g.fixed_g[k] & (1u << d)) a[d] = 0.0;
    }
  }
  return a;
}

template <int D>
void ExplicitSolver<D>::nodal_velocity() {
  auto& g = m_.grid;
  schedule_.for_active_nodes([&](std::int64_t k) { g.v_g[k] = velocity_at(k); });
}

// a_g, and v^L = v_g + dt a_g.
template <int D>
void ExplicitSolver<D>::solve_grid(double dt) {
  auto& g = m_.grid;
  schedule_.for_active_nodes([&](std::int64_t k) {
    g.a_g[k] = acceleration_at(k, g.v_g[k]);
    g.vL_g[k] = g.v_g[k] + dt * g.a_g[k];
  });
}

// nodal_velocity() then solve_grid() in one pass over the nodes, for USL and MUSL, where nothing
// comes between them. With `clear_momentum` p_g is zeroed once read, ready for the remap.
template <int D>
void ExplicitSolver<D>::nodal_velocity_and_solve(double dt, bool clear_momentum) {
  auto& g = m_.grid;
  schedule_.for_active_nodes([&](std::int64_t k) {
    const Vec<D> v = velocity_at(k), a = acceleration_at(k, v);
    g.v_g[k] = v;
    g.a_g[k] = a;
    g.vL_g[k] = v + dt * a;
    if (clear_momentum) g.p_g[k] = Vec<D>::Zero();
  });
}

// Grid to particle, eqs (7)-(8): FLIP v_p += dt sum S a_g, blended with PIC sum S v^L when asked.
// Prescribed components are then set (their acceleration is zero). With `remap` the updated
// particle momenta are projected back to the grid, eq (9) (MUSL), into a p_g cleared by
// nodal_velocity_and_solve(). With `move`, eqs (5)-(6).
template <int D>
template <class Kernel>
void ExplicitSolver<D>::g2p(double dt, bool remap, bool move) {
  auto& g = m_.grid;
  auto& p = m_.particles;
  const double beta = m_.step.pic_fraction;
  const auto particle = [&](std::size_t i) {
    const Vec<D>* const a_g = g.a_g.data();  // local addresses: see p2g
    const Vec<D>* const vL_g = g.vL_g.data();
    Vec<D>* const p_g = g.p_g.data();
    Stencil<D, Kernel> st;
    st.compute(g, p.x_p[i], p.l_p[i]);
    Vec<D> a = Vec<D>::Zero(), vL = Vec<D>::Zero();
    for (int r = 0; r < st.R; ++r) {  // along x first, then the row's weight (stencil.hpp)
      Vec<D> row_a = Vec<D>::Zero(), row_vL = Vec<D>::Zero();
      for (int c = 0; c < st.K; ++c) {
        const auto k = st.offx[c] + st.row[r];
        row_a += st.wx[c] * a_g[k];
        row_vL += st.wx[c] * vL_g[k];
      }
      a += st.T[r] * row_a;
      vL += st.T[r] * row_vL;
    }
    Vec<D> v = p.v_p[i] + dt * a;
    if (beta > 0.0) v = (1.0 - beta) * v + beta * vL;
    impose_motion(i, v);
    if (!v.allFinite()) note_fault(nonfinite_, i);
    p.v_p[i] = v;
    if (remap) {
      const Vec<D> mv = p.m_p[i] * v;
      for (int r = 0; r < st.R; ++r) {
        const Vec<D> Tmv = st.T[r] * mv;
        for (int c = 0; c < st.K; ++c) p_g[st.offx[c] + st.row[r]] += st.wx[c] * Tmv;
      }
    }
    if (move) move_particle(i, dt, vL);
  };
  if (remap) {
    schedule_.scatter(particle);  // the remap writes nodes
  } else {
    const auto np = static_cast<std::int64_t>(p.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < np; ++i) particle(static_cast<std::size_t>(i));
  }
}

// Strain and spin increments from the grid velocity, eq (10); Jaumann rotation (22) and the
// constitutive update (11); volume (12), GIMP domain (14); with Move also positions (5)-(6).
// The material is chosen once per material group, outside the particle loop.
template <int D>
template <class Kernel, bool Move>
void ExplicitSolver<D>::update_stress(double dt, const std::vector<Vec<D>>& v_strain) {
  auto& g = m_.grid;
  auto& p = m_.particles;
  const bool domain_update = m_.step.domain_update();
  const bool defer_domain = !Move;  // USF: the step's later stages still need this step's weights
  if (domain_update && defer_domain) deferred_eps_.resize(p.size());
  const auto& materials = m_.materials;
  // An anisotropic initial stress held by eq (2) turns with the material, as the stress does.
  const bool rotate_sigma0 = m_.rotate_initial_stress;
  // One parallel region for every material group; a thread goes on to the next group without
  // waiting, as the groups hold different particles.
#pragma omp parallel
  for (std::size_t mat = 0; mat < materials.size(); ++mat) {
    std::visit(
        [&](const auto& model) {
          using M = std::decay_t<decltype(model)>;
          const typename M::Context context = model.context();
          const auto state = state_columns<M>(p);
          const auto np = static_cast<std::int64_t>(p.size());
          // Dynamic: yielding points cost several times more than elastic ones, and they gather
          // in the shear bands. Every point's update is its own, so the result does not depend on
          // which thread takes which chunk.
#pragma omp for schedule(dynamic, 128) nowait
          for (std::int64_t ii = 0; ii < np; ++ii) {
            const auto i = static_cast<std::size_t>(ii);
            if (p.material_p[i] != static_cast<std::int32_t>(mat)) continue;
            const Vec<D>* const v_g = v_strain.data();  // local addresses: see p2g
            const Vec<D>* const vL_g = g.vL_g.data();
            Stencil<D, Kernel> st;
            st.compute(g, p.x_p[i], p.l_p[i]);
            // L = sum v G^T, column j = sum v G_j; along x first, then the row factors.
            Mat<D> L = Mat<D>::Zero();
            Vec<D> vL = Vec<D>::Zero();
            for (int r = 0; r < st.R; ++r) {
              Vec<D> row_w = Vec<D>::Zero(), row_dw = Vec<D>::Zero(), row_vL = Vec<D>::Zero();
              for (int a = 0; a < st.K; ++a) {
                const auto k = st.offx[a] + st.row[r];
                row_w += st.wx[a] * v_g[k];
                row_dw += st.dwx[a] * v_g[k];
                if constexpr (Move) row_vL += st.wx[a] * vL_g[k];
              }
              L.col(0) += st.T[r] * row_dw;
              for (int d = 1; d < D; ++d) L.col(d) += st.dT[r][d - 1] * row_w;
              if constexpr (Move) vL += st.T[r] * row_vL;
            }
            const Voigt<D> d_eps = dt * sym_voigt<D>(L);
            const Mat<D> d_omega = 0.5 * dt * (L - L.transpose());
            jaumann_rotate(p.sigma_p[i], d_omega);
            if (rotate_sigma0) jaumann_rotate(p.sigma0_p[i], d_omega);
            model.template update<D>(p.sigma_p[i], d_eps, d_omega, context, StateRef{state.data(), i});
            p.eps_p[i] += d_eps;
            const double J = 1.0 + trace<D>(d_eps);
            if (!p.sigma_p[i].allFinite() || !std::isfinite(J)) note_fault(nonfinite_, i);
            else if (!(J > 0.0)) note_fault(inverted_, i);
            p.V_p[i] *= J;
            if (domain_update) {
              if (defer_domain) deferred_eps_[i] = d_eps;
              else update_particle_domain<D>(p.l_p[i], d_eps, g.h);
            }
            if constexpr (Move) move_particle(i, dt, vL);
          }
        },
        materials[mat].model);
  }
}

// Prescribed components take the prescribed value, evaluated at the start-of-step position.
template <int D>
inline void ExplicitSolver<D>::impose_motion(std::size_t i, Vec<D>& v) const {
  const auto& motion = m_.motion[m_.particles.body_p[i]];
  if (!motion.any) return;
  for (int d = 0; d < D; ++d)
    if (motion.prescribed[d]) v[d] = motion.velocity(d, m_.particles.x_p[i]);
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
}

template <int D>
void ExplicitSolver<D>::apply_deferred_domain_update() {
  if (!m_.step.domain_update()) return;
  auto& p = m_.particles;
  const auto np = static_cast<std::int64_t>(p.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < np; ++i) update_particle_domain<D>(p.l_p[i], deferred_eps_[i], m_.grid.h);
}

// Several threads may find a fault in one step; the lowest particle index is reported, so the
// message does not depend on the number of threads.
template <int D>
void ExplicitSolver<D>::note_fault(std::int64_t& slot, std::size_t i) {
  const auto idx = static_cast<std::int64_t>(i);
#pragma omp critical(tsuchi_fault)
  if (slot < 0 || idx < slot) slot = idx;
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
  if (escaped >= 0)
    throw RunError(fmt::format("{}: {} left the grid; enlarge grid.extent or fix the boundary it crossed", when,
                               describe_particle(static_cast<std::size_t>(escaped))),
                   Fault::LeftGrid);
}

template class ExplicitSolver<2>;
template class ExplicitSolver<3>;

}  // namespace tsuchi
