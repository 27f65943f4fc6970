// tsuchi-bench: particle-steps per second of the explicit step on elastic blocks with GIMP.
// Usage: tsuchi-bench [--quick]   (quick: smaller blocks, for a smoke run)
// A free elastic block under gravity on a fixed floor, MUSL, GIMP with domain update, no output.
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/solver/explicit_step.hpp"
#include "tsuchi/solver/time_step.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstring>

namespace {

using namespace tsuchi;

std::string block_input(int dim, int cells_per_side) {
  const double h = 1.0 / cells_per_side;
  const std::string three = dim == 3 ? ", 0.0" : "";
  const std::string ext = dim == 3 ? ", 1.5" : "";
  return fmt::format(R"(
[model]
dimension = {0}
gravity = [0.0, -9.81{1}]
[grid]
origin = [0.0, 0.0{1}]
extent = [1.5, 1.5{2}]
cell_size = {3}
[[materials]]
name = "elastic"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[[bodies]]
material = "elastic"
min = [0.25, 0.0{1}]
max = [1.25, 1.0{4}]
particles_per_cell = 2
[boundary]
y_min = "fixed"
[solver]
scheme = "musl"
shape_function = "gimp"
[time]
end = 1.0
courant = 0.5
[output]
frames = false
)",
                     dim, three, ext, h, dim == 3 ? ", 1.0" : "");
}

template <int D>
void measure(int cells_per_side, int steps) {
  const Config c = read_config_string(block_input(D, cells_per_side), "bench");
  Model<D> m = build_model<D>(c);
  ExplicitSolver<D> solver(m);
  const double dt = 0.5 * critical_time_step<D>(m.particles, c.materials, m.grid.h);
  solver.step(dt);  // warm-up: first touch of every array
  const auto t0 = std::chrono::steady_clock::now();
  for (int s = 0; s < steps; ++s) solver.step(dt);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double n = static_cast<double>(m.particles.size());
  fmt::print("{}D elastic block, GIMP, MUSL: {:>9} particles, {:>4} steps, {:8.3f} s, {:.3e} particle-steps/s, "
             "{:.1f} bytes/particle\n",
             D, m.particles.size(), steps, wall, n * steps / wall, static_cast<double>(m.bytes()) / n);
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  if (quick) {
    measure<2>(50, 20);   // 10,000 particles
    measure<3>(10, 10);   // 8,000 particles
  } else {
    measure<2>(250, 50);  // 250,000 particles
    measure<3>(40, 20);   // 512,000 particles
  }
  return 0;
}
