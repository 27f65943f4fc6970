#pragma once
// Recorders: one number per row of recorders.csv, a reduction (mean, sum, min, max) of one
// per-particle quantity (model/particle_fields.hpp) over a particle set chosen once, at the
// start, by body and by a box of initial positions. What a lab measures (a platen's displacement,
// the mean stress on a boundary row) is written as recorders in the input file rather than coded
// per case.
#include "tsuchi/model/config.hpp"
#include "tsuchi/model/model.hpp"
#include "tsuchi/model/particle_fields.hpp"
#include "tsuchi/solver/explicit_step.hpp"

#include <string>
#include <vector>

namespace tsuchi {

template <int D>
class Recorder {
 public:
  // Throws InputError (naming `index`, its place in the input's recorders) when the set is empty.
  Recorder(const RecorderConfig& config, std::size_t index, const Model<D>& model);

  double value(const Particles<D>& p) const;  // scale * reduction + offset (a particle quantity)
  // scale * quantity + offset, for every kind: a particle quantity of the solver's particles, the
  // whole-model unbalanced_force_ratio or a body's reaction of its latest step (NaN before the
  // first step).
  double value(const ExplicitSolver<D>& solver) const;
  bool from_solver() const { return c_.from_solver(); }
  const RecorderConfig& config() const { return c_; }
  std::size_t size() const { return count_; }
  // At the start of a stage: the supports and walls the stage's boundary gives (a reaction's
  // nodes), and the particle set found again among the particles the stage removed or added.
  void rebind(const Model<D>& model);
  // Non-empty when the value has crossed its stop bound: says which and where.
  std::string stop_reason(double value) const;

 private:
  RecorderConfig c_;
  std::size_t index_in_input_ = 0;
  const ParticleField* field_ = nullptr;
  int component_ = 0;
  // Membership by particle id, not storage index: particles are reordered during a run (and a
  // restart brings them back in the saved order), while ids stay with their particles. The ids
  // themselves, sorted: 8 bytes per member, where a flag per id of the model cost id_count bytes
  // per recorder (1e5 probes on 1e6 particles: 100 GB).
  std::vector<std::int64_t> members_;
  // A support reaction's nodes: positions in Model::held_nodes of the face's or node set's nodes.
  std::vector<std::size_t> held_;
  int wall_ = -1;  // reaction of a frictional face: its index in Model::contact.walls
  std::size_t count_ = 0;
  // Storage indices of the set and their ids, found again whenever the particles were reordered
  // (a check of count_ ids per evaluation, a pass over all particles only after a reordering).
  mutable std::vector<std::size_t> index_;
  mutable std::vector<std::int64_t> index_id_;
  mutable std::size_t scanned_size_ = static_cast<std::size_t>(-1);  // particle count at the last scan
  const std::vector<std::size_t>& indices(const Particles<D>& p) const;
};

// The recorders of an input, each with its particle set chosen on the model's initial state.
template <int D>
std::vector<Recorder<D>> make_recorders(const Config& config, const Model<D>& model);

extern template class Recorder<2>;
extern template class Recorder<3>;
extern template std::vector<Recorder<2>> make_recorders<2>(const Config&, const Model<2>&);
extern template std::vector<Recorder<3>> make_recorders<3>(const Config&, const Model<3>&);

}  // namespace tsuchi
