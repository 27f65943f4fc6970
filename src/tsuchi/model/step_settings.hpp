#pragma once
// What one explicit step needs besides the grid, the particles and the materials: the physics and
// numerics of the step, never the run's time, output or checkpoint settings.
#include "tsuchi/core/tensor.hpp"
#include "tsuchi/model/config.hpp"

#include <cstdint>
#include <vector>

namespace tsuchi {

template <int D>
struct StepSettings {
  Scheme scheme = Scheme::MUSL;
  ShapeKind kernel = ShapeKind::Gimp;
  double pic_fraction = 0.0;       // 0 = pure FLIP, 1 = pure PIC
  // FLIP (blended by pic_fraction) or APIC, which keeps Particles::C_p; APIC has pic_fraction 0.
  VelocityTransfer velocity_transfer = VelocityTransfer::Flip;
  std::vector<AntiLocking> anti_locking;  // per material (Model::materials)
  bool hold_released_volume = true;       // see SolverConfig
  double damping = 0.0;            // Cundall local damping coefficient alpha, eq (20)
  Vec<D> gravity = Vec<D>::Zero();
  TimeFunction gravity_function;   // gravity at time t is gravity * gravity_function(t)
  double node_mass_floor = 0.0;    // nodes lighter than this are skipped (kg)
  std::int64_t sort_interval = 0;  // particles re-stored in block order every this many steps (0: never)

  // GIMP updates the particle domains (eq 14); uGIMP keeps them, linear has none.
  bool domain_update() const { return kernel == ShapeKind::Gimp; }
};

}  // namespace tsuchi
