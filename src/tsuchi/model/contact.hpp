#pragma once
// Contact between bodies and against frictional walls, as the step sees it (solver/contact.hpp
// applies it): which grid velocity field each body scatters to, the Coulomb law between each pair
// of fields, which fields are rigid, and the nodes of the frictional grid faces.
//
// Multi-velocity-field contact (Bardenhagen et al. 2000, J. Comput. Phys. 2001): a body in a
// frictional or rough [[contact]] pair gets a velocity field of its own on the grid; bodies joined
// by "bonded" pairs share one; every body named in no frictional or rough pair shares one more.
// Where two fields meet at a node their velocities are corrected against the centre-of-mass
// velocity when they approach. A model with one field (no [[contact]], or only bonded pairs) steps
// on one field exactly as before contact existed.
#include "tsuchi/core/tensor.hpp"
#include "tsuchi/model/config.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace tsuchi {

template <int D>
struct Contact {
  // Friction coefficient of a pair of fields that no [[contact]] names: they share the centre-of-mass
  // velocity at every node where they meet, as bonded bodies do.
  static constexpr double kBonded = -1.0;
  static constexpr double kRough = std::numeric_limits<double>::infinity();

  // Body velocity fields, numbered 1..fields in the grid (field 0 then holds their sum, for the
  // support reactions and the unbalanced-force ratio). 0: contact between bodies is off, every body
  // scatters to field 0.
  int fields = 0;
  std::vector<int> field_of_body;  // per body: its field (1..fields), or 0 when fields == 0
  // friction[(i - 1) * fields + (j - 1)] for fields i != j: mu >= 0, kRough, or kBonded. Symmetric.
  std::vector<double> friction;
  // Per field (index i - 1): the body when the field holds exactly one body and that body's
  // velocity is prescribed in every component (a rigid platen, footing or wall); -1 otherwise. A
  // rigid field moves as prescribed and takes the other fields' contact impulses as its reaction.
  // A free rigid body (bodies.N.rigid_mass) is not one of these: it meets the others with its
  // nodal mass, as a deformable body does, and only its strain and motion are rigid.
  std::vector<int> rigid_body;
  // Names of the bodies in each field, for the summary and messages: field i - 1.
  std::vector<std::vector<int>> bodies_of_field;

  // A grid face with BoundaryConfig::face_condition Friction: a rigid wall at rest.
  struct Wall {
    int face = 0;                    // axis * 2 + side (side 1: the upper face)
    Vec<D> normal = Vec<D>::Zero();  // unit, out of the grid (from the material into the wall)
    double friction = 0.0;           // mu, or kRough
    std::vector<std::int64_t> nodes; // grid slots of the face's nodes, increasing
  };
  std::vector<Wall> walls;

  bool between_bodies() const { return fields > 1; }
  bool active() const { return fields > 1 || !walls.empty(); }
  double law(int field_i, int field_j) const {
    return friction[static_cast<std::size_t>((field_i - 1) * fields + (field_j - 1))];
  }
};

// Fields, laws and walls from the input's [[contact]] and boundary faces; throws InputError (with
// the entry's `where`) for a pair whose bodies a chain of bonded pairs joins, and for two pairs that
// give the same two fields different laws. Needs the model's grid (index_axes done) and motion.
template <int D>
struct Model;
template <int D>
Contact<D> build_contact(const Config& config, const Model<D>& model);

}  // namespace tsuchi
