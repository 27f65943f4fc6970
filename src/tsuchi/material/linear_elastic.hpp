#pragma once
// Hooke's law in rate form (hypoelastic): d_sigma = lambda tr(d_eps) I + 2 G d_eps, eq (11).
#include "tsuchi/core/tensor.hpp"
#include "tsuchi/material/state_field.hpp"

#include <array>
#include <type_traits>
#include <string>

namespace tsuchi {

struct LinearElastic {
  static constexpr std::string_view name = "linear_elastic";
  static constexpr std::array<StateField, 0> state_fields{};  // no history

  double K = 0.0;  // bulk modulus (Pa)
  double G = 0.0;  // shear modulus (Pa)

  static LinearElastic from_young(double E, double nu) {
    return {E / (3.0 * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))};
  }
  static LinearElastic from_shear(double G, double nu) {
    return {2.0 * G * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu)), G};
  }

  double constrained_modulus() const { return K + 4.0 * G / 3.0; }

  template <int D>
  Voigt<D> stress_increment(const Voigt<D>& d_eps) const {
    const double lambda_tr = (K - 2.0 * G / 3.0) * trace<D>(d_eps);
    Voigt<D> ds = 2.0 * G * d_eps;
    add_to_normal_entries<D>(ds, lambda_tr);  // by pairs (core/tensor.hpp)
    return ds;
  }

  template <int D>
  void update(Voigt<D>& sigma, const Voigt<D>& d_eps) const {
    sigma += stress_increment<D>(d_eps);
  }

  // The constitutive model interface (material/material.hpp): one step of a point with state s;
  // the stress has been rotated (Jaumann, eq 22) by the caller.
  struct Context {};
  Context context() const { return {}; }
  template <int D>
  void update(Voigt<D>& sigma, const Voigt<D>& d_eps, const Mat<D>& /*d_omega*/, const Context&, StateRef) const {
    update<D>(sigma, d_eps);
  }
  // The moduli of a point in its state: the time step's wave speed, the strain energy.
  const LinearElastic& stiffness(StateRef) const { return *this; }
  // Every stress is admissible.
  Inadmissible outside(const Eigen::Vector3d& /*principal*/, StateRef) const { return {}; }
  std::string describe() const { return {}; }

  // Recoverable elastic energy density of a stress state s: p^2 / 2K + s_dev : s_dev / 4G.
  template <int D>
  double energy_density(const Voigt<D>& s) const {
    const double p = trace<D>(s) / 3.0;
    const Voigt<D> dev = deviator<D>(s);
    return p * p / (2.0 * K) + contract<D>(dev, dev) / (4.0 * G);
  }
};

// Its parameters from an input table: the moduli, which every model's reader has read already.
template <class Table, class Warn>
LinearElastic read_model_parameters(Table&, const LinearElastic& elastic, Warn&&, std::type_identity<LinearElastic>) {
  return elastic;
}

}  // namespace tsuchi
