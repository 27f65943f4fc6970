#pragma once
// The particles' state columns of one constitutive model M, in M's order: what a StateRef reads
// (material/state_field.hpp). Taken once per material group, outside the particle loop.
#include "tsuchi/material/material.hpp"
#include "tsuchi/particles/particles.hpp"

#include <algorithm>
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
  for (std::size_t k = 0; k < c.size(); ++k) {
    const auto column = static_cast<std::size_t>(index[k]);
    // declare_state_columns(p, materials) holds the columns of the materials' models only.
    if (!p.state_held[column]) throw std::logic_error("particles without the state columns of model " + std::string(M::name));
    c[k] = p.state[column].data();
  }
  return c;
}

// For code that only reads the state: stiffness(), outside(). A StateRef is writable; those
// methods are const and must not write (a model that cached something there would make results
// depend on how often output is written).
template <class M, int D>
std::array<double*, M::state_fields.size()> state_columns(const Particles<D>& p) {
  return state_columns<M>(const_cast<Particles<D>&>(p));
}

// The registry's state columns for a new set of particles, holding only the columns of the fields
// some model of `materials` has (a model of Mohr-Coulomb soil and an elastic cap holds
// Mohr-Coulomb's five, not Cam-Clay's): a stage may give a body another of the run's materials,
// never a material the run does not declare.
template <int D>
void declare_state_columns(Particles<D>& p, const std::vector<Material>& materials) {
  std::vector<std::string> names;
  std::vector<double> initial;
  std::vector<char> held;
  for (const StateField& f : material_state_fields()) {
    names.emplace_back(f.name), initial.push_back(f.initial);
    held.push_back(std::any_of(materials.begin(), materials.end(), [&](const Material& m) { return has_state_field(m, f.name); }));
  }
  p.set_state_columns(std::move(names), std::move(initial), std::move(held));
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
