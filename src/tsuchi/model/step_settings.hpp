#pragma once
// What one explicit step needs besides the grid, the particles and the materials: the physics and
// numerics of the step, never the run's time, output or checkpoint settings.
#include "tsuchi/core/tensor.hpp"
#include "tsuchi/model/config.hpp"

#include <array>
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
  // [axis][side]: the grid face holds nothing (no [boundary] condition); a GIMP domain that crosses
  // it has left the grid (ExplicitSolver::free_face_crossed).
  std::array<std::array<bool, 2>, D> free_face{};

  // GIMP updates the particle domains (eq 14); uGIMP keeps them, linear has none.
  bool domain_update() const { return kernel == ShapeKind::Gimp; }

  // The settings the input's [solver] and gravity give (not the gravity function, nor the mass
  // floor, which depend on the run's clock and particles): at the start and at each stage.
  void set_from(const Config& c) {
    scheme = c.solver.scheme;
    kernel = c.solver.shape;
    pic_fraction = c.solver.pic_fraction;
    velocity_transfer = c.solver.velocity_transfer;
    anti_locking.resize(c.materials.size());
    for (std::size_t k = 0; k < c.materials.size(); ++k) anti_locking[k] = anti_locking_of(c, k);
    hold_released_volume = c.solver.hold_released_volume;
    damping = c.solver.damping;
    for (int d = 0; d < D; ++d) gravity[d] = c.gravity[d];
    sort_interval = c.solver.sort_interval;
    for (int d = 0; d < D; ++d)
      for (int side = 0; side < 2; ++side) free_face[d][side] = c.boundary.faces[d][side] == FaceCondition::Free;
  }
};

}  // namespace tsuchi
