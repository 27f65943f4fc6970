#pragma once
// The grid's velocity conditions as the step uses them: which components of which node are held
// (Grid::fixed_g), and the node sets of [[boundary.nodes]] with their driven motion (base motion)
// and their nodes, for the reactions of faces and node sets (docs/input.md "[boundary]").
#include "tsuchi/core/tensor.hpp"
#include "tsuchi/core/time_function.hpp"
#include "tsuchi/grid/grid.hpp"
#include "tsuchi/model/config.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace tsuchi {

template <int D>
struct NodeSet {
  std::string name;                  // "" when unnamed
  std::vector<std::int64_t> nodes;   // grid slots inside its box, increasing
  // Base motion: the driven components follow velocity(t). At each node of driven_nodes this set
  // decides the components of driven_mask (bit d): a later set naming a component overrides it.
  NodeSetConfig::Drive drive = NodeSetConfig::Drive::None;
  Vec<D> value = Vec<D>::Zero();  // m/s or m/s^2
  Vec<D> v0 = Vec<D>::Zero();     // Acceleration: velocity at t = 0
  TimeFunction f;
  std::vector<std::int64_t> driven_nodes;
  std::vector<std::uint8_t> driven_mask;

  // v(t) = value f(t) for a velocity history, v(t) = v0 + value * F(t) for an acceleration, with
  // F(t) = integral_0^t f (solver/held_nodes.hpp: FunctionIntegral). Only the driven components
  // mean anything.
  Vec<D> velocity(double t, double F) const {
    if (drive == NodeSetConfig::Drive::Velocity) return value * f(t);
    return v0 + value * F;
  }
};

// Grid::fixed_g from the faces' conditions and the node sets, and the node sets themselves.
// Faces first, then the sets in input order, each deciding the components it names (fixed at zero
// or driven) at the nodes of its box: where sets overlap, the later one wins for a component both
// name. fixed_g bit d is set where component d is held, at zero or at a driven value. `held`
// gets every slot with a held component, increasing. Throws InputError for a set whose box holds
// no node.
template <int D>
void set_boundary_conditions(const Config& c, Grid<D>& g, std::vector<NodeSet<D>>& sets,
                             std::vector<std::int64_t>& held);

extern template void set_boundary_conditions<2>(const Config&, Grid<2>&, std::vector<NodeSet<2>>&,
                                                std::vector<std::int64_t>&);
extern template void set_boundary_conditions<3>(const Config&, Grid<3>&, std::vector<NodeSet<3>>&,
                                                std::vector<std::int64_t>&);

}  // namespace tsuchi
