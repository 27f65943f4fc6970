#pragma once
// Material points as a structure of flat arrays, one array per field.
#include "tsuchi/core/tensor.hpp"

#include <cstdint>
#include <vector>

namespace tsuchi {

template <int D>
struct Particles {
  std::vector<Vec<D>> x_p;        // position (m)
  std::vector<Vec<D>> u_p;        // displacement from the initial position (m)
  std::vector<Vec<D>> v_p;        // velocity (m/s)
  std::vector<Vec<D>> l_p;        // GIMP half-widths per axis (m)
  std::vector<double> m_p;        // mass (kg; per metre of thickness in 2D)
  std::vector<double> V_p;        // volume (m^3; m^2 in 2D)
  std::vector<Voigt<D>> sigma_p;  // Cauchy stress, tension positive (Pa)
  std::vector<Voigt<D>> sigma0_p; // initial stress subtracted in the internal force, eq (2)
  std::vector<Voigt<D>> eps_p;    // accumulated small strain, eq (10b)
  // Mohr-Coulomb history and strength imperfection (untouched for elastic materials).
  std::vector<std::uint8_t> yield_p;       // YieldMode of the last step: 0 elastic, 1 shear, 2 tension
  std::vector<double> plastic_shear_p;     // accumulated plastic shear strain (eps1_p - eps3_p)
  std::vector<double> plastic_volume_p;    // accumulated plastic volumetric strain, dilation positive
  std::vector<double> c_scale_p;           // cohesion factor 1 + d of the imperfection
  std::vector<double> phi_scale_p;         // friction-angle factor 1 + d
  std::vector<std::int32_t> material_p;
  std::vector<std::int32_t> body_p;
  std::vector<std::int32_t> id_p;  // stable identity, survives reordering

  std::size_t size() const { return x_p.size(); }

  void resize(std::size_t n) {
    x_p.resize(n, Vec<D>::Zero());
    u_p.resize(n, Vec<D>::Zero());
    v_p.resize(n, Vec<D>::Zero());
    l_p.resize(n, Vec<D>::Zero());
    m_p.resize(n, 0.0);
    V_p.resize(n, 0.0);
    sigma_p.resize(n, Voigt<D>::Zero());
    sigma0_p.resize(n, Voigt<D>::Zero());
    eps_p.resize(n, Voigt<D>::Zero());
    yield_p.resize(n, 0);
    plastic_shear_p.resize(n, 0.0);
    plastic_volume_p.resize(n, 0.0);
    c_scale_p.resize(n, 1.0);
    phi_scale_p.resize(n, 1.0);
    material_p.resize(n, 0);
    body_p.resize(n, 0);
    id_p.resize(n, 0);
  }

  // Reorders every array: particle k of the result is particle order[k] of this one. Ids move
  // with their particles, so outputs keyed by id are unchanged.
  template <class Index>
  void permute(const std::vector<Index>& order) {
    const auto apply = [&](auto& a) {
      auto copy = a;
      for (std::size_t k = 0; k < order.size(); ++k) a[k] = copy[static_cast<std::size_t>(order[k])];
    };
    apply(x_p), apply(u_p), apply(v_p), apply(l_p), apply(m_p), apply(V_p), apply(sigma_p), apply(sigma0_p);
    apply(eps_p), apply(yield_p), apply(plastic_shear_p), apply(plastic_volume_p), apply(c_scale_p);
    apply(phi_scale_p), apply(material_p), apply(body_p), apply(id_p);
  }

  static constexpr std::size_t bytes_per_particle() {
    return 4 * sizeof(Vec<D>) + 6 * sizeof(double) + 3 * sizeof(Voigt<D>) +
           3 * sizeof(std::int32_t) + sizeof(std::uint8_t);
  }
};

}  // namespace tsuchi
