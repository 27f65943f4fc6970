#include "tsuchi/element/element_csv.hpp"

#include <fmt/format.h>

namespace tsuchi::element {

const std::vector<std::string>& csv_columns() {
  // The plastic columns and yield_mode carry the names (and signs) of the run's particle fields.
  static const std::vector<std::string> columns{
      "increment", "segment", "eps_xx", "eps_yy", "eps_zz",    "eps_xy",     "eps_yz",
      "eps_xz",    "sig_xx",  "sig_yy", "sig_zz", "sig_xy",    "sig_yz",     "sig_xz",
      "p",         "q",       "deviator", "eps_v", "gamma_max", "yield_mode", "plastic_shear_strain",
      "plastic_volumetric_strain"};
  return columns;
}

std::string format_csv(const std::vector<ElementRow>& rows, const std::vector<std::string>& notes) {
  std::string out;
  out.reserve(320 * (rows.size() + 12));
  for (const auto& n : notes) out += fmt::format("# {}\n", n);
  out +=
      "# eps_*, sig_*: tension positive, sig_* in Pa; eps_xy, eps_yz, eps_xz are tensor components (engineering "
      "gamma = 2 eps)\n"
      "# p = -(sig_xx + sig_yy + sig_zz)/3 (Pa) and eps_v = -(eps_xx + eps_yy + eps_zz): compression positive "
      "(p = -mean_stress of a run's frames and recorders, which are tension positive)\n"
      "# q = sqrt(3 J2) (Pa); deviator = largest - smallest principal stress (Pa); gamma_max = largest - smallest "
      "principal strain\n"
      "# yield_mode of the increment: 0 elastic, 1 shear, 2 tension; plastic_shear_strain = accumulated eps1_p - "
      "eps3_p; plastic_volumetric_strain = accumulated, dilation positive\n";
  const auto& cols = csv_columns();
  for (std::size_t i = 0; i < cols.size(); ++i) out += (i ? "," : "") + cols[i];
  out += '\n';
  for (const auto& r : rows) {
    out += fmt::format("{},{}", r.increment, r.segment);
    for (int k = 0; k < 6; ++k) out += fmt::format(",{:.12g}", r.strain[k]);
    for (int k = 0; k < 6; ++k) out += fmt::format(",{:.12g}", r.stress[k]);
    out += fmt::format(",{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{},{:.12g},{:.12g}\n", r.p(), r.q(), r.deviator(),
                       r.eps_v(), r.gamma_max(), static_cast<int>(r.mode), r.plastic_shear_strain,
                       r.plastic_volumetric_strain);
  }
  return out;
}

}  // namespace tsuchi::element
