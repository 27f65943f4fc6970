#pragma once
// Recorders: one number per row of recorders.csv, a reduction (mean, sum, min, max) of one
// per-particle quantity over a particle set chosen once, at the start, by body and by a box of
// initial positions. What a lab measures (a platen's displacement, the mean stress on a boundary
// row) is written as recorders in the input file rather than coded per case.
#include "tsuchi/model/model.hpp"

#include <string>
#include <vector>

namespace tsuchi {

// The per-particle quantity names a recorder accepts, for messages and docs.
const std::vector<std::string>& recorder_quantities(int dimension);
bool is_recorder_quantity(const std::string& name, int dimension);

template <int D>
class Recorder {
 public:
  Recorder(const RecorderConfig& config, const Model<D>& model);

  double value(const Particles<D>& p) const;  // scale * reduction + offset
  const RecorderConfig& config() const { return c_; }
  std::size_t size() const { return count_; }
  // Non-empty when the value has crossed its stop bound: says which and where.
  std::string stop_reason(double value) const;

 private:
  double particle_value(const Particles<D>& p, std::size_t i) const;

  RecorderConfig c_;
  // Membership by particle id, not storage index: particles are reordered during a run (and a
  // restart brings them back in the saved order), while ids stay with their particles.
  std::vector<std::uint8_t> member_;
  std::size_t count_ = 0;
  // Storage indices of the set and their ids, found again whenever the particles were reordered
  // (a check of count_ ids per evaluation, a pass over all particles only after a reordering).
  mutable std::vector<std::size_t> index_;
  mutable std::vector<std::int32_t> index_id_;
  const std::vector<std::size_t>& indices(const Particles<D>& p) const;
  int kind_ = 0, component_ = 0;
};

extern template class Recorder<2>;
extern template class Recorder<3>;

}  // namespace tsuchi
