#include "tsuchi/io/vtk_xml.hpp"

namespace tsuchi {

std::string vtk_string_array(const std::string& name, const std::vector<std::string>& strings) {
  std::string codes;
  for (const auto& text : strings) {
    for (const char ch : text) codes += fmt::format("{} ", static_cast<unsigned>(static_cast<unsigned char>(ch)));
    codes += "0 ";
  }
  if (!codes.empty()) codes.pop_back();
  return fmt::format(
      "      <DataArray type=\"String\" Name=\"{}\" NumberOfTuples=\"{}\" format=\"ascii\">\n"
      "        {}\n"
      "      </DataArray>\n",
      name, strings.size(), codes);
}

std::string unit_in(const std::string& unit, int dim) {
  const std::size_t open = unit.find(" (");
  if (open == std::string::npos) return unit.empty() ? "-" : unit;
  if (dim == 2 && unit.size() > open + 11 && unit.compare(unit.size() - 7, 7, " in 2D)") == 0)
    return unit.substr(open + 2, unit.size() - 7 - open - 2);
  return unit.substr(0, open);
}

std::vector<std::string> frame_conventions(int dim) {
  return {"SI units: m, s, kg, Pa (the units array gives each field's)",
          "stress and strain: tension and extension positive, so compression is negative (a confining "
          "pressure of 10 kPa is a stress of -10000 Pa)",
          "tensors: 6 components in the order XX, YY, ZZ, XY, YZ, XZ (zero YZ, XZ in 2D)",
          dim == 2 ? "2D: plane strain in x, y; z = 0; volume in m^2 and mass in kg per metre of thickness"
                   : "3D: x, y, z; gravity as the input gives it"};
}

}  // namespace tsuchi
