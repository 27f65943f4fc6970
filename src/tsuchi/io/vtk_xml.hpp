#pragma once
// The pieces every binary VTK XML frame of a run is made of (particle frames, io/vtu_writer.hpp;
// grid frames, io/grid_vtu_writer.hpp): appended raw arrays with UInt64 block headers, FieldData
// string arrays, and the units and conventions that travel with the data.
#include <cstdint>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace tsuchi {

// Collects the XML header entries and the appended binary blocks side by side.
class VtkAppendedArrays {
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

// A FieldData string array: VTK's XML readers take a String array in ascii format as the
// character codes of each string followed by a 0 (as vtkXMLWriter writes them), and ParaView lists
// it under Field Data (the Information panel, and the spreadsheet view's Field Data).
std::string vtk_string_array(const std::string& name, const std::vector<std::string>& strings);

// A field's unit in a model of dimension `dim`: the registry writes "m^3 (m^2 in 2D)" for both.
std::string unit_in(const std::string& unit, int dim);

// The conventions every frame states once (issue 41: a confining stress of -10000 was read as a
// mistake): SI units, the sign of stress and strain, the tensor order, the dimension.
std::vector<std::string> frame_conventions(int dim);

}  // namespace tsuchi
