#pragma once
// The loading path of a single material point: an initial stress, then segments of equal
// increments in which every one of the six stress/strain components is controlled exactly one way.
//
// A segment drives some components by strain (a change of the tensor strain component spread
// evenly over its increments) and the others by stress (a value reached linearly by the segment's
// end, or the value at the segment's start held). The lab-test presets of the element input
// (triaxial, plane strain, simple shear, isotropic) all expand to this one form, so the driver
// has a single code path.
//
// Conventions are those of the solver: tension positive, Pa, tensor (not engineering) shear
// strains, components in Voigt order xx, yy, zz, xy, yz, xz.
#include "tsuchi/core/tensor.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace tsuchi::element {

inline constexpr int n_components = 6;
inline constexpr const char* component_name[n_components] = {"xx", "yy", "zz", "xy", "yz", "xz"};

enum class Control : std::uint8_t {
  Strain,        // value: change of the strain component over the segment
  StressTarget,  // value: stress at the end of the segment (Pa)
  StressHold,    // the stress at the start of the segment is kept; value unused
};

struct ComponentControl {
  Control kind = Control::Strain;
  double value = 0.0;

  bool by_stress() const { return kind != Control::Strain; }
};

struct Segment {
  int increments = 1;
  std::array<ComponentControl, n_components> control{};
};

struct ElementPath {
  std::string kind;         // the preset's name, or "general"
  std::string description;  // one line for the summary and the CSV header
  Voigt<3> initial_stress = Voigt<3>::Zero();
  std::vector<Segment> segments;

  long total_increments() const {
    long n = 0;
    for (const auto& s : segments) n += s.increments;
    return n;
  }
};

}  // namespace tsuchi::element
