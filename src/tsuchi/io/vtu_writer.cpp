#include "tsuchi/io/vtu_writer.hpp"

#include "tsuchi/core/principal.hpp"
#include "tsuchi/core/version.hpp"
#include "tsuchi/io/vtk_xml.hpp"
#include "tsuchi/model/particle_fields.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace tsuchi {

namespace {

// Field f of every particle as the frame stores it: vectors with 3 components and symmetric
// tensors with 6 in ParaView's order XX, YY, ZZ, XY, YZ, XZ (ours too), zero-padded in 2D.
// Point k of a frame is particle order[k]: the particles by increasing id, whatever their storage
// order (the step re-stores them in block order, solver.sort_interval). ParaView matches points
// across frames by index (picking, spreadsheet rows, Temporal Statistics, Pathlines without a
// global-id array): in storage order it silently mixed particles from frame to frame (issue 41).
template <int D>
std::vector<std::size_t> id_order(const Particles<D>& p) {
  std::vector<std::size_t> order(p.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  if (!std::is_sorted(p.id_p.begin(), p.id_p.end()))
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return p.id_p[a] < p.id_p[b]; });
  return order;
}

template <class T, int D>
std::vector<T> field_array(const ParticleField& f, const Particles<D>& p, const std::vector<std::size_t>& order,
                           int components) {
  const std::size_t n = p.size();
  const int used = tsuchi::components(f, D);  // the frame pads vectors to 3 and tensors to 6
  std::vector<T> r(static_cast<std::size_t>(components) * n, T{});
  for (std::size_t k = 0; k < n; ++k)
    for (int c = 0; c < used; ++c)
      r[static_cast<std::size_t>(components) * k + c] = static_cast<T>(field_value(f, p, order[k], c));
  return r;
}

template <int D>
std::vector<double> vectors3(const std::vector<Vec<D>>& v, const std::vector<std::size_t>& order) {
  std::vector<double> r(3 * v.size(), 0.0);
  for (std::size_t k = 0; k < v.size(); ++k)
    for (int d = 0; d < D; ++d) r[3 * k + d] = v[order[k]][d];
  return r;
}

// Field data of a frame: the body names in index order (the point field "body" holds the index);
// each point field's unit and meaning ("stress [Pa]: Cauchy stress, tension positive"), so that the
// units travel with the data (issue 41: a confining stress of -10000 was read as a mistake); and
// the conventions, once.
std::string field_data(const std::vector<std::string>& names, const std::vector<std::string>& fields, int dim) {
  std::vector<std::string> units;
  for (const auto& name : fields)
    if (const ParticleField* f = find_particle_field(name); f && f->frame)
      units.push_back(fmt::format("{} [{}]: {}", f->name, unit_in(f->unit, dim), f->description));
  const std::vector<std::string> conventions = frame_conventions(dim);
  return "    <FieldData>\n" + vtk_string_array("body_names", names) + vtk_string_array("units", units) +
         vtk_string_array("conventions", conventions) + "    </FieldData>\n";
}

// A frame stores vectors with 3 components and symmetric tensors with 6, in 2D too.
int frame_components(const ParticleField& f) { return f.kind == FieldKind::Vector ? 3 : f.kind == FieldKind::Tensor ? 6 : 1; }

std::size_t type_size(FieldType t) {
  switch (t) {
    case FieldType::Float64: case FieldType::Int64: return 8;
    case FieldType::Int32: return 4;
    case FieldType::UInt8: return 1;
  }
  return 8;
}

}  // namespace

template <int D>
double vtu_size(const Model<D>& model, const std::vector<std::string>& fields) {
  double per_point = 3 * 8 + 8 + 8 + 1;  // the point, its connectivity, offset and cell type
  for (const auto& name : fields) {
    const ParticleField* f = find_particle_field(name);
    if (!f || !f->frame) continue;
    per_point += f->quantity == Quantity::Id ? 8 : frame_components(*f) * static_cast<double>(type_size(f->type));
  }
  // The XML around the arrays is that of a frame without particles, but for the digits of the
  // arrays' offsets and of the point count (at most 20 each).
  Model<D> none;
  none.body_names = model.body_names;
  const double header = static_cast<double>(vtu_document<D>(none, fields).size());
  const auto arrays = static_cast<double>(fields.size() + 5);
  return header + 20.0 * (arrays + 2.0) + static_cast<double>(model.particles.size()) * per_point;
}

