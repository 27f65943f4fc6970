// libFuzzer target for the input reader: read_config_string on arbitrary text. Bad input must end
// in InputError; any other exception, crash, leak or sanitizer report is a bug. An input that
// reads is built into its model (build_model) when that model is small, so the checks that only
// the model can make (node sets, recorders, initial stress, formulas) are fuzzed too; a huge
// model is valid input but would only measure the allocator.
//
// Text after a line "#%overrides" is taken as command-line overrides, one "key=value" a line, as
// `tsuchi run --set` passes them, so that path is fuzzed as well.
#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/model/model.hpp"
#include "tsuchi/run/recorder.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace {

using namespace tsuchi;

constexpr double kMaxNodes = 1e5, kMaxParticles = 1e5, kMaxWork = 2e6;

// Grid nodes and an upper bound of the particles build_model would make, and the work of the
// loops over them (nodes per node set, particles per recorder).
bool small_enough(const Config& c) {
  double nodes = 1.0, particles = 0.0;
  for (int d = 0; d < c.dimension; ++d) nodes *= c.grid.cells[d] + 1.0;
  for (const auto& b : c.bodies) {
    double n = 1.0;
    if (b.particles) {
      n = static_cast<double>(b.particles->x.size());
    } else if (b.shape) {
      // The lattice of the shape's bounds clipped to the grid, as build_model places it.
      const geometry::Bounds bb = b.shape->bounds();
      for (int d = 0; d < c.dimension; ++d) {
        const double lo = std::max(bb.min[d], c.grid.origin[d]);
        const double hi = std::min(bb.max[d], c.grid.origin[d] + c.grid.extent[d]);
        n *= std::max(0.0, hi - lo) / c.grid.cell_size * b.particles_per_cell[d] + 2.0;
      }
    }
    if (!std::isfinite(n)) return false;
    particles += n;
  }
  const double work = nodes * (1.0 + static_cast<double>(c.boundary.node_sets.size())) +
                      particles * (1.0 + static_cast<double>(c.recorders.size() + c.bodies.size()));
  return nodes <= kMaxNodes && particles <= kMaxParticles && work <= kMaxWork;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  omp_set_num_threads(1);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> overrides;
  constexpr std::string_view marker = "\n#%overrides\n";
  if (const auto at = text.find(marker); at != std::string::npos) {
    std::string_view rest = std::string_view(text).substr(at + marker.size());
    while (!rest.empty()) {
      const auto nl = rest.find('\n');
      overrides.emplace_back(rest.substr(0, nl));
      rest = nl == std::string_view::npos ? std::string_view{} : rest.substr(nl + 1);
    }
    text.resize(at + 1);
  }
  Config c;
  try {
    c = read_config_string(text, "fuzz.toml", overrides);
  } catch (const InputError&) {
    return 0;
  }
  if (!small_enough(c)) return 0;
  try {
    if (c.dimension == 3) make_recorders<3>(c, build_model<3>(c));
    else make_recorders<2>(c, build_model<2>(c));
  } catch (const InputError&) {
  }
  return 0;
}
