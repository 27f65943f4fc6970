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
  // Then the sets, each over the nodes of its own box only (a scan of every node per set took
  // 42.5 s for 2e4 one-node sets on 1e6 nodes). Where sets overlap, the last set naming a
  // component decides it: walking the sets from the last, a set drives the components it names
  // that no later set has claimed at the node (`claimed`, a bit per component).
  std::vector<std::uint8_t> claimed(n, 0);
  std::array<std::vector<int>, D> axis;
  for (std::size_t s = configs.size(); s-- > 0;) {
    const auto& sc = configs[s];
    std::uint8_t names = 0, drives = 0;
    for (int d = 0; d < D; ++d) {
      if (sc.fix[d] || sc.driven[d]) names = static_cast<std::uint8_t>(names | (1u << d));
      if (sc.driven[d]) drives = static_cast<std::uint8_t>(drives | (1u << d));
    }
    // Per axis, the node numbers inside [min - tol, max + tol]: candidates one node either side of
    // the division, then the comparison of positions of Grid::position, so no rounding differs.
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
      const auto mine = static_cast<std::uint8_t>(drives & ~claimed[idx]);
      if (mine) sets[s].driven_nodes.push_back(k), sets[s].driven_mask.push_back(mine);
      claimed[idx] = static_cast<std::uint8_t>(claimed[idx] | names);
      g.fixed_g[idx] = static_cast<std::uint8_t>(g.fixed_g[idx] | names);
    }
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
