#pragma once
// The contact stage of the step (model/contact.hpp says who meets whom): where body velocity fields
// meet at a node, or a field reaches a frictional wall, the velocities are corrected so that the
// bodies do not interpenetrate, slide with Coulomb friction and may separate.
//
// Multi-velocity-field contact, Bardenhagen et al. (2000) "The material-point method for granular
// materials", CMAME 187, eqs (29)-(33); Bardenhagen, Guilkey et al. (2001) "An improved contact
// algorithm for the material point method ...", CMES 2. At a node with fields a and b (masses m_a,
// m_b, velocities v_a, v_b) and the unit normal n from a towards b,
//   n = g_a / |g_a| if |g_a| >= |g_b|, else -g_b / |g_b|,   g_a = sum_{p in a} m_p grad S_ip   (C1)
// (g_a points out of body a at its surface; the larger one is taken, as at the corner of a body
// the other's flat face gives the surface; a rigid partner's is always taken),
//   v_cm = (m_a v_a + m_b v_b) / (m_a + m_b),   dv = v_a - v_cm,   dn = dv . n,   t = dv - dn n, (C2)
// and the bodies approach when dn > 0. Field a then takes
//   sticking, mu dn >= |t| (or "rough", or bonded always):  v_a <- v_cm
//   sliding:                                                  v_a <- v_a - dn n - mu dn t / |t|    (C3)
// and field b the opposite momentum change, so momentum is kept at the node to round-off.
// A rigid field (one body with every velocity component prescribed) is a partner of infinite
// mass: v_cm is its prescribed velocity at the node, and the other fields' momentum changes go to
// it, where its particles' held impulse (eq R1 of explicit_step.cpp) turns them into its reaction.
// Where more than two fields meet, each non-rigid field is corrected against the centre of mass of
// all the others (or the rigid one), with the law of the heaviest other field, as NairnMPM does;
// momentum is then kept only approximately at those nodes.
// A frictional wall is a rigid partner at rest whose normal is the face's outward normal.
//
// The correction is applied to the start-of-step velocities before USF's stress update, to the
// updated velocities v^L after the solve (every scheme), and to MUSL's remapped velocities before
// its stress update. The momentum changes of the first two are added to the nodal acceleration as
// (dv_start + dv_solve) / dt, so that a FLIP particle feels the contact force as well as an APIC
// (or PIC) one. Held components (fixed faces, base motion) are never changed.
//
// Contact is detected from velocities alone: two fields meeting at a node with a closing relative
// velocity touch, which with GIMP begins up to about one cell before their particles' domains do.
#include "tsuchi/grid/block_schedule.hpp"
#include "tsuchi/model/model.hpp"

#include <cstdint>
#include <vector>

namespace tsuchi {

template <int D>
class ContactStage {
 public:
  enum class Stage { Start, Solve, Remap };

  // The grid's body fields are first()..last(): field 0 alone without contact between bodies.
  int first(const Model<D>& m) const { return m.contact.between_bodies() ? 1 : 0; }
  int last(const Model<D>& m) const { return m.contact.between_bodies() ? m.contact.fields : 0; }

  // Sizes the per-field arrays and zeroes the mass gradients on the active tiles; `motion_scale`
  // is the factor of each body's prescribed velocity in this step.
  void begin_step(Model<D>& m, const BlockSchedule<D>& schedule, const std::vector<double>& motion_scale);
  // g_f = sum_p m_p grad S_ip of field f (1..fields), eq (C1), for the scatter: out of the body.
  std::vector<Vec<D>>& mass_gradient(int f) { return grad_m_[static_cast<std::size_t>(f - 1)]; }
  // Corrects the velocities of the stage: v (Start, Remap) or v^L with a (Solve).
  void correct(Model<D>& m, const BlockSchedule<D>& schedule, Stage stage, double dt);

  // Per grid slot after the latest step: whether contact acted (bit 0: between bodies, bit 1: a
  // wall), the normal from the lowest field present towards the others and the contact force on
  // that field (N; N/m in 2D). Meaningful on the active tiles of the latest step.
  const std::vector<std::uint8_t>& acted() const { return acted_; }
  const std::vector<Vec<D>>& normal() const { return normal_; }
  const std::vector<Vec<D>>& force() const { return force_; }
  // The force each wall exerted on the material in the latest step (Model::contact.walls order).
  const std::vector<Vec<D>>& wall_force() const { return wall_force_; }

 private:
  void between_fields(Model<D>& m, const BlockSchedule<D>& schedule, Stage stage, double dt);
  void against_walls(Model<D>& m, const BlockSchedule<D>& schedule, Stage stage, double dt);
  Vec<D> rigid_velocity(const Model<D>& m, int body, std::int64_t k) const;

  std::vector<std::vector<Vec<D>>> grad_m_;    // per body field: mass gradient
  std::vector<std::vector<Vec<D>>> dv_start_;  // per body field (or field 0): the Start correction, USF
  std::vector<double> scale_;                  // per body: this step's factor of its prescribed velocity
  std::vector<std::uint8_t> acted_;
  std::vector<Vec<D>> normal_, force_;
  std::vector<Vec<D>> wall_force_, wall_impulse_;  // per wall
  bool start_applied_ = false;                   // the Start stage ran this step
};

extern template class ContactStage<2>;
extern template class ContactStage<3>;

}  // namespace tsuchi
