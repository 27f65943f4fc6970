#pragma once
// Strain-softening Mohr-Coulomb (FLAC's strain-softening/hardening model; docs/materials.md,
// "Strain-softening Mohr-Coulomb"): Mohr-Coulomb with tension cut-off (mohr_coulomb.hpp, its
// return and tension rules unchanged) whose c, phi and psi are piecewise-linear functions of a
// softening parameter k, FLAC's k_s, accumulated from the plastic shear strain increments:
//
//   dk = sqrt(1/2 sum_i (de_i^p - de_m^p)^2),  de_m^p = (de_1^p + de_2^p + de_3^p) / 3     (S1)
//
// FLAC writes (S1) for its single-plane shear flow, de_2^p = 0: dk = sqrt(1/2 ((de_1 - de_m)^2 +
// de_m^2 + (de_3 - de_m)^2)), de_m = (de_1 + de_3) / 3; (S1) is the same measure when an edge
// return also strains the intermediate direction. The plastic strain of the step is the
// inelastic part C (sigma_trial - sigma) the Mohr-Coulomb return books, so its deviatoric part is
// dev(sigma_trial - sigma) / 2G and (S1) needs no principal directions:
//
//   dk = |dev(sigma_trial - sigma)| / (2 sqrt(2) G),  |a| = sqrt(a : a)                     (S2)
//
// Only steps that end on the shear surface add to k: FLAC keeps the tensile plastic strain in a
// separate parameter (it softens the tension strength, which this model keeps constant).
// The strength of a step is the one at k at the step's start (FLAC's explicit update): the return
// is Mohr-Coulomb's with c(k), phi(k), psi(k); the point's imperfection factors scale c(k) and
// phi(k). With softening_length L the tables' abscissae are scaled by L / h on a grid of cell
// size h (with_cell_size), so that a band about a cell wide loses its strength over the same
// displacement on every grid (the crack-band idea: Bazant & Oh 1983; Pietruszczak & Mroz 1981).
#include "tsuchi/material/mohr_coulomb.hpp"
#include "tsuchi/material/softening_table.hpp"

#include <limits>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>

namespace tsuchi {

namespace field_name {
inline constexpr std::string_view softening_parameter = "softening_parameter";
}

struct MohrCoulombSoftening {
  static constexpr std::string_view name = "mohr_coulomb_softening";
  // Mohr-Coulomb's fields first, in its order, so that its outside() reads this state too.
  enum StateIndex : std::size_t { kMode, kPlasticShear, kPlasticVolume, kCohesionFactor, kFrictionFactor, kSoftening };
  static constexpr std::array<StateField, 6> state_fields{{
      MohrCoulomb::state_fields[0], MohrCoulomb::state_fields[1], MohrCoulomb::state_fields[2],
      MohrCoulomb::state_fields[3], MohrCoulomb::state_fields[4],
      {field_name::softening_parameter, "", 0.0, false, "",
       "FLAC's k_s: accumulated sqrt(1/2 e:e) of the deviatoric plastic strain increments e of shear steps"},
  }};
  static_assert(std::size_t{kMode} == MohrCoulomb::kMode && std::size_t{kCohesionFactor} == MohrCoulomb::kCohesionFactor &&
                std::size_t{kFrictionFactor} == MohrCoulomb::kFrictionFactor);

  // Elastic moduli, tension strength and rules; its c, phi, psi are replaced by the tables' values.
  MohrCoulomb base;
  SofteningTable cohesion;  // c (Pa)
  SofteningTable phi;       // friction angle (rad)
  SofteningTable psi;       // dilatancy angle (rad)
  double dilatancy_angle() const { return *std::max_element(psi.value.begin(), psi.value.end()); }
  std::optional<double> softening_length;  // L (m), the band width the tables' strains refer to
  double cell_size = 0.0;                  // h (m) the tables were scaled for; 0: used as given

  // The run's hook (material.hpp): the tables for a grid of cell size h.
  MohrCoulombSoftening with_cell_size(double h) const {
    if (!softening_length) return *this;
    MohrCoulombSoftening m = *this;
    const double f = *softening_length / h;
    m.cohesion = cohesion.scaled(f), m.phi = phi.scaled(f), m.psi = psi.scaled(f);
    m.cell_size = h;
    return m;
  }

