// Contact input (io/config_reader.cpp "[[contact]]", frictional faces) and the velocity fields,
// laws, rigid fields and walls build_contact makes of it (model/contact.cpp).
#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/config_reader.hpp"
#include "tsuchi/model/model.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace {

using namespace tsuchi;
using namespace tsuchi::test;

// Three bodies side by side in a 4 x 3 grid of 1 m cells: base (bottom), specimen, cap (top).
const std::string kThree = R"(
[model]
dimension = 2

[grid]
cell_size = 1.0
extent = [4.0, 3.0]

[[materials]]
name = "soil"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3

[[bodies]]
name = "base"
material = "soil"
min = [0.0, 0.0]
max = [4.0, 1.0]

[[bodies]]
name = "specimen"
material = "soil"
min = [1.0, 1.0]
max = [3.0, 2.0]

[[bodies]]
name = "cap"
material = "soil"
min = [1.0, 2.0]
max = [3.0, 3.0]
prescribed_velocity = { x = 0.0, y = -0.01 }

[time]
end = 0.001
)";

Model<2> build(const std::string& text, const std::vector<std::string>& overrides = {}) {
  return build_model<2>(read_config_string(text, "contact.toml", overrides));
}

std::string input_error(const std::string& text) {
  try {
    build(text);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

TEST(ContactInput, NoContactLeavesOneField) {
  const Model<2> m = build(kThree);
  EXPECT_EQ(m.contact.fields, 0);
  EXPECT_EQ(m.contact.field_of_body, (std::vector<int>{0, 0, 0}));
  EXPECT_TRUE(m.contact.friction.empty());
  EXPECT_TRUE(m.contact.rigid_body.empty());
  EXPECT_TRUE(m.contact.bodies_of_field.empty());
  EXPECT_TRUE(m.contact.walls.empty());
  EXPECT_FALSE(m.contact.active());
}

TEST(ContactInput, BondedPairsOnlyLeaveOneField) {
  const Model<2> m = build(kThree + "[[contact]]\nbodies = [\"cap\", \"specimen\"]\nfriction = \"bonded\"\n");
  EXPECT_EQ(m.contact.fields, 0);
  EXPECT_EQ(m.contact.field_of_body, (std::vector<int>{0, 0, 0}));
}

TEST(ContactInput, FrictionalPairGetsTwoFieldsAndTheRestShareOne) {
  const std::string text = kThree + "[[contact]]\nbodies = [\"cap\", \"specimen\"]\nfriction = 0.3\n";
  const Model<2> m = build(text);
  const auto& k = m.contact;
  ASSERT_EQ(k.fields, 3);
  // Numbered by lowest body: base (0, the rest) 1, specimen (1) 2, cap (2) 3.
  EXPECT_EQ(k.field_of_body, (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(k.bodies_of_field, (std::vector<std::vector<int>>{{0}, {1}, {2}}));
  EXPECT_EQ(k.law(2, 3), 0.3);
  EXPECT_EQ(k.law(3, 2), 0.3);
  EXPECT_EQ(k.law(1, 2), Contact<2>::kBonded);
  EXPECT_EQ(k.law(1, 3), Contact<2>::kBonded);
  // Only the cap is prescribed in every component; the rest holds no prescribed body.
  EXPECT_EQ(k.rigid_body, (std::vector<int>{-1, -1, 2}));

  // Prescribed along y only: not rigid.
  const Model<2> y_only = build(replace(text, "{ x = 0.0, y = -0.01 }", "{ y = -0.01 }"));
  EXPECT_EQ(y_only.contact.rigid_body, (std::vector<int>{-1, -1, -1}));
}

TEST(ContactInput, FieldsDoNotDependOnTheOrderOfTheTables) {
  const Model<2> m = build(kThree + "[[contact]]\nbodies = [\"specimen\", \"cap\"]\nfriction = \"rough\"\n");
  EXPECT_EQ(m.contact.field_of_body, (std::vector<int>{1, 2, 3}));
  EXPECT_TRUE(std::isinf(m.contact.law(2, 3)));
}

TEST(ContactInput, BondedPairMergesBodiesIntoOneField) {
  const Model<2> m = build(kThree +
                           "[[contact]]\nbodies = [\"specimen\", \"base\"]\nfriction = \"bonded\"\n"
                           "[[contact]]\nbodies = [\"cap\", \"specimen\"]\nfriction = \"rough\"\n");
  const auto& k = m.contact;
  ASSERT_EQ(k.fields, 2);
  EXPECT_EQ(k.field_of_body, (std::vector<int>{1, 1, 2}));
  EXPECT_EQ(k.bodies_of_field, (std::vector<std::vector<int>>{{0, 1}, {2}}));
  EXPECT_EQ(k.law(1, 2), Contact<2>::kRough);
  EXPECT_EQ(k.rigid_body, (std::vector<int>{-1, 2}));
}

TEST(ContactInput, FrictionalPairJoinedByBondedChainIsRefused) {
  const std::string msg = input_error(kThree +
                                      "[[contact]]\nbodies = [\"specimen\", \"base\"]\nfriction = \"bonded\"\n"
                                      "[[contact]]\nbodies = [\"cap\", \"base\"]\nfriction = \"bonded\"\n"
                                      "[[contact]]\nbodies = [\"cap\", \"specimen\"]\nfriction = 0.2\n");
  expect_message(msg, {"key 'contact.2'", "bodies \"cap\" and \"specimen\" are joined by bonded pairs"});
}

TEST(ContactInput, TwoLawsForTheSameFieldsAreRefused) {
  const std::string msg = input_error(kThree +
                                      "[[contact]]\nbodies = [\"specimen\", \"base\"]\nfriction = \"bonded\"\n"
                                      "[[contact]]\nbodies = [\"cap\", \"specimen\"]\nfriction = 0.2\n"
                                      "[[contact]]\nbodies = [\"cap\", \"base\"]\nfriction = 0.4\n");
  expect_message(msg, {"key 'contact.2'", "contact.1", "friction 0.4", "friction 0.2"});
}

TEST(ContactInput, FrictionalWallNodesNormalAndCoefficient) {
  const Model<2> m = build(kThree + "[boundary]\ny_min = { friction = 0.5 }\nx_max = { friction = \"rough\" }\n");
  const auto& walls = m.contact.walls;
  EXPECT_EQ(m.contact.fields, 0);
  ASSERT_EQ(walls.size(), 2u);
  // Faces in axis order: x_max (1), then y_min (2).
  EXPECT_EQ(walls[0].face, 1);
  EXPECT_TRUE(std::isinf(walls[0].friction));
  EXPECT_EQ(walls[0].normal, Vec<2>(1.0, 0.0));
  EXPECT_EQ(walls[0].nodes.size(), 4u);
  const auto& w = walls[1];
  EXPECT_EQ(w.face, 2);
  EXPECT_EQ(w.friction, 0.5);
  EXPECT_EQ(w.normal, Vec<2>(0.0, -1.0));
  ASSERT_EQ(w.nodes.size(), 5u);
  EXPECT_TRUE(std::is_sorted(w.nodes.begin(), w.nodes.end()));
  for (const auto idx : w.nodes) {
    ASSERT_TRUE(m.grid.is_node(idx));
    EXPECT_EQ(m.grid.ijk(idx)[1], 0);
  }
  EXPECT_TRUE(m.contact.active());
}

TEST(ContactInput, FrictionalWallIn3D) {
  const std::string text = R"(
[model]
dimension = 3
[grid]
cell_size = 1.0
extent = [2.0, 3.0, 4.0]
[[materials]]
name = "soil"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[[bodies]]
name = "block"
material = "soil"
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 1.0]
[time]
end = 0.001
[boundary]
z_max = { friction = 0 }
)";
  const Model<3> m = build_model<3>(read_config_string(text, "wall3d.toml"));
  ASSERT_EQ(m.contact.walls.size(), 1u);
  const auto& w = m.contact.walls[0];
  EXPECT_EQ(w.face, 5);
  EXPECT_EQ(w.friction, 0.0);
  EXPECT_EQ(w.normal, Vec<3>(0.0, 0.0, 1.0));
  ASSERT_EQ(w.nodes.size(), 12u);  // 3 x 4 nodes
  for (const auto idx : w.nodes) EXPECT_EQ(m.grid.ijk(idx)[2], 4);
}

TEST(ContactInput, ContactAndFaceFrictionChangeTheFingerprint) {
  const std::string pair = kThree + "[[contact]]\nbodies = [\"cap\", \"specimen\"]\nfriction = 0.3\n";
  const auto fp = [](const std::string& text, const std::vector<std::string>& o = {}) {
    return read_config_string(text, "contact.toml", o).fingerprint;
  };
  EXPECT_NE(fp(kThree), fp(pair));
  EXPECT_NE(fp(pair), fp(pair, {"contact.0.friction=0.4"}));
  EXPECT_NE(fp(pair), fp(pair, {"contact.0.friction=\"rough\""}));
  const std::string wall = kThree + "[boundary]\ny_min = { friction = 0.5 }\n";
  EXPECT_NE(fp(wall), fp(wall, {"boundary.y_min={ friction = 0.6 }"}));
  EXPECT_NE(fp(wall), fp(wall, {"boundary.y_min=\"roller\""}));
}

TEST(ContactInput, ReaderMessages) {
  const auto reader_error = [](const std::string& text) {
    try {
      read_config_string(text, "contact.toml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    ADD_FAILURE() << "no InputError";
    return std::string();
  };
  expect_message(reader_error(kThree + "[[contact]]\nbodies = [\"cap\", \"lid\"]\nfriction = 0.3\n"),
                 {"key 'contact.0.bodies'", "\"base\", \"specimen\", \"cap\"", "got \"lid\""});
  expect_message(reader_error(kThree + "[[contact]]\nbodies = [\"cap\"]\nfriction = 0.3\n"),
                 {"key 'contact.0.bodies'", "got 1 entries"});
  expect_message(reader_error(kThree + "[[contact]]\nbodies = [\"cap\", \"cap\"]\nfriction = 0.3\n"),
                 {"expected two different bodies", "\"cap\" twice"});
  expect_message(reader_error(kThree + "[[contact]]\nbodies = [\"cap\", \"base\"]\n"),
                 {"missing key 'contact.0.friction'"});
  expect_message(reader_error(kThree + "[[contact]]\nbodies = [\"cap\", \"base\"]\nfriction = -0.1\n"),
                 {"key 'contact.0.friction'", "expected a friction coefficient >= 0, \"rough\" or \"bonded\"", "got -0.1"});
  expect_message(reader_error(kThree + "[[contact]]\nbodies = [\"cap\", \"base\"]\nfriction = 0.1\nmu = 0.1\n"),
                 {"unknown key 'contact.0.mu'"});
  expect_message(reader_error(kThree + "[[contact]]\nbodies = [\"cap\", \"base\"]\nfriction = 0.1\n"
                                       "[[contact]]\nbodies = [\"base\", \"cap\"]\nfriction = 0.2\n"),
                 {"key 'contact.1.bodies'", "paired already in contact.0"});
  expect_message(reader_error(kThree + "[boundary]\ny_min = { friction = \"bonded\" }\n"),
                 {"key 'boundary.y_min.friction'", "expected a friction coefficient >= 0 or \"rough\""});
  expect_message(reader_error(kThree + "[boundary]\ny_min = { mu = 0.3 }\n"), {"unknown key 'boundary.y_min.mu'"});
  expect_message(reader_error(kThree + "[boundary]\ny_min = 0.3\n"),
                 {"key 'boundary.y_min'", "expected one of \"free\", \"roller\", \"fixed\" or a table { friction = MU }"});
  // The words of today's faces still read, in any case.
  const Config c = read_config_string(kThree + "[boundary]\ny_min = \"Fixed\"\nx_min = \"roller\"\n", "contact.toml");
  EXPECT_EQ(c.boundary.faces[1][0], FaceCondition::Fixed);
  EXPECT_EQ(c.boundary.faces[0][0], FaceCondition::Roller);
  EXPECT_EQ(c.boundary.faces[0][1], FaceCondition::Free);
}

}  // namespace
