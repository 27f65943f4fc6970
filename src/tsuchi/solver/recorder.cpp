#include "tsuchi/solver/recorder.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/core/principal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace tsuchi {

namespace {

enum Kind : int {
  Position, Displacement, Velocity,  // vectors: component = axis
  Stress, Strain,                    // tensors: component = Voigt index
  MeanStress, DeviatorStress, MaxShearStrain, PlasticShear, PlasticVolume, Yielded, Volume, Mass, Density
};

constexpr const char* kVectors[] = {"position", "displacement", "velocity"};
constexpr const char* kTensors[] = {"stress", "strain"};
constexpr const char* kScalars[] = {"mean_stress", "deviator_stress", "max_shear_strain", "plastic_shear_strain",
                                    "plastic_volumetric_strain", "yielded", "volume", "mass", "density"};
constexpr const char* kVoigt[] = {"xx", "yy", "zz", "xy", "yz", "xz"};

// (kind, component) of a name, or kind -1.
std::pair<int, int> parse(const std::string& name, int dim) {
  for (int k = 0; k < 3; ++k)
    for (int d = 0; d < dim; ++d)
      if (name == fmt::format("{}_{}", kVectors[k], "xyz"[d])) return {Position + k, d};
  for (int k = 0; k < 2; ++k)
    for (int v = 0; v < (dim == 2 ? 4 : 6); ++v)
      if (name == fmt::format("{}_{}", kTensors[k], kVoigt[v])) return {Stress + k, v};
  for (int k = 0; k < 9; ++k)
    if (name == kScalars[k]) return {MeanStress + k, 0};
  return {-1, 0};
}

}  // namespace

const std::vector<std::string>& recorder_quantities(int dimension) {
  static std::vector<std::string> names[2];
  auto& n = names[dimension == 3];
  if (n.empty()) {
    for (const char* v : kVectors)
      for (int d = 0; d < dimension; ++d) n.push_back(fmt::format("{}_{}", v, "xyz"[d]));
    for (const char* t : kTensors)
      for (int v = 0; v < (dimension == 2 ? 4 : 6); ++v) n.push_back(fmt::format("{}_{}", t, kVoigt[v]));
    for (const char* s : kScalars) n.emplace_back(s);
  }
  return n;
}

bool is_recorder_quantity(const std::string& name, int dimension) { return parse(name, dimension).first >= 0; }

template <int D>
Recorder<D>::Recorder(const RecorderConfig& config, const Model<D>& model) : c_(config) {
  std::tie(kind_, component_) = parse(c_.quantity, D);
  if (kind_ < 0) throw InputError(fmt::format("recorder \"{}\": unknown quantity \"{}\"", c_.name, c_.quantity));
  const auto& p = model.particles;
  member_.assign(p.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (c_.body >= 0 && p.body_p[i] != c_.body) continue;
    const Vec<D> x0 = p.x_p[i] - p.u_p[i];
    bool inside = true;
    for (int d = 0; d < D; ++d) {
      if (c_.min) inside = inside && x0[d] >= (*c_.min)[d];
      if (c_.max) inside = inside && x0[d] <= (*c_.max)[d];
    }
    if (inside) member_[static_cast<std::size_t>(p.id_p[i])] = 1, ++count_;
  }
  if (count_ == 0)
    throw InputError(fmt::format("{}: key 'recorders.{}': recorder \"{}\" selects no particle: no particle of {} starts "
                                 "inside its box; expected a box (min, max) around some initial particle positions",
                                 model.config.source,
                                 std::find_if(model.config.recorders.begin(), model.config.recorders.end(),
                                              [&](const RecorderConfig& r) { return r.name == c_.name; }) -
                                     model.config.recorders.begin(),
                                 c_.name,
                                 c_.body >= 0 ? fmt::format("body \"{}\"", model.config.bodies[c_.body].name)
                                              : std::string("any body")));
}

template <int D>
double Recorder<D>::particle_value(const Particles<D>& p, std::size_t i) const {
  switch (kind_) {
    case Position: return p.x_p[i][component_];
    case Displacement: return p.u_p[i][component_];
    case Velocity: return p.v_p[i][component_];
    case Stress: return p.sigma_p[i][component_];
    case Strain: return p.eps_p[i][component_];
    case MeanStress: return trace<D>(p.sigma_p[i]) / 3.0;
    case DeviatorStress: return von_mises<D>(p.sigma_p[i]);
    case MaxShearStrain: return max_shear_strain<D>(p.eps_p[i]);
    case PlasticShear: return p.plastic_shear_p[i];
    case PlasticVolume: return p.plastic_volume_p[i];
    case Yielded: return p.yield_p[i] != 0 ? 1.0 : 0.0;
    case Volume: return p.V_p[i];
    case Mass: return p.m_p[i];
    case Density: return p.m_p[i] / p.V_p[i];
  }
  return 0.0;
}

template <int D>
const std::vector<std::size_t>& Recorder<D>::indices(const Particles<D>& p) const {
  bool valid = index_.size() == count_;
  for (std::size_t k = 0; valid && k < index_.size(); ++k)
    valid = index_[k] < p.size() && p.id_p[index_[k]] == index_id_[k];
  if (!valid) {
    index_.clear(), index_id_.clear();
    for (std::size_t i = 0; i < p.size(); ++i)
      if (member_[static_cast<std::size_t>(p.id_p[i])]) index_.push_back(i), index_id_.push_back(p.id_p[i]);
  }
  return index_;
}

template <int D>
double Recorder<D>::value(const Particles<D>& p) const {
  const auto& set = indices(p);
  double r = 0.0;
  switch (c_.reduction) {
    case RecorderConfig::Reduction::Mean:
    case RecorderConfig::Reduction::Sum:
      for (auto i : set) r += particle_value(p, i);
      if (c_.reduction == RecorderConfig::Reduction::Mean) r /= static_cast<double>(count_);
      break;
    case RecorderConfig::Reduction::Min:
      r = std::numeric_limits<double>::infinity();
      for (auto i : set) r = std::min(r, particle_value(p, i));
      break;
    case RecorderConfig::Reduction::Max:
      r = -std::numeric_limits<double>::infinity();
      for (auto i : set) r = std::max(r, particle_value(p, i));
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

}  // namespace tsuchi
