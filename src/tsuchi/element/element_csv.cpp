#include "tsuchi/element/element_csv.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string_view>
#include <variant>

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

namespace {

// The state fields with columns of their own: those of the model beyond the fixed columns, and
// beyond the imperfection's strength factors (always 1 for a single point).
bool own_column(std::string_view name) {
  for (std::string_view fixed : {field_name::yield_mode, field_name::plastic_shear_strain,
                                 field_name::plastic_volumetric_strain, field_name::cohesion_factor,
                                 field_name::friction_factor})
    if (name == fixed) return false;
  return true;
}

}  // namespace

std::vector<std::string> csv_columns(const Material& material) {
  std::vector<std::string> columns = csv_columns();
  std::visit(
      [&](const auto& model) {
        for (const StateField& f : std::decay_t<decltype(model)>::state_fields)
          if (own_column(f.name)) columns.emplace_back(f.name);
      },
      material.model);
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
  if (!rows.empty() && std::any_of(rows.front().state.begin(), rows.front().state.end(),
                                   [](const auto& f) { return own_column(f.first); }))
    out += "# the columns after plastic_volumetric_strain are the material model's state fields (docs/materials.md)\n";
  const auto& cols = csv_columns();
  for (std::size_t i = 0; i < cols.size(); ++i) out += (i ? "," : "") + cols[i];
  if (!rows.empty())
    for (const auto& [name, value] : rows.front().state)
      if (own_column(name)) out += fmt::format(",{}", name);
  out += '\n';
  for (const auto& r : rows) {
    out += fmt::format("{},{}", r.increment, r.segment);
    for (int k = 0; k < 6; ++k) out += fmt::format(",{:.12g}", r.strain[k]);
    for (int k = 0; k < 6; ++k) out += fmt::format(",{:.12g}", r.stress[k]);
    out += fmt::format(",{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{},{:.12g},{:.12g}\n", r.p(), r.q(), r.deviator(),
                       r.eps_v(), r.gamma_max(), static_cast<int>(r.mode), r.plastic_shear_strain,
                       r.plastic_volumetric_strain);
    out.pop_back();  // the row goes on with the model's own state columns
    for (const auto& [name, value] : r.state)
      if (own_column(name)) out += fmt::format(",{:.12g}", value);
    out += '\n';
  }
  return out;
}

}  // namespace tsuchi::element
