#pragma once
// GIMP particle domain update, eq (14): each half-width follows the normal strain along its axis.
// The half-width is held at L/2 at most: METHOD.md's GIMP table (and its three-node stencil)
// assumes l_p <= L/2, and a wider domain would need the wider-support form of the weights.
#include "tsuchi/core/tensor.hpp"

#include <algorithm>

namespace tsuchi {

template <int D>
inline void update_particle_domain(Vec<D>& l_p, const Voigt<D>& d_eps, double cell_size) {
  for (int d = 0; d < D; ++d) l_p[d] = std::min(l_p[d] * (1.0 + d_eps[d]), 0.5 * cell_size);
}

}  // namespace tsuchi
