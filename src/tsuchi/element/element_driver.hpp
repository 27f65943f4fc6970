#pragma once
// Drives one material point along an ElementPath with the same constitutive update the solver
// uses on a particle (small strain, no stress rotation: an element test has no spin).
//
// Strain-controlled components are applied directly. Stress-controlled ones make each increment a
// small nonlinear problem: find the unknown strain components for which the updated stress meets
// the targets. It is solved by Newton's method with a finite-difference tangent, every trial
// evaluated on a copy of the point's state; the state is committed once the targets are met.
#include "tsuchi/element/element_path.hpp"
#include "tsuchi/element/element_row.hpp"
#include "tsuchi/material/material.hpp"

#include <functional>
#include <vector>

namespace tsuchi::element {

struct IterationSettings {
  // Stress-controlled components are converged to tolerance x stress scale, the scale being the
  // largest of |stress| at the increment's start, |targets|, (K + 4G/3) x |driven strain increment|
  // and 1 Pa.
  double tolerance = 1e-10;
  int max_iterations = 50;
};

// Calls on_row for the initial state and after every increment. Throws RunError naming the
// increment and the component when the stress targets of an increment cannot be met (typically
// a stress beyond the material's strength); rows delivered before that stand.
void drive_element(const Material& material, const ElementPath& path, const IterationSettings& settings,
                   const std::function<void(const ElementRow&)>& on_row);

// All rows at once; throws like the streaming form.
std::vector<ElementRow> drive_element(const Material& material, const ElementPath& path,
                                      const IterationSettings& settings = {});

}  // namespace tsuchi::element
