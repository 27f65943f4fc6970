#pragma once
// A ground at rest although the unbalanced-force ratio cannot reach its tolerance (issue 41,
// defect 7). With MUSL or USF and the GIMP kernels the ratio of a body with a free side levels off
// at 1e-4 to 1e-2 while the ground stands still (docs/stages.md, "A floor of the default
// schemes"); an equilibrium stage asked for 1e-3 then ran to its max_steps and the next stage, or
// a factor-of-safety search, started from a state reported as not at rest.
//
// The stage is judged over windows of its own steps (rest_window_steps, counted from its first
// step, so a restart judges the same windows). At the end of each window the ground is at rest when
// all of these hold:
//   - the largest movement of a particle over the window, along the axes its body moves freely,
//     is below 1 % of the largest movement over any window of the stage, plus 1e-6 of a cell (a
//     ground that barely moved);
//   - the ratio has not halved over the window: it sits on its floor instead of converging, which
//     the ratio's own tolerance would then take;
//   - the kinetic energy is below 1e-4 of its largest value in the stage (or the stage's own
//     kinetic_energy_ratio, when that is smaller).
// A first window never qualifies (it has no ratio of its start). The state it needs between steps
// (the displacement at the window's start, the largest movement, the ratio at the window's start)
// is saved in a checkpoint, so a restart takes the same verdict at the same step.
#include "tsuchi/model/model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace tsuchi {

inline constexpr double rest_movement_fraction = 1e-2;  // of the stage's largest window movement
inline constexpr double rest_movement_floor = 1e-6;     // of a cell
inline constexpr double rest_kinetic_fraction = 1e-4;   // of the stage's largest kinetic energy

// The window: 1,000 steps, or 20 steps per cell of the grid's longest side (ten crossings of a
// P wave at Courant 0.5), whichever is more, so that a large model's slowest mode has moved.
template <int D>
std::int64_t rest_window_steps(const Grid<D>& grid) {
  int cells = 0;
  for (int d = 0; d < D; ++d) cells = std::max(cells, grid.n_nodes[static_cast<std::size_t>(d)] - 1);
  return std::max<std::int64_t>(1000, 20 * static_cast<std::int64_t>(cells));
}

// What the verdict keeps between steps (RunProgress holds it for a checkpoint).
struct RestWindow {
  // D per particle id (Model::id_count of them): the displacement u_p at the window's start. By
  // id, since the step re-stores the particles in block order (solver.sort_interval).
  std::vector<double> anchor;
  double largest = 0.0;        // the largest movement over a window of the stage so far (m)
  double ratio_start = std::numeric_limits<double>::quiet_NaN();  // the ratio at the window's start
};

// A new window from the present state.
template <int D>
void open_rest_window(const Model<D>& m, double ratio, RestWindow& w) {
  const auto& p = m.particles;
  w.anchor.assign(static_cast<std::size_t>(m.id_count) * D, 0.0);
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int d = 0; d < D; ++d) w.anchor[static_cast<std::size_t>(p.id_p[i]) * D + static_cast<std::size_t>(d)] = p.u_p[i][d];
  w.ratio_start = ratio;
}

// The largest movement since the window's start of a particle, over the components its body does
// not have prescribed: a platen or a held component moves as it is told, while a partly held body
// moves freely along its other axes, and a free rigid body (rigid_mass) by its momentum balance.
template <int D>
double rest_window_movement(const Model<D>& m, const RestWindow& w) {
  const auto& p = m.particles;
  std::vector<std::array<bool, D>> judged(m.motion.size());
  for (std::size_t b = 0; b < m.motion.size(); ++b)
    for (int d = 0; d < D; ++d) {
      const auto& mo = m.motion[b];
      const auto k = static_cast<std::size_t>(d);
      judged[b][k] = !mo.any || !mo.prescribed[k] || (mo.rigid_mass > 0.0 && mo.free[k]);
    }
  double most = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& on = judged[static_cast<std::size_t>(p.body_p[i])];
    double s = 0.0;
    for (int d = 0; d < D; ++d) {
      if (!on[static_cast<std::size_t>(d)]) continue;
      const double du = p.u_p[i][d] - w.anchor[static_cast<std::size_t>(p.id_p[i]) * D + static_cast<std::size_t>(d)];
      s += du * du;
    }
    most = std::max(most, s);
  }
  return std::sqrt(most);
}

// At a window's end: the verdict, and the next window opened. `kinetic_ratio` is the kinetic
// energy over the stage's largest; `kinetic_tolerance` the stage's own kinetic_energy_ratio, when
// it asks for one below rest_kinetic_fraction (the verdict never accepts more than it asked).
template <int D>
bool close_rest_window(const Model<D>& m, double ratio, double kinetic_ratio, RestWindow& w,
                       double kinetic_tolerance = rest_kinetic_fraction) {
  const double moved = rest_window_movement(m, w);
  w.largest = std::max(w.largest, moved);
  const bool still = moved < rest_movement_fraction * w.largest + rest_movement_floor * m.grid.h;
  const bool on_floor = ratio > 0.5 * w.ratio_start;  // false for the first window (NaN)
  const bool quiet = kinetic_ratio < std::min(rest_kinetic_fraction, kinetic_tolerance);
  open_rest_window(m, ratio, w);
  return still && on_floor && quiet;
}

}  // namespace tsuchi
