#pragma once
// Material points as a structure of flat arrays, one array per field.
#include "tsuchi/core/tensor.hpp"

#include <algorithm>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace tsuchi {

template <int D>
struct Particles {
  std::vector<Vec<D>> x_p;        // position (m)
  std::vector<Vec<D>> u_p;        // displacement from the initial position (m)
  std::vector<Vec<D>> v_p;        // velocity (m/s)
  std::vector<Vec<D>> l_p;        // GIMP half-widths per axis (m)
  std::vector<double> m_p;        // mass (kg; per metre of thickness in 2D)
  std::vector<double> V_p;        // volume (m^3; m^2 in 2D)
  std::vector<Voigt<D>> sigma_p;  // Cauchy stress, tension positive (Pa)
  // The initial stress subtracted in the internal force, eq (2): held only when `initial_stress`
  // is set (a body asks for the subtraction); other models do not pay its Voigt entries per particle.
  std::vector<Voigt<D>> sigma0_p;
  bool initial_stress = false;
  std::vector<Voigt<D>> eps_p;    // accumulated small strain, eq (10b)
  // APIC's affine velocity matrix (1/s): the particle carries the velocity field v_p + C_p (x - x_p)
  // (Jiang et al. 2015). Held only when `affine` is set (the APIC transfer): FLIP models do not pay
  // its D*D doubles per particle, nor carry it through resizing, reordering and checkpoints.
  std::vector<Mat<D>> C_p;
  bool affine = false;
  // Material state: one column per state field of the registered constitutive models, named and
  // given its initial value by set_state_columns() (the model builder passes the registry,
  // material_state_fields()). A material updates only the columns of its own fields. Only the
  // columns some material of the model has are held (state_held); the others stay empty, and read
  // as their initial value (state_value), so outputs list every field whatever the model.
  std::vector<std::vector<double>> state;
  std::vector<std::string> state_name;
  std::vector<double> state_initial;
  std::vector<char> state_held;
  std::vector<std::int32_t> material_p;
  std::vector<std::int32_t> body_p;
  std::vector<std::int64_t> id_p;  // stable identity, survives reordering (64-bit: models beyond 2^31 particles)

  std::size_t size() const { return x_p.size(); }

  // Declares the state columns, before any particle is added; `held` (one entry per name) says
  // which are stored.
  void set_state_columns(std::vector<std::string> names, std::vector<double> initial, std::vector<char> held) {
    state_name = std::move(names);
    state_initial = std::move(initial);
    state_held = std::move(held);
    state.clear();
    for (std::size_t k = 0; k < state_initial.size(); ++k)
      state.emplace_back(state_held[k] ? size() : 0, state_initial[k]);
  }
  // The same columns and optional arrays as `o`, for particles that will take some of o's.
  void same_arrays_as(const Particles& o) {
    set_state_columns(o.state_name, o.state_initial, o.state_held);
    affine = o.affine;
    initial_stress = o.initial_stress;
  }
  // The column of the state field `name`, or nullptr (no such field, or not held).
  std::vector<double>* state_column(const std::string& name) {
    for (std::size_t k = 0; k < state_name.size(); ++k)
      if (state_name[k] == name) return state_held[k] ? &state[k] : nullptr;
    return nullptr;
  }
  // State field k of particle i; a field no material of the model has keeps its initial value.
  double state_value(std::size_t k, std::size_t i) const { return state_held[k] ? state[k][i] : state_initial[k]; }
  std::size_t state_columns_held() const {
    return static_cast<std::size_t>(std::count(state_held.begin(), state_held.end(), char{1}));
  }
  // sigma - sigma0 of eq (2), the stress the internal force acts with: sigma itself when no body
  // subtracts an initial stress (sigma - 0 would give the same bits).
  Voigt<D> stress_above_initial(std::size_t i) const {
    return initial_stress ? Voigt<D>(sigma_p[i] - sigma0_p[i]) : sigma_p[i];
  }
  const std::vector<double>* state_column(const std::string& name) const {
    return const_cast<Particles*>(this)->state_column(name);
  }

  // Calls f(name, array) for every per-particle array: the one list that resizing, reordering and
  // checkpoints go through, so a new field cannot be forgotten by one of them.
  template <class F>
  void for_each_array(F&& f) {
    f("x", x_p), f("u", u_p), f("v", v_p), f("l", l_p), f("m", m_p), f("V", V_p), f("sigma", sigma_p);
    if (initial_stress) f("sigma0", sigma0_p);
    f("eps", eps_p);
    if (affine) f("C", C_p);
    for (std::size_t k = 0; k < state.size(); ++k)
      if (state_held[k]) f(state_name[k].c_str(), state[k]);
    f("material", material_p), f("body", body_p), f("id", id_p);
  }
  template <class F>
  void for_each_array(F&& f) const {
    const_cast<Particles*>(this)->for_each_array([&](const char* name, const auto& a) { f(name, a); });
  }

  // New particles are zero, except their state, which takes each field's initial value.
  void resize(std::size_t n) {
    for (std::size_t k = 0; k < state.size(); ++k)  // first: then at size n
      if (state_held[k]) state[k].resize(n, state_initial[k]);
    for_each_array([n](const char*, auto& a) {
      using T = typename std::decay_t<decltype(a)>::value_type;
      a.resize(n, zero_of<T>());
    });
  }

  // Reorders every array: particle k of the result is particle order[k] of this one. Ids move
  // with their particles, so outputs keyed by id are unchanged. In place, cycle by cycle: the only
  // storage it takes is one byte per particle (`moved`, kept between calls, so a periodic
  // reordering allocates only the first time), not a copy of the largest array (72 bytes per
  // particle in 3D), which set the peak memory of a large run. The periodic sort moves few
  // particles (most stay in their block between sorts), and a fixed point costs one comparison.
  using Scratch = std::vector<std::uint8_t>;

  template <class Index>
  void permute(const std::vector<Index>& order, Scratch& moved) {
    const std::size_t n = order.size();
    for_each_array([&](const char*, auto& a) {
      moved.assign(n, 0);
      for (std::size_t s = 0; s < n; ++s) {
        if (moved[s] || static_cast<std::size_t>(order[s]) == s) continue;
        // The cycle s <- order[s] <- order[order[s]] ... <- s: each slot takes its source's
        // element, the last one the element first held at s.
        auto first = std::move(a[s]);
        std::size_t k = s;
        for (;;) {
          moved[k] = 1;
          const auto from = static_cast<std::size_t>(order[k]);
          if (from == s) break;
          a[k] = std::move(a[from]);
          k = from;
        }
        a[k] = std::move(first);
      }
    });
  }
  template <class Index>
  void permute(const std::vector<Index>& order) {
    Scratch moved;
    permute(order, moved);
  }

  static constexpr std::size_t bytes_per_particle(std::size_t state_columns, bool with_affine, bool with_initial_stress) {
    return 4 * sizeof(Vec<D>) + (with_affine ? sizeof(Mat<D>) : 0) + (2 + state_columns) * sizeof(double) +
           (with_initial_stress ? 3 : 2) * sizeof(Voigt<D>) + 2 * sizeof(std::int32_t) + sizeof(std::int64_t);
  }
  std::size_t bytes_per_particle() const { return bytes_per_particle(state_columns_held(), affine, initial_stress); }
};

}  // namespace tsuchi