  // The `tsuchi fos` hook (material.hpp): every point of the c and phi tables reduced by F
  // (strength_reduction.hpp); psi's reduced too with reduce_dilatancy, else capped at the smallest
  // reduced phi of the table; the tension strength with c.
  MohrCoulombSoftening reduced(double F, bool reduce_dilatancy) const {
    MohrCoulombSoftening m = *this;
    for (double& c : m.cohesion.value) c /= F;
    double lowest = std::numeric_limits<double>::infinity();
    for (double& a : m.phi.value) a = reduced_angle(a, F), lowest = std::min(lowest, a);
    for (double& a : m.psi.value) a = reduce_dilatancy ? reduced_angle(a, F) : std::min(a, lowest);
    m.base = base.reduced(F, reduce_dilatancy);
    return m;
  }

  // Mohr-Coulomb with the strength parameters at softening parameter k.
  MohrCoulomb at(double k) const {
    MohrCoulomb m = base;
    m.cohesion = cohesion.at(k), m.phi = phi.at(k), m.psi = psi.at(k);
    return m;
  }

  // (S2): the softening increment of a step from the stress its return removed.
  template <int D>
  double softening_increment(const Voigt<D>& removed) const {
    const Voigt<D> dev = deviator<D>(removed);
    return std::sqrt(0.5 * contract<D>(dev, dev)) / (2.0 * base.elastic.G);
  }

  // The constitutive model interface (material/material.hpp). Every point has its own strength,
  // so nothing is shared beyond the parameters.
  struct Context {};
  Context context() const { return {}; }
  template <int D>
  void update(Voigt<D>& sigma, const Voigt<D>& d_eps, const Mat<D>& /*d_omega*/, const Context&, StateRef s) const {
    const MohrCoulomb m = at(s[kSoftening]);  // explicit: the strength at the step's start
    PlasticPoint point{YieldMode::Elastic, s[kPlasticShear], s[kPlasticVolume]};
    m.elastic.update<D>(sigma, d_eps);
    const Voigt<D> trial = sigma;
    const MohrCoulomb::Strength strength = m.scaled_strength(s[kCohesionFactor], s[kFrictionFactor], m.angles());
    const YieldMode mode = m.correct<D>(sigma, strength, point);
    if (mode == YieldMode::Shear) s[kSoftening] += softening_increment<D>(trial - sigma);
    s[kMode] = static_cast<double>(mode);
    s[kPlasticShear] = point.plastic_shear;
    s[kPlasticVolume] = point.plastic_volume;
  }
  const LinearElastic& stiffness(StateRef) const { return base.elastic; }
  bool released(StateRef s) const { return s[kMode] == static_cast<double>(YieldMode::Tension); }

  // Against the strength at the point's own k (0 for a new point: the peak).
  Inadmissible outside(const Eigen::Vector3d& principal, StateRef s) const {
    return at(s[kSoftening]).outside(principal, s);
  }
  static constexpr std::string_view k0_hint = MohrCoulomb::k0_hint;

  std::string imperfection_limit(double amplitude, bool /*cohesion*/, bool friction) const {
    return friction ? friction_scale_limit(phi.max_value(), amplitude, "largest friction angle of the table")
                    : std::string{};
  }

  std::string describe() const {
    constexpr double deg = 180.0 / std::numbers::pi;
    const auto table = [](const SofteningTable& t, double unit) {
      if (!t.varies()) return fmt::format("{:.6g}", t.value[0] * unit);
      std::string r = "[";
      for (std::size_t i = 0; i < t.strain.size(); ++i)
        r += fmt::format("{}({:.6g}, {:.6g})", i ? ", " : "", t.strain[i], t.value[i] * unit);
      return r + "]";
    };
    std::string length = "no softening_length: tables used as given";
    if (softening_length && cell_size > 0.0)
      length = fmt::format("softening_length {:.6g} m on cells of {:.6g} m: strains above scaled by {:.6g}",
                           *softening_length, cell_size, *softening_length / cell_size);
    else if (softening_length)
      length = fmt::format("softening_length {:.6g} m, no grid here: tables used as given", *softening_length);
    return fmt::format(", c(k) = {} Pa, phi(k) = {} deg, psi(k) = {} deg (k the softening parameter; {}), "
                       "tension strength {:.6g} Pa ({} rule, {} selection)",
                       table(cohesion, 1.0), table(phi, deg), table(psi, deg), length, base.tension,
                       base.tension_rule == TensionRule::Flac ? "flac" : "paper",
                       base.tension_selection == TensionSelection::Flac ? "flac" : "paper");
  }
};

}  // namespace tsuchi