template <int D>
std::string vtu_document(const Model<D>& model, const std::vector<std::string>& fields) {
  const auto& p = model.particles;
  const std::size_t n = p.size();
  const std::vector<std::size_t> order = id_order(p);
  VtkAppendedArrays b;
  std::string xml = fmt::format(
      "<?xml version=\"1.0\"?>\n"
      "<!-- written by tsuchi {} -->\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <UnstructuredGrid>\n"
      "{}"
      "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n"
      "      <PointData{}>\n",
      version, field_data(model.body_names, fields, D), n, n,
      // The field ParaView colours by when a frame is opened: where the shear bands are.
      std::find(fields.begin(), fields.end(), "max_shear_strain") != fields.end() ? " Scalars=\"max_shear_strain\"" : "");
  for (const auto& name : fields) {
    const ParticleField* f = find_particle_field(name);
    if (!f || !f->frame) continue;  // the input reader accepts frame fields only
    const int components = frame_components(*f);
    if (f->quantity == Quantity::Id) {  // as stored: no round trip through a double
      std::vector<std::int64_t> ids(n);
      for (std::size_t k = 0; k < n; ++k) ids[k] = p.id_p[order[k]];
      b.array(xml, "Int64", name, 1, ids);
      continue;
    }
    switch (f->type) {
      case FieldType::Float64: b.array(xml, "Float64", name, components, field_array<double>(*f, p, order, components)); break;
      case FieldType::Int64: b.array(xml, "Int64", name, components, field_array<std::int64_t>(*f, p, order, components)); break;
      case FieldType::Int32: b.array(xml, "Int32", name, components, field_array<std::int32_t>(*f, p, order, components)); break;
      case FieldType::UInt8: b.array(xml, "UInt8", name, components, field_array<std::uint8_t>(*f, p, order, components)); break;
    }
  }
  xml += "      </PointData>\n      <Points>\n";
  b.array(xml, "Float64", "", 3, vectors3<D>(p.x_p, order));
  xml += "      </Points>\n      <Cells>\n";
  std::vector<std::int64_t> connectivity(n), offsets(n);
  for (std::size_t i = 0; i < n; ++i) {
    connectivity[i] = static_cast<std::int64_t>(i);
    offsets[i] = static_cast<std::int64_t>(i + 1);
  }
  b.array(xml, "Int64", "connectivity", 1, connectivity);
  b.array(xml, "Int64", "offsets", 1, offsets);
  b.array(xml, "UInt8", "types", 1, std::vector<std::uint8_t>(n, 1));  // VTK_VERTEX
  xml += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _";
  xml += b.blob();
  xml += "\n  </AppendedData>\n</VTKFile>\n";
  return xml;
}

// ASCII: a frame holds a few hundred contact nodes at most, and the file stays readable as text.
std::string contact_vtu_document(const ContactPoints& c) {
  const std::size_t n = c.x.size();
  std::string xml = fmt::format(
      "<?xml version=\"1.0\"?>\n"
      "<!-- written by tsuchi {}: grid nodes where contact acted -->\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n",
      version, n, n);
  const auto vectors = [&](const char* name, const std::vector<std::array<double, 3>>& v) {
    std::string s = fmt::format("        <DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"3\" format=\"ascii\">\n", name);
    for (const auto& a : v) s += fmt::format("          {:.9g} {:.9g} {:.9g}\n", a[0], a[1], a[2]);
    return s + "        </DataArray>\n";
  };
  xml += "      <PointData Vectors=\"force\">\n" + vectors("normal", c.normal) + vectors("force", c.force);
  xml += "        <DataArray type=\"Int32\" Name=\"kind\" format=\"ascii\">\n";
  for (const int k : c.kind) xml += fmt::format("          {}\n", k);
  xml += "        </DataArray>\n      </PointData>\n      <Points>\n" + vectors("points", c.x) + "      </Points>\n";
  xml += "      <Cells>\n        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < n; ++i) xml += fmt::format("          {}\n", i);
  xml += "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < n; ++i) xml += fmt::format("          {}\n", i + 1);
  xml += "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < n; ++i) xml += "          1\n";  // VTK_VERTEX
  xml += "        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  return xml;
}

std::string pvd_document(const std::vector<std::pair<double, std::string>>& frames) {
  std::string xml = fmt::format(
      "<?xml version=\"1.0\"?>\n"
      "<!-- written by tsuchi {} -->\n"
      "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n",
      version);
  for (const auto& [t, file] : frames)
    xml += fmt::format("    <DataSet timestep=\"{:.12g}\" part=\"0\" file=\"{}\"/>\n", t, file);
  xml += "  </Collection>\n</VTKFile>\n";
  return xml;
}

template std::string vtu_document<2>(const Model<2>&, const std::vector<std::string>&);
template std::string vtu_document<3>(const Model<3>&, const std::vector<std::string>&);
template double vtu_size<2>(const Model<2>&, const std::vector<std::string>&);
template double vtu_size<3>(const Model<3>&, const std::vector<std::string>&);

}  // namespace tsuchi
