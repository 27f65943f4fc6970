#pragma once
// The particles' state columns of one constitutive model M, in M's order: what a StateRef reads
// (material/state_field.hpp). Taken once per material group, outside the particle loop.
#include "tsuchi/material/material.hpp"
#include "tsuchi/particles/particles.hpp"

#include <array>
#include <stdexcept>
#include <vector>

namespace tsuchi {

template <class M, int D>
std::array<double*, M::state_fields.size()> state_columns(Particles<D>& p) {
  // Particles built without declare_state_columns() (below) have no columns to point into.
  if (p.state.size() != material_state_fields().size())
    throw std::logic_error("particles without the material state columns (declare_state_columns)");
  std::array<double*, M::state_fields.size()> c{};
  const auto& index = state_columns_of<M>();
  for (std::size_t k = 0; k < c.size(); ++k) c[k] = p.state[static_cast<std::size_t>(index[k])].data();
  return c;
}

// For code that only reads the state: stiffness(), outside(). A StateRef is writable; those
// methods are const and must not write (a model that cached something there would make results
// depend on how often output is written).
template <class M, int D>
std::array<double*, M::state_fields.size()> state_columns(const Particles<D>& p) {
  return state_columns<M>(const_cast<Particles<D>&>(p));
}

// The registry's state columns for a new set of particles.
template <int D>
void declare_state_columns(Particles<D>& p) {
  std::vector<std::string> names;
  std::vector<double> initial;
  for (const StateField& f : material_state_fields()) names.emplace_back(f.name), initial.push_back(f.initial);
  p.set_state_columns(std::move(names), std::move(initial));
}

// The stiffness of particle i (material/material.hpp): outside the hot loops only.
template <int D>
LinearElastic stiffness_of(const Material& m, const Particles<D>& p, std::size_t i) {
  return std::visit(
      [&](const auto& model) -> LinearElastic {
        using M = std::decay_t<decltype(model)>;
        const auto cols = state_columns<M>(p);
        return model.stiffness(StateRef{cols.data(), i});
      },
      m.model);
}

}  // namespace tsuchi
