#pragma once
// Strain-softening Mohr-Coulomb's parameters from an input table (docs/input.md): Mohr-Coulomb's
// keys, except that cohesion, friction_angle and dilatancy_angle may each be a number or a table
// of points [[k, value], ...] in the softening parameter k, and the optional softening_length.
#include "tsuchi/material/mohr_coulomb_input.hpp"
#include "tsuchi/material/mohr_coulomb_softening.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <type_traits>

namespace tsuchi {

// A number (a constant) or an array of [k, value] pairs: k from 0, strictly increasing, each
// value passing `ok` (`expected` says the range in words). Absent: the constant `fallback`.
template <class Table>
SofteningTable read_softening_table(Table& s, std::string_view key, const std::string& expected,
                                    const std::function<bool(double)>& ok, std::optional<double> fallback = {}) {
  const std::string both = fmt::format("{}, or a table [[k, value], ...] of such values in the softening parameter k", expected);
  if (!s.has(key) && fallback) {
    s.get(key);
    return SofteningTable::constant(*fallback);
  }
  const auto& node = s.need(key, both);
  const auto* a = node.as_array();
  if (!a) return SofteningTable::constant(s.number(key, both, ok));
  if (a->size() < 2)
    s.fail(key, fmt::format("expected a table of at least two points [[k, value], ...], got {} (for a constant value "
                            "write the number)", a->empty() ? "an empty array" : "one point"));
  SofteningTable t;
  t.strain.clear(), t.value.clear();
  for (std::size_t i = 0; i < a->size(); ++i) {
    const auto* pair = a->get(i)->as_array();
    if (!pair || pair->size() != 2)
      s.fail(key, fmt::format("expected every entry a pair [k, value], got entry {} {}", i,
                              pair ? fmt::format("with {} numbers", pair->size()) : std::string("that is not an array")));
    const double k = s.number_of(key, *pair->get(0), "a softening parameter k (a strain) in every pair");
    const double v = s.number_of(key, *pair->get(1), both);
    if (i == 0 && k != 0.0)
      s.fail(key, fmt::format("expected the table to start at k = 0 (the strength of a new point), got k = {} in entry 0", k));
    if (i > 0 && !(k > t.strain.back()))
      s.fail(key, fmt::format("expected k to increase strictly along the table, got k = {} in entry {} after k = {}", k,
                              i, t.strain.back()));
    if (ok && !ok(v)) s.fail(key, fmt::format("expected {} in every entry, got {} in entry {}", expected, v, i));
    t.strain.push_back(k), t.value.push_back(v);
  }
  return t;
}

template <class Table, class Warn>
MohrCoulombSoftening read_model_parameters(Table& s, const LinearElastic& elastic, Warn&& warn,
                                           std::type_identity<MohrCoulombSoftening>) {
  constexpr double rad = std::numbers::pi / 180.0;
  MohrCoulombSoftening m;
  m.base.elastic = elastic;
  m.cohesion = read_softening_table(s, "cohesion", "a cohesion >= 0 in Pa", [](double v) { return v >= 0.0; });
  SofteningTable phi = read_softening_table(s, "friction_angle", "a friction angle in degrees, in (0, 90)",
                                            [](double v) { return v > 0.0 && v < 90.0; });
  SofteningTable psi = read_softening_table(s, "dilatancy_angle", "a dilatancy angle in degrees, in [0, friction_angle]",
                                            [](double v) { return v >= 0.0 && v < 90.0; }, 0.0);
  // An angle below 1 degree was most likely given in radians.
  for (const auto& [key, t] : {std::pair{"friction_angle", &phi}, std::pair{"dilatancy_angle", &psi}})
    for (double v : t->value)
      if (v > 0.0 && v < 1.0) {
        warn(key, fmt::format("{:g} degrees is below 1 degree; angles are in degrees", v));
        break;
      }
  if (!m.cohesion.varies() && !phi.varies() && !psi.varies())
    s.fail_here("none of cohesion, friction_angle and dilatancy_angle is a table [[k, value], ...]: without "
                "softening this is model = \"mohr_coulomb\"");
  // psi <= phi everywhere: both are linear between the union of their breakpoints.
  std::set<double> ks(phi.strain.begin(), phi.strain.end());
  ks.insert(psi.strain.begin(), psi.strain.end());
  for (double k : ks)
    if (psi.at(k) > phi.at(k))
      s.fail("dilatancy_angle", fmt::format("expected a dilatancy angle no larger than the friction angle at every k, got "
                                            "{} degrees above {} degrees at k = {}",
                                            psi.at(k), phi.at(k), k));
  for (double& v : phi.value) v *= rad;
  for (double& v : psi.value) v *= rad;
  m.phi = std::move(phi), m.psi = std::move(psi);
  // Capped per point at the apex c / tan(phi) of its current strength (MohrCoulomb::strength).
  m.base.tension = s.number("tension_strength", "a tension strength >= 0 in Pa", [](double v) { return v >= 0.0; }, 0.0);
  m.base.tension_rule = static_cast<TensionRule>(s.choice("tension_rule", {"flac", "paper"}, 0));
  const int rule = static_cast<int>(m.base.tension_rule);
  m.base.tension_selection = static_cast<TensionSelection>(s.choice("tension_selection", {"flac", "paper"}, rule));
  if (m.base.tension_rule == TensionRule::Paper && m.base.tension_selection == TensionSelection::Flac)
    s.fail("tension_selection",
           "tension_rule = \"paper\" needs tension_selection = \"paper\": with FLAC's h-function the release "
           "and the shear return meet at different stresses where h = 0, so the result would jump");
  m.softening_length = s.optional_number("softening_length", "a positive length in m (the band width the tables' "
                                         "strains refer to)", [](double v) { return v > 0.0; });
  return m;
}

}  // namespace tsuchi
