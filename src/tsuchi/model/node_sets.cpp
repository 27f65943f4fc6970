#include "tsuchi/model/node_sets.hpp"

#include "tsuchi/core/errors.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace tsuchi {

template <int D>
void set_boundary_conditions(const Config& c, Grid<D>& g, std::vector<NodeSet<D>>& sets,
                             std::vector<std::int64_t>& held) {
  const auto& configs = c.boundary.node_sets;
  sets.assign(configs.size(), NodeSet<D>{});
  for (std::size_t s = 0; s < configs.size(); ++s) {
    const auto& sc = configs[s];
    auto& set = sets[s];
    set.name = sc.name;
    set.drive = sc.drive;
    for (int d = 0; d < D; ++d) set.value[d] = sc.value[d], set.v0[d] = sc.initial_velocity[d];
    if (sc.function >= 0) set.f = c.functions[static_cast<std::size_t>(sc.function)].f;
  }
  held.clear();
  const std::size_t n = g.size();
  const double tol = 1e-9 * g.h;
  // The faces' conditions, node by node.
  for (std::size_t idx = 0; idx < n; ++idx) {
    const auto k = static_cast<std::int64_t>(idx);
    if (!g.is_node(k)) continue;
    const auto ijk = g.ijk(k);
    std::uint8_t mask = 0;
    for (int d = 0; d < D; ++d)
      for (int side = 0; side < 2; ++side) {
        const bool on_face = side == 0 ? ijk[d] == 0 : ijk[d] == g.n_nodes[d] - 1;
        if (!on_face) continue;
        switch (c.boundary.faces[d][side]) {
          case FaceCondition::Fixed: mask |= static_cast<std::uint8_t>((1u << D) - 1); break;
          case FaceCondition::Roller: mask |= static_cast<std::uint8_t>(1u << d); break;
          case FaceCondition::Free:
          case FaceCondition::Friction: break;  // a wall the contact stage applies (model/contact.hpp)
        }
      }
    g.fixed_g[idx] = mask;
  }
  // Then the sets in input order, each over the nodes of its own box only (a scan of every node
  // per set took 48 s for 2e4 one-node sets on 1e6 nodes). A later set overrides an earlier one
  // component by component: per node the operations run in set order, as they did node-major.
  // Per node and component, the set that drives it (-1: fixed at zero or free); only when a set drives.
  bool any_driven = false;
  for (const auto& sc : configs)
    for (int d = 0; d < D; ++d) any_driven = any_driven || sc.driven[d];
  std::vector<std::array<int, D>> driver;
  if (any_driven) {
    std::array<int, D> none;
    none.fill(-1);
    driver.assign(n, none);
  }
  std::array<std::vector<int>, D> axis;
  for (std::size_t s = 0; s < configs.size(); ++s) {
    const auto& sc = configs[s];
    // Per axis, the node numbers inside [min - tol, max + tol]: candidates one node either side of
    // the division, then the same comparison of positions as before, so no rounding differs.
    std::size_t count = 1;
    for (int d = 0; d < D; ++d) {
      axis[d].clear();
      const double last = g.n_nodes[d] - 1;
      const double lo = std::clamp(std::floor((sc.min[d] - tol - g.origin[d]) / g.h) - 1.0, 0.0, last);
      const double hi = std::clamp(std::ceil((sc.max[d] + tol - g.origin[d]) / g.h) + 1.0, 0.0, last);
      for (int i = static_cast<int>(lo); i <= static_cast<int>(hi); ++i) {
        const double x = g.origin[d] + g.h * i;  // Grid::position, axis d
        if (x >= sc.min[d] - tol && x <= sc.max[d] + tol) axis[d].push_back(i);
      }
      count *= axis[d].size();
    }
    auto& nodes = sets[s].nodes;
    nodes.reserve(count);
    std::array<std::size_t, D> at{};
    for (std::size_t q = 0; q < count; ++q) {
      std::array<int, D> ijk;
      for (int d = 0; d < D; ++d) ijk[d] = axis[d][at[d]];
      nodes.push_back(g.index(ijk));
      for (int d = 0; d < D && ++at[d] == axis[d].size(); ++d) at[d] = 0;
    }
    std::sort(nodes.begin(), nodes.end());  // node order, as the step and the outputs expect
    for (const std::int64_t k : nodes) {
      const auto idx = static_cast<std::size_t>(k);
      for (int d = 0; d < D; ++d) {
        if (sc.fix[d]) g.fixed_g[idx] |= static_cast<std::uint8_t>(1u << d);
        if (sc.driven[d]) g.fixed_g[idx] |= static_cast<std::uint8_t>(1u << d);
        if (any_driven) {
          if (sc.fix[d]) driver[idx][d] = -1;
          if (sc.driven[d]) driver[idx][d] = static_cast<int>(s);
        }
      }
    }
  }
  if (any_driven)
    for (std::size_t s = 0; s < configs.size(); ++s)
      for (const std::int64_t k : sets[s].nodes) {
        std::uint8_t drives = 0;
        for (int d = 0; d < D; ++d)
          if (driver[static_cast<std::size_t>(k)][d] == static_cast<int>(s)) drives = static_cast<std::uint8_t>(drives | (1u << d));
        if (drives) sets[s].driven_nodes.push_back(k), sets[s].driven_mask.push_back(drives);
      }
  for (std::size_t idx = 0; idx < n; ++idx)
    if (g.fixed_g[idx]) held.push_back(static_cast<std::int64_t>(idx));
  for (std::size_t s = 0; s < sets.size(); ++s)
    if (sets[s].nodes.empty())
      throw InputError(fmt::format("{}: key 'boundary.nodes.{}': the box holds no grid node; grid nodes lie "
                                   "at multiples of cell_size from grid.origin",
                                   c.source, s));
}

template void set_boundary_conditions<2>(const Config&, Grid<2>&, std::vector<NodeSet<2>>&, std::vector<std::int64_t>&);
template void set_boundary_conditions<3>(const Config&, Grid<3>&, std::vector<NodeSet<3>>&, std::vector<std::int64_t>&);

}  // namespace tsuchi
