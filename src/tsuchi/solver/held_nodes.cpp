#include "tsuchi/solver/held_nodes.hpp"

#include "tsuchi/core/reduction.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tsuchi {

namespace {

// A node the solve takes: on an active tile and heavier than the mass floor.
template <int D>
bool has_mass(const Model<D>& m, const BlockSchedule<D>& schedule, const NodalField<D>& n, std::int64_t k) {
  return schedule.on_active_tile(k) && n.m[static_cast<std::size_t>(k)] > m.step.node_mass_floor;
}

}  // namespace

template <int D>
bool HeldNodes<D>::drives(const Model<D>& m) const {
  return std::any_of(m.node_sets.begin(), m.node_sets.end(), [](const NodeSet<D>& s) { return !s.driven_nodes.empty(); });
}

double FunctionIntegral::operator()(double t) {
  // Exact: a constant acceleration gives a0 t at every step's end (from its stage's start).
  if (f_->is_one()) return std::max(0.0, t - f_->start());
  const auto K = static_cast<std::size_t>(std::max(0.0, std::floor(t / kChunk)));
  while (at_.size() <= K) {
    const double a = static_cast<double>(at_.size() - 1) * kChunk;
    at_.push_back(at_.back() + f_->integral(a, a + kChunk));
  }
  return at_[K] + f_->integral(static_cast<double>(K) * kChunk, t);
}

template <int D>
void HeldNodes<D>::begin_step(const Model<D>& m, double t, double dt) {
  dt_ = dt;
  const std::size_t sets = m.node_sets.size();
  start_.assign(sets, Vec<D>::Zero());
  end_.assign(sets, Vec<D>::Zero());
  if (integral_.size() != sets) {
    integral_.clear();
    for (const auto& set : m.node_sets) integral_.emplace_back(&set.f);
  }
  for (std::size_t s = 0; s < sets; ++s) {
    const auto& set = m.node_sets[s];
    if (set.driven_nodes.empty()) continue;
    const bool integrate = set.drive == NodeSetConfig::Drive::Acceleration;
    start_[s] = set.velocity(t, integrate ? integral_[s](t) : 0.0);
    end_[s] = set.velocity(t + dt, integrate ? integral_[s](t + dt) : 0.0);
  }
}

template <int D>
void HeldNodes<D>::book(const Model<D>& m, const BlockSchedule<D>& schedule, const NodalField<D>& n) {
  const auto& held = m.held_nodes;
  free_.resize(held.size());
  live_.resize(held.size());
  const auto nh = static_cast<std::int64_t>(held.size());
  const double dt = dt_;
#pragma omp parallel for schedule(static)
  for (std::int64_t j = 0; j < nh; ++j) {
    const std::int64_t k = held[static_cast<std::size_t>(j)];
    const bool live = has_mass(m, schedule, n, k);
    live_[static_cast<std::size_t>(j)] = live;
    free_[static_cast<std::size_t>(j)] = live ? Vec<D>(n.p[k] + dt * n.f[k]) : Vec<D>::Zero();
  }
  booked_ = true;
}

template <int D>
void HeldNodes<D>::set_velocity(const Model<D>& m, const BlockSchedule<D>& schedule, NodalField<D>& n, At at) const {
  for (std::size_t s = 0; s < m.node_sets.size(); ++s) {
    const auto& set = m.node_sets[s];
    const Vec<D>& v = at == At::Start ? start_[s] : end_[s];
    for (std::size_t j = 0; j < set.driven_nodes.size(); ++j) {
      const std::int64_t k = set.driven_nodes[j];
      if (!schedule.on_active_tile(k)) continue;
      for (int d = 0; d < D; ++d)
        if (set.driven_mask[j] & (1u << d)) n.v[k][d] = v[d];
    }
  }
}

template <int D>
void HeldNodes<D>::set_solve(const Model<D>& m, const BlockSchedule<D>& schedule, NodalField<D>& n) const {
  for (std::size_t s = 0; s < m.node_sets.size(); ++s) {
    const auto& set = m.node_sets[s];
    const Vec<D>& v0 = start_[s];
    const Vec<D>& v1 = end_[s];
    for (std::size_t j = 0; j < set.driven_nodes.size(); ++j) {
      const std::int64_t k = set.driven_nodes[j];
      if (!schedule.on_active_tile(k)) continue;
      for (int d = 0; d < D; ++d)
        if (set.driven_mask[j] & (1u << d)) {
          n.v[k][d] = v0[d];
          if (m.grid.keep_acceleration) n.a[k][d] = (v1[d] - v0[d]) / dt_;
          n.vL[k][d] = v1[d];
        }
    }
  }
}

// The force the supports exert on the material at a set of held nodes, over the held components:
//   R = sum_i (m_i v_i^held - (p_i + f_i dt)) / dt                                             (R2)
// with p_i + f_i dt the momentum node i would have at the end of the step if its held components
// were free (eq 4 without the damping force, which a held component does not take), and
// v^held = v^L of the solve on those components (0, or the driven v(t_n+1)): the impulse the
// supports gave the material in the step, per unit time, as eq (R1) is for a prescribed body.
// For a block at rest on a fixed base under gravity it is +weight along up. Summed serially in
// the order of `held` (the same bits on any thread count), then over processes.
template <int D>
Vec<D> HeldNodes<D>::reaction(const Model<D>& m, const NodalField<D>& n, const std::vector<std::size_t>& held) const {
  Vec<D> r = Vec<D>::Zero();
  if (!booked_ || !(dt_ > 0.0)) {
    r.setConstant(std::numeric_limits<double>::quiet_NaN());
    return r;
  }
  for (const std::size_t j : held) {
    if (!live_[j]) continue;
    const std::int64_t k = m.held_nodes[j];
    const unsigned mask = m.grid.fixed_g[static_cast<std::size_t>(k)];
    for (int d = 0; d < D; ++d)
      if (mask & (1u << d)) r[d] += n.m[k] * n.vL[k][d] - free_[j][d];
  }
  for (int d = 0; d < D; ++d) r[d] = reduce::sum(r[d]);
  return r / dt_;
}

template class HeldNodes<2>;
template class HeldNodes<3>;

}  // namespace tsuchi
