#include "tsuchi/run/recorder.hpp"

#include "tsuchi/core/reduction.hpp"

#include "tsuchi/core/errors.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace tsuchi {

namespace {

// The held nodes of a reaction recorder's face or node set, as positions in Model::held_nodes;
// throws InputError when none of them holds the recorded component (a free face, a set that holds
// another component only): its reaction would be 0 whatever happens.
template <int D>
std::vector<std::size_t> support_nodes(const RecorderConfig& c, std::size_t index, const Model<D>& model) {
  const auto& g = model.grid;
  const auto& held = model.held_nodes;
  const int axis = c.reaction_axis();
  std::vector<std::size_t> r;
  bool holds = false;
  const auto take = [&](std::int64_t k) {
    const auto it = std::lower_bound(held.begin(), held.end(), k);
    if (it == held.end() || *it != k) return;
    r.push_back(static_cast<std::size_t>(it - held.begin()));
    holds = holds || ((g.fixed_g[static_cast<std::size_t>(k)] >> axis) & 1u) != 0;
  };
  std::string what;
  if (c.face >= 0) {
    const int d = c.face / 2, side = c.face % 2;
    what = "face " + face_name(c.face);
    for (const std::int64_t k : held)
      if (g.ijk(k)[d] == (side ? g.n_nodes[d] - 1 : 0)) take(k);
  } else {
    const auto& set = model.node_sets[static_cast<std::size_t>(c.node_set)];
    what = fmt::format("node set \"{}\"", set.name);
    for (const std::int64_t k : set.nodes) take(k);
  }
  if (!holds)
    throw InputError(fmt::format("{}: key 'recorders.{}': recorder \"{}\": no node of {} holds the {} component, so "
                                 "its {} is 0; expected a {} whose condition ([boundary], [[boundary.nodes]] fix, "
                                 "velocity or acceleration) holds {}",
                                 c.where.empty() ? model.source : c.where, index, c.name, what, "xyz"[axis], c.quantity,
                                 c.face >= 0 ? "face" : "node set", "xyz"[axis]));
  return r;
}

}  // namespace

template <int D>
Recorder<D>::Recorder(const RecorderConfig& config, std::size_t index, const Model<D>& model)
    : c_(config), index_in_input_(index) {
  rebind(model);
  if (c_.from_solver()) return;  // no particle set
  const auto q = find_recorder_quantity(c_.quantity, D);
  if (!q) throw InputError(fmt::format("recorder \"{}\": unknown quantity \"{}\"", c_.name, c_.quantity));
  field_ = q->first, component_ = q->second;
  // Over the bodies a later stage adds as well (Model::dormant): a recorder may follow a fill.
  members_.clear();
  for (const Particles<D>* set : {&model.particles, &model.dormant}) {
    const auto& p = *set;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (c_.body >= 0 && p.body_p[i] != c_.body) continue;
      const Vec<D> x0 = p.x_p[i] - p.u_p[i];
      bool inside = true;
      for (int d = 0; d < D; ++d) {
        if (c_.min) inside = inside && x0[d] >= (*c_.min)[d];
        if (c_.max) inside = inside && x0[d] <= (*c_.max)[d];
      }
      if (inside) members_.push_back(p.id_p[i]);
    }
  }
  std::sort(members_.begin(), members_.end());
  count_ = members_.size();
  if (reduce::sum(static_cast<double>(count_)) == 0.0)
    throw InputError(fmt::format("{}: key 'recorders.{}': recorder \"{}\" selects no particle: no particle of {} starts "
                                 "inside its box; expected a box (min, max) around some initial particle positions",
                                 c_.where.empty() ? model.source : c_.where, index, c_.name,
                                 c_.body >= 0 ? fmt::format("body \"{}\"", model.body_names[static_cast<std::size_t>(c_.body)])
                                              : std::string("any body")));
}

template <int D>
void Recorder<D>::rebind(const Model<D>& model) {
  // A frictional face is a wall of the contact stage: its reaction is the wall's force.
  wall_ = -1;
  if (c_.face >= 0)
    for (std::size_t w = 0; w < model.contact.walls.size(); ++w)
      if (model.contact.walls[w].face == c_.face) wall_ = static_cast<int>(w);
  held_.clear();
  if (c_.node_set >= 0 && static_cast<std::size_t>(c_.node_set) >= model.node_sets.size())
    throw InputError(fmt::format("{}: key 'recorders.{}': recorder \"{}\" records the reaction of node set {}, which the "
                                 "boundary no longer has (a stage replaced [[boundary.nodes]])",
                                 c_.where.empty() ? model.source : c_.where, index_in_input_, c_.name, c_.node_set + 1));
  if ((c_.face >= 0 && wall_ < 0) || c_.node_set >= 0) held_ = support_nodes<D>(c_, index_in_input_, model);
  scanned_size_ = static_cast<std::size_t>(-1);
}

