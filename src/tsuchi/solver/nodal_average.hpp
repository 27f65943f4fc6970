#pragma once
// A volume-weighted average of a particle quantity q through the grid nodes, per body field and
// per material:
//   Q_i = sum_p S_ip V_p q_p / sum_p S_ip V_p,          q_bar_p = sum_i S_ip Q_i / sum_i S_ip [i],
// the sums over the particles of p's field and material, where [i] is 1 at the nodes where Q_i is
// defined. Per material because an average across an interface mixes materials of any stiffness:
// a stiff body bonded to soil (a cap, a footing, a wall) would take the soil's volume change, and
// with a modulus 1e5 times the soil's a 3D slab ran away within 13 steps; as in a B-bar element,
// which never spans two materials, each material's volume change is averaged over itself. Only
// the materials that take the average have sums. The second normalisation matters beyond the
// grid's edge, where a GIMP stencil loses weight and sum S_ip < 1 would scale q_bar down. The
// anti-locking remedies take it for the volumetric strain increment (eq V3) and, with "bbar", for
// the pressure in the internal force (eq V5), both in solver/explicit_step.cpp.
#include "tsuchi/grid/block_schedule.hpp"
#include "tsuchi/shape/stencil.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace tsuchi {

// A node's pair (sum of S V q, sum of S V), and after finish() (Q_i, [i]); also a gather's running
// sums of w Q_i and w [i]. One pair per node: a scatter or gather touches one cache line per node,
// and both entries take one vector operation.
using NodalAveragePair = Eigen::Vector2d;

template <int D>
class NodalAverage {
 public:
  // Zeroes the sums of body fields first..last on the active nodes of a grid of `grid_size` nodes,
  // for the materials m < `materials` with averaged(m) true (the others take no part).
  template <class Averaged>
  void begin(const BlockSchedule<D>& schedule, std::size_t grid_size, int first, int last, std::size_t materials,
             Averaged&& averaged) {
    size_ = grid_size;
    slot_.assign(materials, 0);
    slots_ = 0;
    for (std::size_t mat = 0; mat < materials; ++mat)
      if (averaged(mat)) slot_[mat] = slots_++;
    const std::size_t slots = size_ * static_cast<std::size_t>(last + 1) * slots_;
    sum_.resize(slots);
    first_ = first;
    last_ = last;
    for_fields(schedule, [](NodalAveragePair& a) { a.setZero(); });
  }

  // Particle p's share, V_p q_p (Vq, formed by the caller) and V_p, spread by its stencil; called
  // inside a coloured scatter, so no two threads add to one node at once.
  template <class Kernel>
  [[gnu::always_inline]] inline void add(const Stencil<D, Kernel>& st, int field, int material, double V, double Vq) {
    NodalAveragePair* const a_g = sum_.data() + offset(field, material);
    const NodalAveragePair share(Vq, V);
    st.scatter([&](double T, const std::array<double, D - 1>&) { return T; },
               [&](std::int64_t k, double w, double, double T) { a_g[k] += (w * T) * share; });
  }

  // Q_i once per node, and the weight becomes [i]: the gathers then need no division or test per
  // node.
  void finish(const BlockSchedule<D>& schedule) {
    for_fields(schedule, [](NodalAveragePair& a) {
      if (a[1] > 0.0) a[0] /= a[1], a[1] = 1.0;
      else a.setZero();
    });
  }

  // q_bar_p of the particle with stencil st in body field `field`, of material `material`.
  template <class Kernel>
  [[gnu::always_inline]] inline double gather(const Stencil<D, Kernel>& st, int field, int material) const {
    const NodalAveragePair* const a_g = sum_.data() + offset(field, material);
    NodalAveragePair total = NodalAveragePair::Zero();
    st.gather(
        NodalAveragePair::Zero().eval(),
        [&](NodalAveragePair& row, std::int64_t k, double w, double) { row += w * a_g[k]; },
        [&](const NodalAveragePair& row, double T, const std::array<double, D - 1>&) { total += T * row; });
    return total[1] > 0.0 ? total[0] / total[1] : 0.0;
  }

 private:
  // Only for a material that takes the average (averaged[material] set in begin).
  std::size_t offset(int field, int material) const {
    return slot_offset(field, slot_[static_cast<std::size_t>(material)]);
  }
  std::size_t slot_offset(int field, std::size_t slot) const {
    return (static_cast<std::size_t>(field) * slots_ + slot) * size_;
  }
  // Every field's and slot's sums at the active nodes, in one parallel region (a region per slot
  // cost a fork and a join each, two per step per material).
  template <class F> void for_fields(const BlockSchedule<D>& schedule, F&& f) {
    if (slots_ == 0) return;
    const std::size_t first = slot_offset(first_, 0), count = static_cast<std::size_t>(last_ - first_ + 1) * slots_;
    schedule.for_active_nodes([&](std::int64_t k) {
      for (std::size_t j = 0; j < count; ++j) f(sum_[first + j * size_ + static_cast<std::size_t>(k)]);
    });
  }

  std::vector<NodalAveragePair> sum_;  // per field, slot and node
  std::vector<std::size_t> slot_;  // material -> its sums' slot; meaningful where averaged
  std::size_t size_ = 0, slots_ = 0;
  int first_ = 0, last_ = 0;
};

}  // namespace tsuchi
