#pragma once
// The initial stress of a particle of a body (Config's InitialStressConfig), tension positive.
//
// K0 (geostatic): gravity must point along one axis. Depth is measured down from the free surface,
// sigma_v = surface_stress - rho |g| depth, and both horizontal normal stresses (sigma_zz too in
// plane strain) are k0 sigma_v, with no shear. This is the state at rest of a level layer.
#include "tsuchi/model/config.hpp"
#include "tsuchi/core/tensor.hpp"

#include <cmath>

namespace tsuchi {

struct GeostaticFrame {
  int up_axis = 1;
  double up_sign = 1.0;  // +1 when "up" is the positive up_axis direction
  double g = 0.0;        // |gravity|
  double surface = 0.0;  // coordinate of the free surface along up_axis
};

template <int D>
Voigt<D> initial_stress(const InitialStressConfig& s, const GeostaticFrame& f, double density, const Vec<D>& x) {
  Voigt<D> sigma = Voigt<D>::Zero();
  switch (s.kind) {
    case InitialStressConfig::Kind::None: break;
    case InitialStressConfig::Kind::Uniform:
      for (int k = 0; k < n_voigt<D>; ++k) sigma[k] = s.tensor[static_cast<std::size_t>(k)];
      break;
    case InitialStressConfig::Kind::K0: {
      const double depth = f.up_sign * (f.surface - x[f.up_axis]);
      const double sv = s.surface_stress - density * f.g * depth;
      for (int i = 0; i < 3; ++i) sigma[i] = i == f.up_axis ? sv : s.k0 * sv;
      break;
    }
  }
  return sigma;
}

}  // namespace tsuchi
