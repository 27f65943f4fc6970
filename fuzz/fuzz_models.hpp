#pragma once
// The two small models the checkpoint fuzzer decodes into, and from which its seed checkpoints
// are written (fuzz/make_seeds.cpp): a 2D and a 3D Mohr-Coulomb block under an isotropic initial
// stress, with a strength imperfection, a recorder and checkpoints every step. Small on purpose:
// every input copies the model and, when it decodes, takes one explicit step from it.
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/model/model.hpp"

#include <string>

namespace tsuchi::fuzz {

inline const std::string kModel2D = R"([model]
dimension = 2
title = "checkpoint fuzzing, 2D"
gravity = [0.0, -9.81]

[grid]
origin = [0.0, 0.0]
extent = [0.4, 0.4]
cell_size = 0.1

[[materials]]
name = "soil"
model = "mohr_coulomb"
density = 1530.0
shear_modulus = 8.514e6
poisson_ratio = 0.2
cohesion = 8.5e3
friction_angle = 30.5
dilatancy_angle = 5.0
tension_strength = 1.0e3

[[bodies]]
name = "specimen"
material = "soil"
min = [0.1, 0.1]
max = [0.3, 0.3]
particles_per_cell = 2

[bodies.initial_stress]
isotropic = -10.0e3
subtract = true

[bodies.imperfection]
amplitude = 0.1
seed = 7

[boundary]
y_min = "fixed"
x_min = "roller"

[solver]
scheme = "musl"
shape_function = "gimp"
damping = 0.05

[time]
end = 1.0
courant = 0.5
max_steps = 3

[output]
directory = "results"
fields = ["stress", "plastic_shear_strain"]

[checkpoint]
every_steps = 1

[[recorders]]
name = "mean_stress_kPa"
body = "specimen"
quantity = "stress_yy"
scale = -1.0e-3
stop_above = 1.0e6
)";

inline const std::string kModel3D = R"([model]
dimension = 3
title = "checkpoint fuzzing, 3D"

[grid]
origin = [0.0, 0.0, 0.0]
extent = [0.3, 0.3, 0.3]
cell_size = 0.1

[[materials]]
name = "soil"
model = "mohr_coulomb"
density = 1530.0
youngs_modulus = 20.0e6
poisson_ratio = 0.25
cohesion = 5.0e3
friction_angle = 35.0

[[bodies]]
name = "block"
material = "soil"
min = [0.1, 0.1, 0.1]
max = [0.2, 0.2, 0.2]
particles_per_cell = 2
velocity = [0.0, "0.01 * x", 0.0]

[bodies.initial_stress]
isotropic = -5.0e3
subtract = true

[bodies.imperfection]
amplitude = 0.05
seed = 3
parameters = ["cohesion"]

[solver]
scheme = "usl"
shape_function = "ugimp"

[time]
end = 1.0
dt = 1.0e-5
max_steps = 3

[output]
frames = true

[checkpoint]
every_steps = 1

[[recorders]]
name = "largest_shear"
quantity = "max_shear_strain"
reduction = "max"
)";

template <int D>
Config small_config() {
  return read_config_string(D == 2 ? kModel2D : kModel3D, D == 2 ? "fuzz2d.toml" : "fuzz3d.toml");
}

template <int D>
Model<D> small_model() {
  return build_model<D>(small_config<D>());
}

}  // namespace tsuchi::fuzz
