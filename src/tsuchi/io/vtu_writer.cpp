#include "tsuchi/io/vtu_writer.hpp"

#include "tsuchi/core/principal.hpp"
#include "tsuchi/core/version.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace tsuchi {

namespace {

// Collects the XML header entries and the appended binary blocks side by side.
class VtuBuilder {
 public:
  template <class T>
  void array(std::string& xml, const char* vtk_type, const std::string& name, int components,
             const std::vector<T>& data) {
    xml += fmt::format(
        "        <DataArray type=\"{}\"{} NumberOfComponents=\"{}\" format=\"appended\" offset=\"{}\"/>\n",
        vtk_type, name.empty() ? std::string{} : fmt::format(" Name=\"{}\"", name), components,
        blob_.size());
    const std::uint64_t bytes = data.size() * sizeof(T);
    append(&bytes, sizeof bytes);
    append(data.data(), bytes);
  }

  const std::string& blob() const { return blob_; }

 private:
  void append(const void* p, std::size_t n) { blob_.append(static_cast<const char*>(p), n); }
  std::string blob_;
};

template <int D>
std::vector<double> vectors3(const std::vector<Vec<D>>& v) {
  std::vector<double> r(3 * v.size(), 0.0);
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int d = 0; d < D; ++d) r[3 * i + d] = v[i][d];
  return r;
}

// Symmetric tensors in ParaView's six-component order XX, YY, ZZ, XY, YZ, XZ (ours too).
template <int D>
std::vector<double> tensors6(const std::vector<Voigt<D>>& s) {
  std::vector<double> r(6 * s.size(), 0.0);
  for (std::size_t i = 0; i < s.size(); ++i)
    for (int k = 0; k < n_voigt<D>; ++k) r[6 * i + k] = s[i][k];
  return r;
}

}  // namespace

template <int D>
std::string vtu_document(const Model<D>& model, const std::vector<std::string>& fields) {
  const auto& p = model.particles;
  const std::size_t n = p.size();
  VtuBuilder b;
  std::string xml = fmt::format(
      "<?xml version=\"1.0\"?>\n"
      "<!-- written by tsuchi {} -->\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <UnstructuredGrid>\n"
      "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n"
      "      <PointData{}>\n",
      version, n, n,
      // The field ParaView colours by when a frame is opened: where the shear bands are.
      std::find(fields.begin(), fields.end(), "max_shear_strain") != fields.end() ? " Scalars=\"max_shear_strain\"" : "");
  for (const auto& f : fields) {
    if (f == "id") b.array(xml, "Int32", f, 1, p.id_p);
    else if (f == "displacement") b.array(xml, "Float64", f, 3, vectors3<D>(p.u_p));
    else if (f == "velocity") b.array(xml, "Float64", f, 3, vectors3<D>(p.v_p));
    else if (f == "stress") b.array(xml, "Float64", f, 6, tensors6<D>(p.sigma_p));
    else if (f == "strain") b.array(xml, "Float64", f, 6, tensors6<D>(p.eps_p));
    else if (f == "max_shear_strain") {
      std::vector<double> g(n);
      for (std::size_t i = 0; i < n; ++i) g[i] = max_shear_strain<D>(p.eps_p[i]);
      b.array(xml, "Float64", f, 1, g);
    } else if (f == "mean_stress") {
      // p = tr(sigma) / 3, tension positive (sigma_zz included in 2D), Pa.
      std::vector<double> mean(n);
      for (std::size_t i = 0; i < n; ++i) mean[i] = trace<D>(p.sigma_p[i]) / 3.0;
      b.array(xml, "Float64", f, 1, mean);
    } else if (f == "deviator_stress") {
      // q = sqrt(3 J2), the von Mises stress, Pa.
      std::vector<double> q(n);
      for (std::size_t i = 0; i < n; ++i) q[i] = von_mises<D>(p.sigma_p[i]);
      b.array(xml, "Float64", f, 1, q);
    } else if (f == "radius") {
      // Half the side of the particle's GIMP domain, the mean over the axes: the size ParaView's
      // Point Gaussian representation draws each particle with (docs/input.md).
      std::vector<double> r(n);
      for (std::size_t i = 0; i < n; ++i) r[i] = p.l_p[i].mean();
      b.array(xml, "Float64", f, 1, r);
    } else if (f == "volume") b.array(xml, "Float64", f, 1, p.V_p);
    else if (f == "mass") b.array(xml, "Float64", f, 1, p.m_p);
    else if (f == "density") {
      std::vector<double> rho(n);
      for (std::size_t i = 0; i < n; ++i) rho[i] = p.m_p[i] / p.V_p[i];
      b.array(xml, "Float64", f, 1, rho);
    } else if (f == "material") b.array(xml, "Int32", f, 1, p.material_p);
    else if (f == "body") b.array(xml, "Int32", f, 1, p.body_p);
    else if (f == "yield_mode") b.array(xml, "UInt8", f, 1, p.yield_p);
    else if (f == "plastic_shear_strain") b.array(xml, "Float64", f, 1, p.plastic_shear_p);
    else if (f == "plastic_volumetric_strain") b.array(xml, "Float64", f, 1, p.plastic_volume_p);
    else if (f == "cohesion_factor") b.array(xml, "Float64", f, 1, p.c_scale_p);
    else if (f == "friction_factor") b.array(xml, "Float64", f, 1, p.phi_scale_p);
  }
  xml += "      </PointData>\n      <Points>\n";
  b.array(xml, "Float64", "", 3, vectors3<D>(p.x_p));
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

}  // namespace tsuchi
