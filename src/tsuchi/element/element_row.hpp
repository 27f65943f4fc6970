#pragma once
// One state along an element path (a CSV row) and the lab quantities derived from it.
//
// The tensor components keep the solver's sign (tension positive); the derived quantities follow
// soil mechanics (p and eps_v compression positive) because that is how lab results are read.
#include "tsuchi/core/principal.hpp"
#include "tsuchi/core/principal_frame.hpp"
#include "tsuchi/core/tensor.hpp"
#include "tsuchi/material/mohr_coulomb.hpp"

#include <cmath>
#include <limits>
#include <string_view>
#include <utility>
#include <vector>

namespace tsuchi::element {

struct ElementRow {
  long increment = 0;  // 0 is the initial state; counted over all segments
  int segment = 0;     // 0-based, as in the input's key paths
  Voigt<3> strain = Voigt<3>::Zero();  // accumulated small strain (sum of the increments)
  Voigt<3> stress = Voigt<3>::Zero();
  YieldMode mode = YieldMode::Elastic;  // of the increment that led here
  // As the run's particle fields of the same names: accumulated eps1_p - eps3_p, and accumulated
  // plastic volumetric strain, dilation positive.
  double plastic_shear_strain = 0.0;
  double plastic_volumetric_strain = 0.0;
  // Every state field of the tested model (material/state_field.hpp), in the model's order: a
  // preconsolidation pressure, a specific volume, a softening parameter.
  std::vector<std::pair<std::string_view, double>> state;

  // The state field named `name`, NaN when the model has none.
  double state_value(std::string_view name) const {
    for (const auto& [n, v] : state)
      if (n == name) return v;
    return std::numeric_limits<double>::quiet_NaN();
  }

  // Mean stress, compression positive.
  double p() const { return 0.0 - trace<3>(stress) / 3.0; }

  // Von Mises equivalent stress q = sqrt(3 J2); equals sigma1 - sigma3 in a triaxial test.
  double q() const { return von_mises<3>(stress); }

  // Largest minus smallest principal stress: the deviator at failure of any Mohr-Coulomb test.
  // (The iterative eigen-solver of PrincipalFrame: the direct one loses ~1e-9 relative.)
  double deviator() const {
    const Eigen::Vector3d v = PrincipalFrame<3>(stress).values;
    return v[2] - v[0];
  }

  // Volumetric strain, compression positive.
  double eps_v() const { return 0.0 - trace<3>(strain); }  // 0 - x, not -x: no "-0" in the CSV

  double gamma_max() const { return max_shear_strain<3>(strain); }
};

}  // namespace tsuchi::element
