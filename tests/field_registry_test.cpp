// The field registries (issue 14): a constitutive model's state fields become particle columns,
// frame fields, recorder quantities and checkpoint sections under one name, with nothing listed
// by hand; the time step reads the model's stiffness.
#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/checkpoint.hpp"
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/model/particle_fields.hpp"
#include "tsuchi/run/recorder.hpp"
#include "tsuchi/solver/time_step.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

namespace {

using namespace tsuchi;

const std::string kBlock = R"([model]
dimension = 2

[grid]
origin = [0.0, 0.0]
extent = [0.4, 0.4]
cell_size = 0.05

[[materials]]
name = "soil"
model = "mohr_coulomb"
density = 1600.0
shear_modulus = 2.0e6
poisson_ratio = 0.25
cohesion = 5.0e3
friction_angle = 30.0

[[bodies]]
name = "block"
material = "soil"
min = [0.1, 0.1]
max = [0.3, 0.3]
velocity = [0.5, 0.0]

[time]
end = 0.01
courant = 0.5

[output]
frames = false

[[recorders]]
name = "yielded"
quantity = "yielded"

[[recorders]]
name = "worst_mode"
quantity = "yield_mode"
reduction = "max"

[[recorders]]
name = "c_factor"
quantity = "cohesion_factor"
)";

bool contains(const std::vector<std::string>& v, std::string_view s) { return std::find(v.begin(), v.end(), s) != v.end(); }

// Every state field of every registered model is a particle field, a frame field and a recorder
// quantity, under its own name, and a particle column when a material of the model has it; the
// registry's names are unique.
TEST(FieldRegistry, EveryStateFieldIsAFrameFieldRecorderQuantityAndColumn) {
  const auto frames = frame_field_names();
  const auto quantities = recorder_quantities(2);
  const Model<2> m = build_model<2>(read_config_string(kBlock, "block.toml"));
  std::vector<std::string> arrays;
  m.particles.for_each_array([&](const char* name, const auto&) { arrays.emplace_back(name); });
  ASSERT_FALSE(material_state_fields().empty());
  for (const StateField& f : material_state_fields()) {
    const std::string name(f.name);
    EXPECT_NE(find_particle_field(name), nullptr) << name;
    EXPECT_TRUE(contains(frames, name)) << name;
    EXPECT_TRUE(contains(quantities, name)) << name;
    // A column (and checkpoint section) exactly for the fields of the model's materials (the
    // block is Mohr-Coulomb); the others read as their initial value.
    const bool held = MohrCoulomb::state_fields.end() !=
                      std::find_if(MohrCoulomb::state_fields.begin(), MohrCoulomb::state_fields.end(),
                                   [&](const StateField& g) { return g.name == f.name; });
    EXPECT_EQ(contains(arrays, name), held) << name;
    const auto* column = m.particles.state_column(name);
    ASSERT_EQ(column != nullptr, held) << name;
    if (column) {
      for (double v : *column) ASSERT_EQ(v, f.initial) << name;
    }
    const int k = state_column(name);
    for (std::size_t i = 0; i < m.particles.size(); ++i) ASSERT_EQ(m.particles.state_value(static_cast<std::size_t>(k), i), f.initial) << name;
    if (!f.indicator.empty()) {
      EXPECT_TRUE(contains(quantities, f.indicator)) << f.indicator;
      EXPECT_FALSE(contains(frames, f.indicator)) << f.indicator;  // a recorder quantity only
    }
  }
  std::set<std::string> names;
  for (const auto& f : particle_fields()) EXPECT_TRUE(names.insert(f.name).second) << f.name << " twice";
  // A state field named like a built-in array would give the checkpoint two sections of one name.
  std::set<std::string> sections;
  for (const auto& a : arrays) EXPECT_TRUE(sections.insert(a).second) << "particle array " << a << " twice";
}

// Vectors record their D components, symmetric tensors their Voigt entries (4 in 2D, 6 in 3D).
TEST(FieldRegistry, ComponentsFollowTheDimension) {
  const auto q2 = recorder_quantities(2), q3 = recorder_quantities(3);
  EXPECT_TRUE(contains(q2, "velocity_y"));
  EXPECT_FALSE(contains(q2, "velocity_z"));
  EXPECT_TRUE(contains(q3, "velocity_z"));
  EXPECT_TRUE(contains(q2, "stress_xy"));
  EXPECT_FALSE(contains(q2, "stress_xz"));
  EXPECT_TRUE(contains(q3, "stress_xz"));
  const auto hit = find_recorder_quantity("stress_xy", 2);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->first->name, "stress");
  EXPECT_EQ(hit->second, 3);  // Voigt order xx, yy, zz, xy
  EXPECT_FALSE(find_recorder_quantity("stress_xy_", 2).has_value());
}

// Recorders read state columns through the registry: the flag's indicator is the fraction of
// nonzero entries, the flag itself its largest value, a factor without imperfection its initial 1.
TEST(FieldRegistry, RecordersReadStateColumns) {
  const Config c = read_config_string(kBlock, "block.toml");
  Model<2> m = build_model<2>(c);
  auto& mode = *m.particles.state_column("yield_mode");
  for (std::size_t i = 0; i < mode.size(); ++i) mode[i] = static_cast<double>(i % 3);
  const auto rec = make_recorders<2>(c, m);
  std::size_t nonzero = 0;
  for (double v : mode) nonzero += v != 0.0;
  EXPECT_DOUBLE_EQ(rec[0].value(m.particles), static_cast<double>(nonzero) / static_cast<double>(mode.size()));
  EXPECT_EQ(rec[1].value(m.particles), 2.0);
  EXPECT_EQ(rec[2].value(m.particles), 1.0);
}

// The stable step from the model's stiffness: h / (sqrt((K + 4G/3) / rho) + |v|), eq of time_step.hpp.
TEST(FieldRegistry, TimeStepUsesTheModelsStiffness) {
  const Model<2> m = build_model<2>(read_config_string(kBlock, "block.toml"));
  const double G = 2.0e6, nu = 0.25, K = 2.0 * G * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu));
  const double expected = 0.05 / (std::sqrt((K + 4.0 * G / 3.0) / 1600.0) + 0.5);
  EXPECT_NEAR(critical_time_step<2>(m.particles, m.materials, m.grid.h), expected, 1e-12 * expected);
}

// A flag column is written to frames as a byte: a checkpoint holding anything else is refused.
TEST(FieldRegistry, CheckpointRefusesAFlagOutOfRange) {
  tsuchi::test::TempDir tmp("tsuchi_registry");
  Model<2> m = build_model<2>(read_config_string(kBlock, "block.toml"));
  (*m.particles.state_column("yield_mode"))[3] = 300.0;
  const std::string file = (tmp.path / "c.tsuchi").string();
  write_checkpoint<2>(file, m, RunProgress{});
  Model<2> fresh = build_model<2>(read_config_string(kBlock, "block.toml"));
  try {
    read_checkpoint<2>(file, fresh);
    ADD_FAILURE() << "a yield mode of 300 was accepted";
  } catch (const InputError& e) {
    tsuchi::test::expect_message(e.what(), {"yield_mode = 300", "whole number from 0 to 255"});
  }
  (*m.particles.state_column("yield_mode"))[3] = 2.0;
  write_checkpoint<2>(file, m, RunProgress{});
  EXPECT_NO_THROW(read_checkpoint<2>(file, fresh));
}

}  // namespace
