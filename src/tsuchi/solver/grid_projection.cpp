#include "tsuchi/solver/grid_projection.hpp"

#include "tsuchi/shape/gimp.hpp"
#include "tsuchi/shape/linear.hpp"
#include "tsuchi/shape/stencil.hpp"

#include <algorithm>
#include <limits>

namespace tsuchi {

bool is_projectable_field(const ParticleField& f) {
  switch (f.quantity) {
    case Quantity::Position: case Quantity::Id: case Quantity::Radius: case Quantity::Volume: case Quantity::Mass:
    case Quantity::Density: case Quantity::MaterialIndex: case Quantity::BodyIndex: case Quantity::StateIndicator:
      return false;
    default: return f.frame && f.type == FieldType::Float64;
  }
}

std::vector<std::string> projectable_field_names() {
  std::vector<std::string> names;
  for (const ParticleField& f : particle_fields())
    if (is_projectable_field(f)) names.push_back(f.name);
  return names;
}

namespace {

// Particle p's weights S_ip per axis and its nodes' grid indices, the kernel's own weights, with a
// node beyond the grid's edge taken as the edge node (see grid_projection.hpp).
template <int D, class Kernel>
struct AxisWeights {
  std::array<std::array<double, Kernel::K>, D> w;
  std::array<std::array<int, Kernel::K>, D> node;

  void compute(const Grid<D>& grid, const Vec<D>& x, const Vec<D>& lp) {
    std::array<Eigen::Array<double, D, 1>, Kernel::K> wa, dwa;
    const Eigen::Array<int, D, 1> node0 =
        Kernel::template weights<D>(Stencil<D, Kernel>::in_cells(grid, x), grid.inv_h, lp.array(), wa, dwa);
    for (int d = 0; d < D; ++d)
      for (int k = 0; k < Kernel::K; ++k) {
        w[d][k] = wa[k][d];
        node[d][k] = std::clamp(node0[d] + k, 0, grid.n_nodes[d] - 1);
      }
  }
};

template <int D, class Kernel>
void project_with(const Model<D>& model, GridProjection<D>& g) {
  constexpr int K = Kernel::K;
  constexpr int N = D == 2 ? K * K : K * K * K;
  const Grid<D>& grid = model.grid;
  const Particles<D>& p = model.particles;
  if (p.size() == 0) return;
  // The box: every node some particle's stencil reaches (inside the grid, by the clamp).
  std::array<int, D> lo, hi;
  lo.fill(std::numeric_limits<int>::max());
  hi.fill(std::numeric_limits<int>::min());
  AxisWeights<D, Kernel> a;
  for (std::size_t i = 0; i < p.size(); ++i) {
    a.compute(grid, p.x_p[i], p.l_p[i]);
    for (int d = 0; d < D; ++d) lo[d] = std::min(lo[d], a.node[d][0]), hi[d] = std::max(hi[d], a.node[d][K - 1]);
  }
  for (int d = 0; d < D; ++d) g.first[d] = lo[d], g.count[d] = hi[d] - lo[d] + 1;
  const std::size_t nodes = g.nodes(), stride = static_cast<std::size_t>(g.stride);
  g.m.assign(nodes, 0.0);
  g.V.assign(nodes, 0.0);
  g.values.assign(nodes * stride, 0.0);
  std::vector<double> q(stride);
  for (std::size_t i = 0; i < p.size(); ++i) {
    a.compute(grid, p.x_p[i], p.l_p[i]);
    for (std::size_t f = 0; f < g.fields.size(); ++f)
      for (int c = 0; c < g.components[f]; ++c)
        q[static_cast<std::size_t>(g.offset[f] + c)] = field_value(*g.fields[f], p, i, c);
    const double m_p = p.m_p[i], V_p = p.V_p[i];
    for (int n = 0; n < N; ++n) {
      // Node n = k_0 + K (k_1 + K k_2) of the stencil: S = prod_d w_d[k_d], eqs (18)-(19).
      double S = 1.0;
      std::array<int, D> ijk;
      for (int d = 0, rest = n; d < D; ++d, rest /= K) {
        S *= a.w[d][rest % K];
        ijk[d] = a.node[d][rest % K];
      }
      if (S == 0.0) continue;  // beyond the GIMP support
      const std::size_t b = g.at(ijk);
      const double Sm = S * m_p;
      g.m[b] += Sm;  // (P1)
      g.V[b] += S * V_p;
      double* const v = g.values.data() + b * stride;
      for (std::size_t j = 0; j < stride; ++j) v[j] += Sm * q[j];
    }
  }
  for (std::size_t b = 0; b < nodes; ++b)
    if (g.m[b] > 0.0) {
      const double inv_m = 1.0 / g.m[b];
      for (std::size_t j = 0; j < stride; ++j) g.values[b * stride + j] *= inv_m;
    }
}

}  // namespace

template <int D>
GridProjection<D> project_to_grid(const Model<D>& model, const std::vector<std::string>& fields) {
  GridProjection<D> g;
  for (const std::string& name : fields) {
    const ParticleField* f = find_particle_field(name);
    if (!f || !is_projectable_field(*f)) continue;  // the input reader accepts projectable fields only
    g.fields.push_back(f);
    g.components.push_back(components(*f, D));
    g.offset.push_back(g.stride);
    g.stride += g.components.back();
  }
  switch (model.step.kernel) {
    case ShapeKind::Linear: project_with<D, shape::LinearKernel>(model, g); break;
    case ShapeKind::UGimp:
    case ShapeKind::Gimp: project_with<D, shape::GimpKernel>(model, g); break;
  }
  return g;
}

template GridProjection<2> project_to_grid<2>(const Model<2>&, const std::vector<std::string>&);
template GridProjection<3> project_to_grid<3>(const Model<3>&, const std::vector<std::string>&);

}  // namespace tsuchi
