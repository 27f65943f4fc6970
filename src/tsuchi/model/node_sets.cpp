#include "tsuchi/model/node_sets.hpp"

#include "tsuchi/core/errors.hpp"

#include <fmt/format.h>

#include <array>

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
    // Per component, the set that drives it here (-1: fixed at zero or free).
    std::array<int, D> driver;
    driver.fill(-1);
    const Vec<D> x = g.position(ijk);
    for (std::size_t s = 0; s < configs.size(); ++s) {
      const auto& sc = configs[s];
      bool inside = true;
      for (int d = 0; d < D; ++d) inside = inside && x[d] >= sc.min[d] - tol && x[d] <= sc.max[d] + tol;
      if (!inside) continue;
      sets[s].nodes.push_back(k);
      for (int d = 0; d < D; ++d) {
        if (sc.fix[d]) mask |= static_cast<std::uint8_t>(1u << d), driver[d] = -1;
        if (sc.driven[d]) mask |= static_cast<std::uint8_t>(1u << d), driver[d] = static_cast<int>(s);
      }
    }
    for (std::size_t s = 0; s < configs.size(); ++s) {
      std::uint8_t drives = 0;
      for (int d = 0; d < D; ++d)
        if (driver[d] == static_cast<int>(s)) drives = static_cast<std::uint8_t>(drives | (1u << d));
      if (drives) sets[s].driven_nodes.push_back(k), sets[s].driven_mask.push_back(drives);
    }
    g.fixed_g[idx] = mask;
    if (mask) held.push_back(k);
  }
  for (std::size_t s = 0; s < sets.size(); ++s)
    if (sets[s].nodes.empty())
      throw InputError(fmt::format("{}: key 'boundary.nodes.{}': the box holds no grid node; grid nodes lie "
                                   "at multiples of cell_size from grid.origin",
                                   c.source, s));
}

template void set_boundary_conditions<2>(const Config&, Grid<2>&, std::vector<NodeSet<2>>&, std::vector<std::int64_t>&);
template void set_boundary_conditions<3>(const Config&, Grid<3>&, std::vector<NodeSet<3>>&, std::vector<std::int64_t>&);

}  // namespace tsuchi
