#pragma once
// One explicit MPM step (METHOD.md section 1) as a short list of stages over whole arrays.
// The three schemes differ only in where the stress update sits and which grid velocity it uses:
//   USF : p2g(m, p) -> v_g -> stress(v_g) -> p2g(f) -> solve -> g2p + move
//   USL : p2g(m, p, f) -> v_g -> solve -> g2p -> stress(v^L) + move
//   MUSL: p2g(m, p, f) -> v_g -> solve -> g2p + remap -> v_g -> stress(v_g) + move
// Every stage evaluates S and G at the positions of the start of the step: particles move only in
// the last stage. What a stage does besides its main work is a named compile-time choice (Scatter,
// Momentum, AfterGather, AfterStress below), so the step's body reads as its scheme; the fused
// passes (p2g of mass, momentum and force at once, g2p with the remap, the stress update moving
// the particles) save a sweep over the particles or the nodes.
//
// The velocity transfer is a named compile-time choice of p2g and g2p as well (VelocityTransfer,
// model/config.hpp): FLIP, blended with PIC by pic_fraction, or APIC (Jiang et al. 2015), where each
// particle carries the affine velocity field v_p + C_p (x - x_p).
//
// Without contact between bodies the stages work on nodal field 0 of the grid (nodes()). With it
// (model/contact.hpp) each particle scatters to and gathers from its body's field, 1..fields; the
// node passes run on each of them, the contact stage (solver/contact_stage.hpp) corrects them where
// they meet, and field 0 holds their sum for the support reactions and the unbalanced-force ratio.
#include "tsuchi/model/model.hpp"
#include "tsuchi/grid/block_schedule.hpp"
#include "tsuchi/solver/contact_stage.hpp"
#include "tsuchi/solver/held_nodes.hpp"
#include "tsuchi/solver/load_stage.hpp"
#include "tsuchi/solver/nodal_average.hpp"
#include "tsuchi/shape/gimp.hpp"
#include "tsuchi/shape/linear.hpp"
#include "tsuchi/shape/stencil.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>
#include <string>

namespace tsuchi {

template <int D>
class ExplicitSolver {
 public:
  explicit ExplicitSolver(Model<D>& model) : m_(model) {}

  // Advances by dt. Throws RunError (with the fault kind) if a particle leaves the grid, collapses
  // or gets a non-finite state; the particles then hold the faulty step's result.
  void step(double dt);

  // Continues a run saved at (time, steps), for a restart.
  void resume(double time, std::int64_t steps) { time_ = time, steps_ = steps; }

  double time() const { return time_; }
  std::int64_t steps() const { return steps_; }
  Model<D>& model() { return m_; }
  const Model<D>& model() const { return m_; }
  // FLAC's unbalanced-force ratio of the grid solve of the latest step (explicit_step.cpp gives
  // the definition); NaN before the first step. Computed on the first call after a step, by one
  // pass over the active nodes, which leaves every other result alone.
  double unbalanced_force_ratio() const;
  // The force (N; N/m in 2D) that held body `body` to its prescribed velocity in the latest step,
  // eq (R1) in explicit_step.cpp: pushing a footing down into soil gives a negative y component.
  // Zero for a body without prescribed motion; NaN before the first step of this process.
  Vec<D> reaction(int body) const;
  // The force (N; N/m in 2D) the supports exerted on the material in the latest step at the held
  // nodes `held` (positions in Model::held_nodes: a face's or a node set's), over the components
  // held there, eq (R2) in solver/held_nodes.cpp: a block resting on a fixed base under gravity
  // gives +weight along up. NaN before the first step of this process.
  Vec<D> support_reaction(const std::vector<std::size_t>& held) const {
    if (!stepped_) return Vec<D>::Constant(std::numeric_limits<double>::quiet_NaN());
    return held_nodes_.reaction(m_, m_.grid.field(0), held);
  }
  // Particles whose expansion the latest step held because their stress was released in tension
  // (solver.hold_released_volume; StepSettings::hold_released_volume).
  std::int64_t released_particles() const { return released_; }
  // The contact stage of the latest step: where contact acted, its normals and forces, the walls' forces.
  const ContactStage<D>& contact() const { return contact_; }
  // The particle schedule of the latest step: its threads' parts and their shares (benchmarks).
  const BlockSchedule<D>& schedule() const { return schedule_; }
  // The grid nodes where contact acted in the latest step, in storage order (the same on any
  // thread count): position, the normal from the lowest body field there towards the others (a
  // wall's outward normal at a wall), the contact force on that field (N; N/m in 2D), and what
  // acted (1: bodies, 2: a wall, 3: both). Empty without contact or before the first step.
  struct ContactNode {
    Vec<D> x, normal, force;
    int kind = 0;
  };
  std::vector<ContactNode> contact_nodes() const;
  // Their number; -1 for a model without contact (no column in global.csv).
  std::int64_t contact_node_count() const;
  // "particle ID of body "NAME" at (x, y)", for messages.
  std::string describe_particle(std::size_t i) const;

