#include "tsuchi/material/material.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace tsuchi {

namespace {

template <class... M>
std::vector<StateField> union_of_fields(std::variant<M...>*) {
  std::vector<StateField> all;
  // Models may share a field (a yield mode, a plastic strain) only if they mean the same by it.
  const auto add = [&](const auto& fields) {
    for (const StateField& f : fields) {
      const auto same = std::find_if(all.begin(), all.end(), [&](const StateField& g) { return g.name == f.name; });
      if (same == all.end()) all.push_back(f);
      else if (same->initial != f.initial || same->flag != f.flag || same->unit != f.unit || same->indicator != f.indicator)
        throw std::logic_error("two constitutive models declare state field '" + std::string(f.name) +
                               "' with different initial values, units or kinds");
    }
  };
  (add(M::state_fields), ...);
  return all;
}

}  // namespace

const std::vector<StateField>& material_state_fields() {
  static const std::vector<StateField> fields = union_of_fields(static_cast<ConstitutiveModel*>(nullptr));
  return fields;
}

int state_column(std::string_view name) {
  const auto& f = material_state_fields();
  for (std::size_t k = 0; k < f.size(); ++k)
    if (f[k].name == name) return static_cast<int>(k);
  return -1;
}

namespace {

template <class... M>
std::vector<std::string_view> models_with(std::string_view name, std::variant<M...>*) {
  std::vector<std::string_view> names;
  const auto add = [&](std::string_view model, const auto& fields) {
    if (std::any_of(fields.begin(), fields.end(), [&](const StateField& f) { return f.name == name; }))
      names.push_back(model);
  };
  (add(M::name, M::state_fields), ...);
  return names;
}

}  // namespace

std::vector<std::string_view> models_with_state_field(std::string_view name) {
  return models_with(name, static_cast<ConstitutiveModel*>(nullptr));
}

bool has_state_field(const Material& m, std::string_view name) {
  return std::visit(
      [&](const auto& model) {
        const auto& fields = std::decay_t<decltype(model)>::state_fields;
        return std::any_of(fields.begin(), fields.end(), [&](const StateField& f) { return f.name == name; });
      },
      m.model);
}

}  // namespace tsuchi
