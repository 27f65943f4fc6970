#pragma once
// The initial stress of a particle of a body (Config's InitialStressConfig), tension positive.
//
// K0 (geostatic): gravity must point along one axis. The vertical stress is the weight of the
// material above the particle plus the surcharge on top (model/overburden.hpp),
//   sigma_v = surface_stress - |g| * integral of rho over the column above,
// or, when the profile gives a level `surface`, sigma_v = surface_stress - rho |g| (surface - x_up)
// with the particle's own density. Both horizontal normal stresses (sigma_zz too in plane strain)
// are k0 sigma_v, with no shear: the state at rest of ground that was never strained sideways.
#include "tsuchi/model/config.hpp"
#include "tsuchi/core/tensor.hpp"

#include <cmath>

namespace tsuchi {

struct GeostaticFrame {
  int up_axis = 1;
  double up_sign = 1.0;  // +1 when "up" is the positive up_axis direction
  double g = 0.0;        // |gravity|
};

// sigma_v: the vertical stress at the particle (used by a K0 profile only).
template <int D>
Voigt<D> initial_stress(const InitialStressConfig& s, const GeostaticFrame& f, double sigma_v) {
  Voigt<D> sigma = Voigt<D>::Zero();
  switch (s.kind) {
    case InitialStressConfig::Kind::None: break;
    case InitialStressConfig::Kind::Uniform:
      for (int k = 0; k < n_voigt<D>; ++k) sigma[k] = s.tensor[static_cast<std::size_t>(k)];
      break;
    case InitialStressConfig::Kind::K0:
      for (int i = 0; i < 3; ++i) sigma[i] = i == f.up_axis ? sigma_v : s.k0 * sigma_v;
      break;
  }
  return sigma;
}

}  // namespace tsuchi