 private:
  // What a p2g pass scatters: mass and momentum, the force, or all three in one pass.
  enum class Scatter { MassMomentum, Force, All };
  // What nodal_velocity_and_solve() does with the momentum once read: keep it, or clear it for
  // the remap of g2p<AfterGather::Remap>.
  enum class Momentum { Keep, Clear };
  // What g2p does after updating a particle's velocity: nothing more, project the particle's
  // momentum back to the grid (MUSL, eq 9), or move the particle (eqs 5-6).
  enum class AfterGather { None, Remap, Move };
  // What the stress update does after the constitutive update and the GIMP domain update: move
  // the particles, or leave them where they are (USF, which moves them in g2p).
  enum class AfterStress { Stay, Move };

  using Transfer = VelocityTransfer;
  template <class Kernel> void step_with(double dt);
  template <class Kernel, Transfer How> void step_with(double dt);
  NodalField<D>& nodes() { return m_.grid.field(0); }
  // The grid field particle i scatters to and gathers from: its body's (field 0 without contact).
  int field_of(std::size_t i) const { return field_of_body_[static_cast<std::size_t>(m_.particles.body_p[i])]; }
  // Body fields first_field_..last_field_: 0..0 without contact between bodies.
  bool contact_on() const { return m_.contact.active(); }
  template <class Kernel> void compute_stencils();
  // Particle i's stencil from this step's factors (compute_stencils), for the stages.
  template <class Kernel> [[gnu::always_inline]] Stencil<D, Kernel> stencil_of(std::size_t i) {
    Stencil<D, Kernel> st;
    st.assemble(m_.grid, stencils<Kernel>()[i]);
    return st;
  }
  template <class Kernel> std::vector<typename Stencil<D, Kernel>::Axes>& stencils() {
    if constexpr (std::is_same_v<Kernel, shape::GimpKernel>) return gimp_stencils_;
    else return linear_stencils_;
  }
  template <class Kernel> void scatter_mass_gradient();
  // The input's [[loads]] into the nodal force, at the step's stencils (solver/load_stage.hpp).
  template <class Kernel> void apply_loads() {
    loads_.template apply<Kernel>(m_.loads, m_.grid, m_.particles, stencils<Kernel>(), schedule_,
                                  m_.step.node_mass_floor, m_.grid.fields, field_of_body_, first_field_, last_field_);
  }
  template <class F> void for_body_fields(F&& f) {
    for (int k = first_field_; k <= last_field_; ++k) f(k, m_.grid.field(k));
  }
  template <class Kernel, Scatter What, Transfer How> void p2g();
  Vec<D> velocity_at(const NodalField<D>& n, std::int64_t k) const;
  Vec<D> acceleration_at(const NodalField<D>& n, std::int64_t k, const Vec<D>& v, std::size_t driven_offset = 0,
                         bool undamped = false) const;
  void mark_contact_nodes();
  template <class F> void for_each_contact_node(F&& f) const;
  using At = typename HeldNodes<D>::At;
  void nodal_velocity(At driven_at = At::Start);
  void solve_grid(double dt);
  template <Momentum Then> void nodal_velocity_and_solve(double dt);
  template <class Kernel, AfterGather Then, Transfer How> void g2p(double dt);
  template <class Kernel, AfterGather Then> void g2p_flip(double dt);
  template <class Kernel, AfterGather Then> void g2p_affine(double dt);
  template <AfterGather Then, class F> void for_each_gathering_particle(F&& particle);
  // Whether some body has a prescribed velocity component (it holds particles, books impulses).
  bool drives_bodies() const {
    return std::any_of(m_.motion.begin(), m_.motion.end(), [](const BodyMotion<D>& b) { return b.any; });
  }
  using FieldArray = std::vector<Vec<D>> NodalField<D>::*;  // &NodalField::v or &NodalField::vL
  template <class Kernel, AfterStress Then> void update_stress(double dt, FieldArray v_strain);
  template <class Kernel> void average_volumetric_strain(double dt, FieldArray v_strain);
  // Follower pressures through the step (LoadStage::follow), from the velocity gradient the stress
  // update takes: the same nodal velocities v_strain and the step's stencils.
  template <class Kernel> void follow_loads(double dt, FieldArray v_strain);
  template <class Kernel> bool average_pressure();
  // Whether particle i's force takes the averaged pressure (eq V5): its material asks for "bbar"
  // and it is not in a rigid body's field (which takes no remedy, as in update_stress).
  bool takes_averaged_pressure(std::size_t i) const {
    const auto mat = static_cast<std::size_t>(m_.particles.material_p[i]);
    const auto& by_material = m_.step.anti_locking;
    return mat < by_material.size() && by_material[mat] == AntiLocking::Bbar &&
           !rigid_field_[static_cast<std::size_t>(field_of(i))];
  }
  // Inlined: both run for every particle in the innermost stages.
  [[gnu::always_inline]] inline void impose_motion(std::size_t i, Vec<D>& v) const;
  [[gnu::always_inline]] inline void impose_motion(std::size_t i, Vec<D>& v, Mat<D>& C) const;
  [[gnu::always_inline]] inline void hold_motion(std::size_t i, Vec<D>& v);
  [[gnu::always_inline]] inline void hold_motion(std::size_t i, Vec<D>& v, Mat<D>& C);
  [[gnu::always_inline]] inline void move_particle(std::size_t i, double dt, Vec<D> vL);
  void watch_free_faces();
  void update_free_rigid_bodies(double dt);
  void restore_free_rigid_bodies();
  template <class Kernel> void mark_driven_nodes() const;
  void report_faults() const;
  static void note_fault(std::int64_t& slot, std::size_t i);

