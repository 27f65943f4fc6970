#pragma once
// Free grid faces and the GIMP domains that reach them.
//
// A GIMP domain that reaches past a grid face puts weight on nodes beyond the last row, which do
// not exist and are dropped (Grid::axis_inside). The weights in the grid then sum to less than one
// and their gradients no longer to zero, so the particle's stress pushes on the grid as a traction
// would: the internal forces of eq (3) summed over the grid's nodes leave
// sum_p V_p sigma_p grad S_{beyond,p}, the reaction of a wall. At a fixed, roller or frictional
// face that wall is wanted; at a free face it held a body up against gravity (issue 41). So a
// particle whose domain crosses a free face has left the grid there, as its centre does with the
// linear kernel, unless the face node nearest to it holds that component ([[boundary.nodes]]) or
// its body's motion is prescribed along the axis.
#include "tsuchi/model/model.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace tsuchi {

// The first free face (axis * 2 + side) that particle i's domain reaches past by more than
// `slack` (m; a negative slack finds domains that come within -slack of a face), or -1.
template <int D>
int free_face_reached(const Model<D>& m, std::size_t i, double slack) {
  const auto& p = m.particles;
  const auto& g = m.grid;
  const Vec<D>& x = p.x_p[i];
  const Vec<D>& l = p.l_p[i];
  const Vec<D> hi = g.upper();
  const auto& motion = m.motion[static_cast<std::size_t>(p.body_p[i])];
  for (int d = 0; d < D; ++d)
    for (int side = 0; side < 2; ++side) {
      if (!m.step.free_face[d][side] || (motion.any && motion.prescribed[d])) continue;
      if (side == 0 ? x[d] - l[d] >= g.origin[d] - slack : x[d] + l[d] <= hi[d] + slack) continue;
      std::array<int, D> ijk{};
      for (int e = 0; e < D; ++e)
        ijk[e] = e == d ? (side == 0 ? 0 : g.n_nodes[e] - 1)
                        : std::clamp(static_cast<int>(std::lround((x[e] - g.origin[e]) * g.inv_h)), 0, g.n_nodes[e] - 1);
      if (!(g.fixed_g[static_cast<std::size_t>(g.index(ijk))] & (1u << d))) return d * 2 + side;
    }
  return -1;
}

// Weights of order (slack / h)^2 on a missing node are no hold: the slack of the run-time check.
template <int D>
double free_face_slack(const Model<D>& m) {
  return 1e-9 * m.grid.h;
}


}  // namespace tsuchi
