#pragma once
// The anti-locking remedy (solver.anti_locking = "cell"): a particle's volumetric strain increment
// is replaced by that of the centre of the background cell holding it, and its deviatoric part is
// kept:
//   d_eps_bar = d_eps + (tr d_eps_c - tr d_eps) / 3 * I,      tr d_eps_c = dt div v (x_c)      (V1)
// with div v at the cell centre x_c from the bilinear (trilinear) interpolation of the cell's 2^D
// nodal velocities:
//   div v (x_c) = sum_a sum_d (2 a_d - 1) v_a,d / (h 2^(D-1)),   a in {0, 1}^D                 (V2)
// On the regular grid (V2) is also the mean of div v over the cell, so (V1) is the mean-dilatation
// (selective reduced integration, Q1P0) element of Nagtegaal, Parks and Rice (1974) and of FLAC's
// mixed discretisation: one volumetric strain per cell, so a cell's particles cannot each impose
// their own incompressibility constraint. In the F-bar form of de Souza Neto et al. (1996), the
// particle's deformation gradient takes the cell centre's volume change; (V1) is its small-
// increment (rate) form, which is what the Jaumann-rate update integrates. Coombs, Charlton,
// Cortis and Augarde ("Overcoming volumetric locking in material point methods", CMAME 2018)
// bring F-bar to MPM with the same idea of an assumed volumetric strain per background cell.
// With the cell's value only the stress update and the volume see (V1); the internal force keeps
// the particle's own weights (not a B-bar operator in the force as well). With "bbar" the nodal
// average (V3) has its transpose in the force too (eq V5, ExplicitSolver::average_pressure): with
// "node" alone the pair is not symmetric, and perfectly plastic, nearly incompressible soil can
// gain energy.
//
// In plane strain (D = 2) the shift goes to zz as well, as in Hughes' (1980) B-bar for plane
// strain: the deviatoric part of the particle's own increment (zz included) is kept, so a 2D model
// gives the answer of the same model in 3D between rollers (Verification.ColumnSelfWeight3D).
#include "tsuchi/core/tensor.hpp"
#include "tsuchi/grid/grid.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace tsuchi {

// div v at the centre of the cell holding the point xi = (x - origin) / h, eq (V2). A point on or
// beyond the grid's last node belongs to the last cell.
template <int D>
[[gnu::always_inline]] inline double cell_centre_divergence(const Grid<D>& g, const Vec<D>* v,
                                                            const Eigen::Array<double, D, 1>& xi) {
  constexpr int E = Grid<D>::kEdge;
  std::array<const std::int64_t*, D> term;
  for (int d = 0; d < D; ++d) {
    const int c = std::clamp(static_cast<int>(std::floor(xi[d])), 0, g.n_nodes[d] - 2);
    term[d] = g.axis_term[d].data() + c + E;  // term[d][0], term[d][1]: the cell's two nodes
  }
  double div = 0.0;
  for (int a = 0; a < (1 << D); ++a) {
    std::int64_t k = 0;
    for (int d = 0; d < D; ++d) k += term[d][(a >> d) & 1];
    for (int d = 0; d < D; ++d) div += ((a >> d) & 1 ? v[k][d] : -v[k][d]);
  }
  return div * g.inv_h / static_cast<double>(1 << (D - 1));
}

// Eq (V1): the particle's strain increment with the volumetric part `volumetric` (the cell's, or
// the nodal average's).
template <int D>
[[gnu::always_inline]] inline void replace_volumetric_strain(Voigt<D>& d_eps, double volumetric) {
  const double shift = (volumetric - trace<D>(d_eps)) / 3.0;
  add_to_normal_entries<D>(d_eps, shift);  // by pairs (core/tensor.hpp)
}

}  // namespace tsuchi
