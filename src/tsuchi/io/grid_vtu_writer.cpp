#include "tsuchi/io/grid_vtu_writer.hpp"

#include "tsuchi/core/version.hpp"
#include "tsuchi/io/vtk_xml.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace tsuchi {

namespace {

// The box nodes a grid frame holds (m_i > 0), numbered in box order: the point of each, or -1.
template <int D>
std::vector<std::int64_t> points_of(const GridProjection<D>& g, std::size_t& points) {
  std::vector<std::int64_t> point(g.nodes(), -1);
  points = 0;
  for (std::size_t b = 0; b < point.size(); ++b)
    if (g.m[b] > 0.0) point[b] = static_cast<std::int64_t>(points++);
  return point;
}

// Calls f(corners) for each grid cell of the box whose 2^D nodes all have mass, the corners in
// VTK's order (VTK_QUAD: counter-clockwise; VTK_HEXAHEDRON: the face at the lower z
// counter-clockwise seen from above, then the one above it).
template <int D, class F>
void for_each_cell(const GridProjection<D>& g, const std::vector<std::int64_t>& point, F&& f) {
  constexpr int corners = D == 2 ? 4 : 8;
  constexpr int square[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::array<std::int64_t, corners> c{};
  for (std::size_t b = 0; b < point.size(); ++b) {
    const std::array<int, D> lo = g.ijk(b);
    bool whole = true;
    for (int d = 0; d < D; ++d) whole = whole && lo[d] + 1 < g.first[d] + g.count[d];
    if (!whole) continue;
    for (int k = 0; k < corners && whole; ++k) {
      std::array<int, D> n = lo;
      n[0] += square[k % 4][0], n[1] += square[k % 4][1];
      if constexpr (D == 3) n[2] += k / 4;
      c[static_cast<std::size_t>(k)] = point[g.at(n)];
      whole = c[static_cast<std::size_t>(k)] >= 0;
    }
    if (whole) f(c);
  }
}

template <int D> constexpr std::uint8_t vtk_cell_type() { return D == 2 ? 9 : 12; }

// A frame stores vectors with 3 components and symmetric tensors with 6, in 2D too (as the
// particle frames: ParaView's order XX, YY, ZZ, XY, YZ, XZ).
int frame_components(const ParticleField& f) { return f.kind == FieldKind::Vector ? 3 : f.kind == FieldKind::Tensor ? 6 : 1; }

}  // namespace

template <int D>
std::string grid_vtu_document(const Model<D>& model, const GridProjection<D>& g) {
  std::size_t n = 0;
  const std::vector<std::int64_t> point = points_of(g, n);
  std::vector<std::int64_t> connectivity, offsets;
  for_each_cell(g, point, [&](const auto& c) {
    connectivity.insert(connectivity.end(), c.begin(), c.end());
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
  });
  const std::size_t cells = offsets.size();
  // Units and meanings, as the particle frames give them, and how the nodal values were formed.
  std::vector<std::string> units{
      fmt::format("mass [{}]: nodal mass m_i = sum_p S_ip m_p", unit_in("kg (kg/m in 2D)", D)),
      "density [kg/m^3]: m_i / V_i, V_i = sum_p S_ip V_p"};
  for (const ParticleField* f : g.fields)
    units.push_back(fmt::format("{} [{}]: {}, nodal value sum_p S_ip m_p q_p / m_i", f->name, unit_in(f->unit, D),
                                f->description));
  std::vector<std::string> conventions = frame_conventions(D);
  conventions.push_back(fmt::format(
      "grid nodes: cell size {:.9g} m, the run's {} shape functions S_ip at the particles' positions of the frame; "
      "points only where m_i > 0, cells where all their nodes have mass",
      model.grid.h, to_string(model.step.kernel)));
  const bool shear = std::any_of(g.fields.begin(), g.fields.end(), [](const ParticleField* f) { return f->name == "max_shear_strain"; });
  std::string xml = fmt::format(
      "<?xml version=\"1.0\"?>\n"
      "<!-- written by tsuchi {}: the particles' fields on the background grid's nodes -->\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <UnstructuredGrid>\n"
      "    <FieldData>\n{}{}    </FieldData>\n"
      "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n"
      "      <PointData{}>\n",
      version, vtk_string_array("units", units), vtk_string_array("conventions", conventions), n, cells,
      shear ? " Scalars=\"max_shear_strain\"" : "");
  VtkAppendedArrays b;
  std::vector<double> mass, density, x(3 * n, 0.0);
  mass.reserve(n), density.reserve(n);
  for (std::size_t k = 0; k < point.size(); ++k)
    if (point[k] >= 0) {
      mass.push_back(g.m[k]);
      density.push_back(g.V[k] > 0.0 ? g.m[k] / g.V[k] : 0.0);
      const Vec<D> at = model.grid.position(g.ijk(k));
      for (int d = 0; d < D; ++d) x[3 * static_cast<std::size_t>(point[k]) + static_cast<std::size_t>(d)] = at[d];
    }
  b.array(xml, "Float64", "mass", 1, mass);
  b.array(xml, "Float64", "density", 1, density);
  for (std::size_t f = 0; f < g.fields.size(); ++f) {
    const int components = frame_components(*g.fields[f]);
    std::vector<double> a(static_cast<std::size_t>(components) * n, 0.0);
    for (std::size_t k = 0; k < point.size(); ++k)
      if (point[k] >= 0)
        for (int c = 0; c < g.components[f]; ++c)
          a[static_cast<std::size_t>(components * point[k] + c)] =
              g.values[k * static_cast<std::size_t>(g.stride) + static_cast<std::size_t>(g.offset[f] + c)];
    b.array(xml, "Float64", g.fields[f]->name, components, a);
  }
  xml += "      </PointData>\n      <Points>\n";
  b.array(xml, "Float64", "", 3, x);
  xml += "      </Points>\n      <Cells>\n";
  b.array(xml, "Int64", "connectivity", 1, connectivity);
  b.array(xml, "Int64", "offsets", 1, offsets);
  b.array(xml, "UInt8", "types", 1, std::vector<std::uint8_t>(cells, vtk_cell_type<D>()));
  xml += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _";
  xml += b.blob();
  xml += "\n  </AppendedData>\n</VTKFile>\n";
  return xml;
}

template <int D>
GridFrameSize grid_vtu_size(const Model<D>& model, const std::vector<std::string>& fields) {
  GridFrameSize s;
  const GridProjection<D> mass_only = project_to_grid<D>(model, {});
  const std::vector<std::int64_t> point = points_of(mass_only, s.points);
  for_each_cell(mass_only, point, [&](const auto&) { ++s.cells; });
  double per_point = 3 * 8 + 2 * 8;  // the point, its mass and density
  for (const auto& name : fields)
    if (const ParticleField* f = find_particle_field(name); f && is_projectable_field(*f))
      per_point += 8.0 * frame_components(*f);
  const double per_cell = (D == 2 ? 4 : 8) * 8 + 8 + 1;  // connectivity, offset, type
  // The XML around the arrays is that of a frame without nodes, but for the digits of the arrays'
  // offsets and of the point and cell counts (at most 20 each).
  Model<D> none;
  none.grid.h = model.grid.h;
  none.step.kernel = model.step.kernel;
  const double header = static_cast<double>(grid_vtu_document<D>(none, project_to_grid<D>(none, fields)).size()) +
                        20.0 * static_cast<double>(fields.size() + 8);
  s.bytes = header + per_point * static_cast<double>(s.points) + per_cell * static_cast<double>(s.cells);
  return s;
}

template std::string grid_vtu_document<2>(const Model<2>&, const GridProjection<2>&);
template std::string grid_vtu_document<3>(const Model<3>&, const GridProjection<3>&);
template GridFrameSize grid_vtu_size<2>(const Model<2>&, const std::vector<std::string>&);
template GridFrameSize grid_vtu_size<3>(const Model<3>&, const std::vector<std::string>&);

}  // namespace tsuchi