  Model<D>& m_;
  double time_ = 0.0;
  std::int64_t steps_ = 0;
  std::int64_t escaped_ = -1;   // first particle found outside the grid in this step
  Vec<D> domain_lo_ = Vec<D>::Zero(), domain_hi_ = Vec<D>::Zero();  // watch_free_faces()
  std::int64_t inverted_ = -1;  // first particle whose volume went to zero or below
  std::int64_t nonfinite_ = -1; // first particle with a NaN or Inf stress, velocity or volume
  std::int64_t released_ = 0;  // released_particles()
  double step_dt_ = 0.0;       // length of the latest step
  Vec<D> gravity_ = Vec<D>::Zero();  // gravity of the latest step: StepSettings::gravity times its function
  bool undamped_driven_ = false;  // this step's driven_ marks exempt held components from damping
  HeldNodes<D> held_nodes_;  // driven components of the grid (base motion), support reactions
  std::vector<Vec<D>> held_impulse_;  // per particle of a prescribed body: m (v_held - v_free) of the latest step
  bool stepped_ = false;                     // a step ran in this process: the grid holds its solve
  mutable double ratio_ = 0.0;               // unbalanced_force_ratio() of step ratio_step_
  mutable std::int64_t ratio_step_ = -1;
  mutable std::vector<std::array<double, 3>> tile_sums_;  // per active tile: max, sum, count
  // This step's stencil factors of every particle (compute_stencils), for the kernel in use.
  std::vector<typename Stencil<D, shape::GimpKernel>::Axes> gimp_stencils_;
  std::vector<typename Stencil<D, shape::LinearKernel>::Axes> linear_stencils_;
  NodalAverage<D> volume_strain_average_;  // anti_locking = "node" and "bbar": eq (V3)
  NodalAverage<D> pressure_average_;       // anti_locking = "bbar": the pressures of eq (V5)
  // Per node: bit d set where a held body drives component d; with contact, per body field at
  // offset f * grid size as well (field 0's slot: any body's mark, for the unbalanced-force ratio).
  mutable std::vector<std::uint8_t> driven_;
  BlockSchedule<D> schedule_;           // colour-by-colour scatter order, brought up to date every step
  typename Particles<D>::Scratch sort_scratch_;  // storage for the periodic reordering
  // Loads (solver/load_stage.hpp) and, per body, the factor of its prescribed velocity in this step:
  // the mean of its function over the step (begin_loads()).
  void begin_loads(double dt);
  LoadStage<D> loads_;
  std::vector<double> motion_scale_;
  ContactStage<D> contact_;
  std::vector<int> field_of_body_;       // per body: its grid field (all 0 without contact between bodies)
  int first_field_ = 0, last_field_ = 0;  // the body fields
  std::vector<std::uint8_t> contact_node_;  // per node: contact may act there (mark_contact_nodes)
  std::vector<std::uint8_t> rigid_field_;  // per field: Contact::rigid_body is set (0 for field 0)
};

extern template class ExplicitSolver<2>;
extern template class ExplicitSolver<3>;

}  // namespace tsuchi
