#pragma once
// The held components of the grid nodes beyond the zeroing that the step's node passes do
// (Grid::fixed_g): the driven components of a base motion (model/node_sets.hpp) and the reaction
// of the supports of a face or node set. Work only on the held nodes, never per grid node: a
// model without driven sets pays nothing in the passes over the nodes.
//
// A driven component of a node on an active tile (any node a particle may reach) gets
//   v = v(t_n) at nodal velocity, a = (v(t_n+1) - v(t_n)) / dt and v^L = v(t_n+1) at the solve,
//   v = v(t_n+1) at MUSL's nodal velocity after the remap,                                 (B1)
// so that a FLIP particle on driven nodes takes the base's velocity change and an APIC (or PIC)
// particle its velocity, the base moves exactly as prescribed, and no damping acts on it. Nodes
// lighter than the mass floor are driven too: their velocity is known without their mass, and left
// at 0 they would put a spurious velocity gradient into the particles at the edge of the material
// (1e-8 m/s of vertical velocity in a block translated rigidly, tests/base_motion_test.cpp).
#include "tsuchi/grid/block_schedule.hpp"
#include "tsuchi/model/model.hpp"

#include <cstdint>
#include <vector>

namespace tsuchi {

// F(t) = integral_0^t f of a function of time, for an acceleration history: the sum of the
// integrals over whole chunks [k c, (k+1) c] (c = 1 ms, kept as they are first needed) plus
// the last part, [K c, t]. TimeFunction::integral is exact for a table (so the velocity of a record
// does not depend on how the steps fall) and accurate for a formula over a chunk (fifty pieces of
// 20 us); integral(0, t) in one call would cost a pass over the whole record every step, and for a
// formula spread its fifty pieces over [0, t], missing a pulse shorter than t / 50. F(t) depends
// on t only (each chunk is integrated alone and the sums are added in chunk order), so a restart
// at t continues with the same bits.
class FunctionIntegral {
 public:
  static constexpr double kChunk = 1e-3;  // s
  explicit FunctionIntegral(const TimeFunction* f = nullptr) : f_(f) {}
  double operator()(double t);

 private:
  const TimeFunction* f_;
  std::vector<double> at_{0.0};  // at_[k] = F(k kChunk)
};

template <int D>
class HeldNodes {
 public:
  // When the velocity of a driven component is taken: the start of the step or its end.
  enum class At { Start, End };

  // The driven velocities of the step [t, t + dt], per node set.
  void begin_step(const Model<D>& m, double t, double dt);
  // Before the solve: p + f dt at every held node with mass, the momentum its components would
  // have at the end of the step if free (eq R2 below); after p2g of the force and before the
  // solve clears p (MUSL).
  void book(const Model<D>& m, const BlockSchedule<D>& schedule, const NodalField<D>& n);
  // After a nodal-velocity pass: driven components get v(t_n) (Start) or v(t_n+1) (End), eq (B1).
  void set_velocity(const Model<D>& m, const BlockSchedule<D>& schedule, NodalField<D>& n, At at) const;
  // After the solve pass: v, a and v^L of the driven components, eq (B1).
  void set_solve(const Model<D>& m, const BlockSchedule<D>& schedule, NodalField<D>& n) const;
  // The force the supports exerted on the material at the held nodes `held` (positions in
  // Model::held_nodes) in the latest step, eq (R2); NaN when no step was booked.
  Vec<D> reaction(const Model<D>& m, const NodalField<D>& n, const std::vector<std::size_t>& held) const;
  bool drives(const Model<D>& m) const;

 private:
  double dt_ = 0.0;
  bool booked_ = false;
  std::vector<Vec<D>> start_, end_;    // per node set: v(t_n), v(t_n+1)
  std::vector<FunctionIntegral> integral_;  // per node set: integral_0^t of its function
  std::vector<Vec<D>> free_;           // per held node: p + f dt of the latest step
  std::vector<std::uint8_t> live_;     // per held node: it had mass in the latest step
};

extern template class HeldNodes<2>;
extern template class HeldNodes<3>;

}  // namespace tsuchi
