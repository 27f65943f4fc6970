#pragma once
// A named material: density plus one constitutive model. The model is a small value type chosen
// once per material group in the step's loops (std::visit outside the particle loop); only code
// off the hot path (output rows, messages) visits per particle.
//
// A constitutive model M is a type with
//   static constexpr std::string_view name;                 the input's `model = "..."`
//   static constexpr std::array<StateField, N> state_fields; its per-point history (state_field.hpp)
//   struct Context; Context context() const;                 what all its points share in a step
//   template <int D> void update(Voigt<D>& sigma, const Voigt<D>& d_eps, const Mat<D>& d_omega,
//                                const Context&, StateRef state) const;   one step of one point
//   const LinearElastic& stiffness(StateRef) const;         current moduli: time step, energy
//                                     (may return by value; must not write the state)
//   Inadmissible outside(const Eigen::Vector3d& principal, StateRef) const;  starting-stress check
//   std::string describe() const;     its parameters after the moduli, starting ", " (tsuchi element)
// optionally k0_hint (a string_view added to a refused K0 profile), imperfection_limit() (why
// an imperfection cannot apply), bool released(StateRef) (the last update released the point
// in tension: its expansion is an opening between particles, solver.hold_released_volume),
//   void start(const Eigen::Vector3d& principal, StateRef) const;   state that depends on the
//                                     stress a point starts from (an OCR's preconsolidation
//                                     pressure), called once per point before outside(),
//   M with_cell_size(double h) const; the model for a grid of cell size h, called once where a
//                                     run builds its materials (a strength that depends on the
//                                     mesh, like a softening regularised by a band width; the
//                                     element driver has no grid and uses the model as read),
//   M reduced(double F, bool reduce_dilatancy) const;  the model with its strength divided by F
//                                     (material/strength_reduction.hpp), for `tsuchi fos`; a model
//                                     without it is not reduced (and an input with none is refused),
//   static constexpr bool reads_own_elasticity;   true: the material reader reads no moduli and
//                                     passes a default LinearElastic (the model's reader reads its own),
//   double dilatancy_angle() const;   the largest dilatancy angle (rad) its plastic flow takes:
//                                     a dilatant material takes no volumetric-strain average by
//                                     default (model/config.hpp, anti_locking_of),
// and
// with a reader of its input parameters beside it, in namespace tsuchi,
//   template <class Table, class Warn> M read_model_parameters(Table&, const LinearElastic& moduli,
//                                                              Warn&& warn, std::type_identity<M>);
// and is registered by adding it to ConstitutiveModel below (its header included here). Nothing
// else changes: the input reader, particle storage, frame fields, recorder quantities,
// checkpoints and the time step follow from these.
#include "tsuchi/material/drucker_prager.hpp"
#include "tsuchi/material/drucker_prager_input.hpp"
#include "tsuchi/material/linear_elastic.hpp"
#include "tsuchi/material/modified_cam_clay.hpp"
#include "tsuchi/material/modified_cam_clay_input.hpp"
#include "tsuchi/material/mohr_coulomb.hpp"
#include "tsuchi/material/mohr_coulomb_input.hpp"
#include "tsuchi/material/mohr_coulomb_softening.hpp"
#include "tsuchi/material/mohr_coulomb_softening_input.hpp"
#include "tsuchi/material/state_field.hpp"

#include <array>
#include <cstddef>
#include <string>
#include <variant>
#include <vector>

namespace tsuchi {

// The registration: every constitutive model the program knows.
using ConstitutiveModel = std::variant<LinearElastic, MohrCoulomb, DruckerPrager, ModifiedCamClay, MohrCoulombSoftening>;

struct Material {
  std::string name;
  double density = 0.0;  // kg/m^3
  ConstitutiveModel model;
};

// Every state field of every registered model, each name once, in the order of ConstitutiveModel
// and of each model's list: the particles' state columns (model/particle_fields.hpp).
const std::vector<StateField>& material_state_fields();

// Index in material_state_fields() of the field named `name`, or -1.
int state_column(std::string_view name);

// Column of each of M's state fields, in M's order.
template <class M>
const std::array<int, M::state_fields.size()>& state_columns_of() {
  static const std::array<int, M::state_fields.size()> columns = [] {
    std::array<int, M::state_fields.size()> c{};
    for (std::size_t k = 0; k < c.size(); ++k) c[k] = state_column(M::state_fields[k].name);
    return c;
  }();
  return columns;
}

// The state of a single point (an element test, a check of a starting stress), every field at its
// initial value to start with; copies are independent points.
template <class M>
class PointStateOf {
 public:
  static constexpr std::size_t N = M::state_fields.size();
  PointStateOf() {
    for (std::size_t k = 0; k < N; ++k) value_[k] = M::state_fields[k].initial;
  }
  PointStateOf(const PointStateOf& o) : value_(o.value_) {}
  PointStateOf& operator=(const PointStateOf& o) {
    value_ = o.value_;
    return *this;
  }
  // For the model's update: column k points at field k (rebuilt on each call, so copies stay apart).
  StateRef ref() {
    for (std::size_t k = 0; k < N; ++k) column_[k] = &value_[k];
    return {column_.data(), 0};
  }
  // The field named `name`, 0 when the model has none.
  double field(std::string_view name) const {
    for (std::size_t k = 0; k < N; ++k)
      if (M::state_fields[k].name == name) return value_[k];
    return 0.0;
  }

 private:
  std::array<double, N> value_{};
  std::array<double*, N> column_{};
};

// A point's state at the stress it starts from (principal values, ascending): every field holds
// its initial value (or a value read from a particle file); the model's optional start hook then
// sets what depends on the starting stress. Called once per point, before the check outside().
template <class M>
void start_state(const M& model, const Eigen::Vector3d& principal, StateRef s) {
  if constexpr (requires { model.start(principal, s); }) model.start(principal, s);
}

// The names of the registered models that have a state field named `name`, in registration order.
std::vector<std::string_view> models_with_state_field(std::string_view name);

// Whether the model of `m` has a state field named `name`.
bool has_state_field(const Material& m, std::string_view name);

// The largest dilatancy angle (rad) the plastic flow of `m` takes; 0 for a model without one.
inline double dilatancy_angle_of(const Material& m) {
  return std::visit([](const auto& model) {
    if constexpr (requires { model.dilatancy_angle(); }) return model.dilatancy_angle();
    else return 0.0;
  }, m.model);
}

}  // namespace tsuchi