template <int D>
std::vector<Recorder<D>> make_recorders(const Config& config, const Model<D>& model) {
  std::vector<Recorder<D>> r;
  for (std::size_t k = 0; k < config.recorders.size(); ++k) r.emplace_back(config.recorders[k], k, model);
  return r;
}

template <int D>
const std::vector<std::size_t>& Recorder<D>::indices(const Particles<D>& p) const {
  // Found again after a reordering, and after a stage removed or added particles.
  bool valid = scanned_size_ == p.size();
  for (std::size_t k = 0; valid && k < index_.size(); ++k)
    valid = index_[k] < p.size() && p.id_p[index_[k]] == index_id_[k];
  if (!valid) {
    index_.clear(), index_id_.clear();
    for (std::size_t i = 0; i < p.size(); ++i)
      if (std::binary_search(members_.begin(), members_.end(), p.id_p[i])) index_.push_back(i), index_id_.push_back(p.id_p[i]);
    scanned_size_ = p.size();
  }
  return index_;
}

template <int D>
double Recorder<D>::value(const ExplicitSolver<D>& solver) const {
  if (c_.whole_model()) return c_.scale * solver.unbalanced_force_ratio() + c_.offset;
  if (const int axis = c_.reaction_axis(); axis >= 0) {
    if (wall_ >= 0) {
      const auto& f = solver.contact().wall_force();
      return static_cast<std::size_t>(wall_) < f.size() ? c_.scale * f[static_cast<std::size_t>(wall_)][axis] + c_.offset
                                                         : std::numeric_limits<double>::quiet_NaN();
    }
    const Vec<D> r = c_.body >= 0 ? solver.reaction(c_.body) : solver.support_reaction(held_);
    return c_.scale * r[axis] + c_.offset;
  }
  return value(solver.model().particles);
}

template <int D>
double Recorder<D>::value(const Particles<D>& p) const {
  if (c_.from_solver()) return std::numeric_limits<double>::quiet_NaN();  // needs the solver: value(solver)
  const auto& set = indices(p);
  double r = 0.0;
  switch (c_.reduction) {
    case RecorderConfig::Reduction::Mean:
    case RecorderConfig::Reduction::Sum:
      for (auto i : set) r += field_value(*field_, p, i, component_);
      r = reduce::sum(r);
      // Over the members present (a stage may remove or add some; none: NaN).
      if (c_.reduction == RecorderConfig::Reduction::Mean) r /= reduce::sum(static_cast<double>(set.size()));
      break;
    case RecorderConfig::Reduction::Min:
      r = std::numeric_limits<double>::infinity();
      for (auto i : set) r = std::min(r, field_value(*field_, p, i, component_));
      r = reduce::min(r);
      break;
    case RecorderConfig::Reduction::Max:
      r = -std::numeric_limits<double>::infinity();
      for (auto i : set) r = std::max(r, field_value(*field_, p, i, component_));
      r = reduce::max(r);
      break;
  }
  return c_.scale * r + c_.offset;
}

template <int D>
std::string Recorder<D>::stop_reason(double v) const {
  // Round-off must not cost a step: a platen that reaches its bound exactly at a frame time stops there.
  const auto tol = [](double b) { return 1e-9 * std::max(1.0, std::abs(b)); };
  if (c_.stop_above && v >= *c_.stop_above - tol(*c_.stop_above)) return fmt::format("{} reached {:.6g} (stop_above = {:.6g})", c_.name, v, *c_.stop_above);
  if (c_.stop_below && v <= *c_.stop_below + tol(*c_.stop_below)) return fmt::format("{} reached {:.6g} (stop_below = {:.6g})", c_.name, v, *c_.stop_below);
  return {};
}

template class Recorder<2>;
template class Recorder<3>;
template std::vector<Recorder<2>> make_recorders<2>(const Config&, const Model<2>&);
template std::vector<Recorder<3>> make_recorders<3>(const Config&, const Model<3>&);

}  // namespace tsuchi
