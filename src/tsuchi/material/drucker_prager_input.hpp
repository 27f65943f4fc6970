#pragma once
// Drucker-Prager's parameters from an input table, past the elastic moduli (docs/input.md,
// model = "drucker_prager"). `Table` is the input reader's table (io/toml_section.hpp); `warn(key,
// text)` records a valid value that looks like a slip of units. Angles in degrees.
#include "tsuchi/material/drucker_prager.hpp"
#include "tsuchi/material/mohr_coulomb_input.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string_view>
#include <string>
#include <type_traits>
#include <vector>

namespace tsuchi {

template <class Table, class Warn>
DruckerPrager read_model_parameters(Table& s, const LinearElastic& elastic, Warn&& warn,
                                    std::type_identity<DruckerPrager>) {
  const CohesionFriction cf = read_cohesion_friction(s, warn);
  DruckerPrager m;
  m.elastic = elastic;
  m.cohesion = cf.cohesion;
  m.phi = cf.phi;
  m.psi = cf.psi;
  m.tension = cf.tension;  // capped at the apex c / tan(phi), the same for every matching
  // The three cones differ by up to a factor (3 + sin phi) / (3 - sin phi) in strength: no default.
  const std::string matches = "one of \"compression\", \"extension\", \"plane_strain\" (the Mohr-Coulomb strength the cone reproduces)";
  if (!s.has("match")) s.need("match", matches);
  m.match = static_cast<ConeMatch>(s.choice("match", std::vector<std::string>(cone_match_names.begin(), cone_match_names.end()), 0));
  return m;
}

}  // namespace tsuchi
