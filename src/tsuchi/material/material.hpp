#pragma once
// A named material: density plus one constitutive model. The model is a small value type chosen
// once per material group (std::visit outside the particle loop), never per particle.
#include "tsuchi/material/linear_elastic.hpp"
#include "tsuchi/material/mohr_coulomb.hpp"

#include <string>
#include <variant>

namespace tsuchi {

using ConstitutiveModel = std::variant<LinearElastic, MohrCoulomb>;

struct Material {
  std::string name;
  double density = 0.0;  // kg/m^3
  ConstitutiveModel model;

  // Elastic moduli drive the wave speed and the time step, whatever the model.
  const LinearElastic& elastic() const {
    return std::visit([](const auto& m) -> const LinearElastic& { return elastic_part(m); }, model);
  }

  bool is_plastic() const { return std::holds_alternative<MohrCoulomb>(model); }

 private:
  static const LinearElastic& elastic_part(const LinearElastic& m) { return m; }
  static const LinearElastic& elastic_part(const MohrCoulomb& m) { return m.elastic; }
};

}  // namespace tsuchi
