#pragma once
// The fixed Cartesian background grid: geometry and nodal fields as flat arrays (one per field).
#include "tsuchi/core/tensor.hpp"

#include <cstdint>
#include <vector>

namespace tsuchi {

template <int D>
struct Grid {
  Vec<D> origin = Vec<D>::Zero();
  double h = 1.0;                       // cell size, the same on every axis
  std::array<int, D> n_nodes{};         // nodes per axis = cells + 1

  // Nodal fields, index i + n_x (j + n_y k).
  std::vector<double> m_g;              // mass
  std::vector<Vec<D>> p_g;              // momentum
  std::vector<Vec<D>> f_g;              // internal + external force
  std::vector<Vec<D>> v_g;              // velocity p_g / m_g (before the step, or remapped)
  std::vector<Vec<D>> a_g;              // acceleration
  std::vector<Vec<D>> vL_g;             // updated velocity v^L = v_g + dt a_g
  std::vector<std::uint8_t> fixed_g;    // bit d set: velocity component d held at zero

  std::size_t size() const {
    std::size_t n = 1;
    for (int d = 0; d < D; ++d) n *= static_cast<std::size_t>(n_nodes[d]);
    return n;
  }

  std::int64_t index(const std::array<int, D>& ijk) const {
    std::int64_t idx = ijk[D - 1];
    for (int d = D - 2; d >= 0; --d) idx = idx * n_nodes[d] + ijk[d];
    return idx;
  }

  std::array<int, D> ijk(std::int64_t idx) const {
    std::array<int, D> r{};
    for (int d = 0; d < D; ++d) {
      r[d] = static_cast<int>(idx % n_nodes[d]);
      idx /= n_nodes[d];
    }
    return r;
  }

  Vec<D> position(const std::array<int, D>& ijk_) const {
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = origin[d] + h * ijk_[d];
    return x;
  }

  Vec<D> upper() const {
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = origin[d] + h * (n_nodes[d] - 1);
    return x;
  }

  void allocate() {
    const std::size_t n = size();
    m_g.assign(n, 0.0);
    p_g.assign(n, Vec<D>::Zero());
    f_g.assign(n, Vec<D>::Zero());
    a_g.assign(n, Vec<D>::Zero());
    v_g.assign(n, Vec<D>::Zero());
    vL_g.assign(n, Vec<D>::Zero());
    fixed_g.assign(n, 0);
  }

  std::size_t bytes() const {
    return size() * (sizeof(double) + 5 * sizeof(Vec<D>) + sizeof(std::uint8_t));
  }
};

}  // namespace tsuchi
