#pragma once
// A volume-weighted average of a particle quantity q through the grid nodes, per body field:
//   Q_i = sum_p S_ip V_p q_p / sum_p S_ip V_p,          q_bar_p = sum_i S_ip Q_i / sum_i S_ip [i],
// where [i] is 1 at the nodes where Q_i is defined. The second normalisation matters beyond the
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

// A gather's running sums, of w Q_i and of w [i]. At namespace scope: clang 14 cannot instantiate
// a local struct of a lambda in a template.
struct NodalAverageSums {
  double q, w;
};

template <int D>
class NodalAverage {
 public:
  // Zeroes the sums of body fields first..last on the active nodes of a grid of `grid_size` nodes.
  void begin(const BlockSchedule<D>& schedule, std::size_t grid_size, int first, int last) {
    size_ = grid_size;
    const std::size_t slots = size_ * static_cast<std::size_t>(last + 1);
    sum_.resize(slots);
    weight_.resize(slots);
    first_ = first;
    last_ = last;
    for_fields(schedule, [](double& s, double& w) { s = 0.0, w = 0.0; });
  }

  // Particle p's share, V_p q_p (Vq, formed by the caller) and V_p, spread by its stencil; called
  // inside a coloured scatter, so no two threads add to one node at once.
  template <class Kernel>
  [[gnu::always_inline]] inline void add(const Stencil<D, Kernel>& st, int field, double V, double Vq) {
    double* const s_g = sum_.data() + offset(field);
    double* const w_g = weight_.data() + offset(field);
    st.scatter([&](double T, const std::array<double, D - 1>&) { return T; },
               [&](std::int64_t k, double w, double, double T) {
                 s_g[k] += (w * T) * Vq;
                 w_g[k] += (w * T) * V;
               });
  }

  // Q_i once per node, and the weight becomes [i]: the gathers then need no division or test per
  // node.
  void finish(const BlockSchedule<D>& schedule) {
    for_fields(schedule, [](double& s, double& w) {
      if (w > 0.0) s /= w, w = 1.0;
      else s = 0.0, w = 0.0;
    });
  }

  // q_bar_p of the particle with stencil st in body field `field`.
  template <class Kernel>
  [[gnu::always_inline]] inline double gather(const Stencil<D, Kernel>& st, int field) const {
    const double* const s_g = sum_.data() + offset(field);
    const double* const w_g = weight_.data() + offset(field);
    NodalAverageSums total{0.0, 0.0};
    st.gather(
        NodalAverageSums{0.0, 0.0},
        [&](NodalAverageSums& row, std::int64_t k, double w, double) {
          row.q += w * s_g[k];
          row.w += w * w_g[k];
        },
        [&](const NodalAverageSums& row, double T, const std::array<double, D - 1>&) {
          total.q += T * row.q;
          total.w += T * row.w;
        });
    return total.w > 0.0 ? total.q / total.w : 0.0;
  }

 private:
  std::size_t offset(int field) const { return static_cast<std::size_t>(field) * size_; }
  template <class F> void for_fields(const BlockSchedule<D>& schedule, F&& f) {
    for (int field = first_; field <= last_; ++field) {
      const std::size_t o = offset(field);
      schedule.for_active_nodes([&](std::int64_t k) {
        f(sum_[o + static_cast<std::size_t>(k)], weight_[o + static_cast<std::size_t>(k)]);
      });
    }
  }

  std::vector<double> sum_, weight_;
  std::size_t size_ = 0;
  int first_ = 0, last_ = 0;
};

}  // namespace tsuchi
