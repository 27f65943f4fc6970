#pragma once
// Material points as a structure of flat arrays, one array per field.
#include "tsuchi/core/tensor.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <type_traits>
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

  // Calls f(name, array) for every per-particle array: the one list that resizing, reordering and
  // checkpoints go through, so a new field cannot be forgotten by one of them.
  template <class F>
  void for_each_array(F&& f) {
    f("x", x_p), f("u", u_p), f("v", v_p), f("l", l_p), f("m", m_p), f("V", V_p), f("sigma", sigma_p);
    f("sigma0", sigma0_p), f("eps", eps_p), f("yield", yield_p), f("plastic_shear", plastic_shear_p);
    f("plastic_volume", plastic_volume_p), f("c_scale", c_scale_p), f("phi_scale", phi_scale_p);
    f("material", material_p), f("body", body_p), f("id", id_p);
  }
  template <class F>
  void for_each_array(F&& f) const {
    const_cast<Particles*>(this)->for_each_array([&](const char* name, const auto& a) { f(name, a); });
  }

  // New particles are zero, except the strength factors, which are 1.
  void resize(std::size_t n) {
    const std::size_t old = size();
    for_each_array([n](const char*, auto& a) {
      using T = typename std::decay_t<decltype(a)>::value_type;
      a.resize(n, zero_of<T>());
    });
    for (std::size_t i = old; i < n; ++i) c_scale_p[i] = phi_scale_p[i] = 1.0;
  }

  // Reorders every array: particle k of the result is particle order[k] of this one. Ids move
  // with their particles, so outputs keyed by id are unchanged. `scratch` keeps its storage between
  // calls, so a periodic reordering allocates only the first time.
  // Scratch storage in 64-byte lines: aligned for any element type, as vectorised loads of Eigen
  // types require (32 bytes with AVX).
  struct alignas(64) ScratchLine {
    unsigned char bytes[64];
  };
  using Scratch = std::vector<ScratchLine>;

  template <class Index>
  void permute(const std::vector<Index>& order, Scratch& scratch) {
    for_each_array([&](const char*, auto& a) {
      using T = typename std::decay_t<decltype(a)>::value_type;
      const std::size_t lines = (a.size() * sizeof(T) + sizeof(ScratchLine) - 1) / sizeof(ScratchLine);
      scratch.resize(std::max(scratch.size(), lines));
      std::memcpy(static_cast<void*>(scratch.data()), static_cast<const void*>(a.data()), a.size() * sizeof(T));
      const auto* copy = reinterpret_cast<const T*>(scratch.data());
      for (std::size_t k = 0; k < order.size(); ++k) a[k] = copy[static_cast<std::size_t>(order[k])];
    });
  }
  template <class Index>
  void permute(const std::vector<Index>& order) {
    Scratch scratch;
    permute(order, scratch);
  }

  static constexpr std::size_t bytes_per_particle() {
    return 4 * sizeof(Vec<D>) + 6 * sizeof(double) + 3 * sizeof(Voigt<D>) +
           3 * sizeof(std::int32_t) + sizeof(std::uint8_t);
  }
};

}  // namespace tsuchi
