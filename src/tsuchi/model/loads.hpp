#pragma once
// The loads of the input's [[loads]] as the solver applies them (solver/load_stage.hpp): forces at
// the value 1 of their function of time, fixed when the model is built.
//
// Surface loads act on a body's boundary particles, the standard MPM traction: the external nodal
// force f_i += sum_p S_ip(x_p) F_p over the loaded particles, F_p = t_p A_p (Sulsky, Zhou and
// Schreyer 1995, eq 24; Bardenhagen and Kober 2004 for GIMP). A particle of a lattice-filled body is
// on the boundary in direction +-e_d when the lattice site next to it, x +- s_d e_d, holds no
// particle of the same body; its exposed faces give the area vector a_p = sum n_face A_face, with
// A_face the product of the particle's other edge lengths (times 1 m of thickness in 2D).
//   pressure p:  F_p = -p a_p            traction t:  F_p = t |a_p|
// A dead load keeps the areas and directions of the initial lattice; a follower pressure
// (`follow = true`) turns and stretches each a_p with its particle's deformation by Nanson's
// relation, step by step (solver/follower_area.hpp, eq N1; docs/input.md).
#include "tsuchi/core/time_function.hpp"
#include "tsuchi/core/tensor.hpp"
#include "tsuchi/grid/grid.hpp"
#include "tsuchi/model/config.hpp"
#include "tsuchi/particles/particles.hpp"

#include <cstdint>
#include <vector>

namespace tsuchi {

// A traction or pressure: a force on each loaded particle.
template <int D>
struct ParticleLoad {
  TimeFunction function;
  std::vector<std::int64_t> id;  // the loaded particles by Particles::id_p, increasing
  std::vector<Vec<D>> force;     // force on each at f = 1 (N; N/m in 2D): -p a_p, or t |a_p|
  // A follower pressure: `force` is -p a_p of the current a_p, carried through every step by eq N1
  // (LoadStage::follow); it is then state, and checkpoints hold it.
  bool follow = false;
};

// Forces on grid nodes (a point or line load shared over a node set).
template <int D>
struct NodalLoad {
  TimeFunction function;
  std::vector<std::int64_t> node;  // grid node indices
  std::vector<Vec<D>> force;       // force on each at f = 1 (N; N/m in 2D)
};

// A force per unit volume on the particles of some bodies, as an acceleration per body: b / rho of
// the body's material, so that m_p (b / rho) = V_p0 b (per unit of initial volume, like gravity).
template <int D>
struct BodyForceLoad {
  TimeFunction function;
  std::vector<Vec<D>> acceleration;  // per body (m/s^2), zero for a body it does not load
};

template <int D>
struct Loads {
  std::vector<ParticleLoad<D>> surface;
  std::vector<NodalLoad<D>> nodal;
  std::vector<BodyForceLoad<D>> body;
  bool empty() const { return surface.empty() && nodal.empty() && body.empty(); }
  bool any_follower() const {
    for (const auto& l : surface)
      if (l.follow) return true;
    return false;
  }
};

// The exposed faces of every particle of body `body` (0 for other bodies' particles), from the
// lattice of the initial particles (spacing s = 2 l_p, sites x = origin + (j + 1/2) s): bit 2d is
// set when the face towards -e_d is exposed, bit 2d + 1 the face towards +e_d.
template <int D>
std::vector<std::uint8_t> exposed_faces(const Particles<D>& p, const Grid<D>& g, int body);

// a_p = sum over the faces of `faces` of n_face A_face (m^2; m per metre of thickness in 2D) for a
// particle of edge lengths 2 l.
template <int D>
Vec<D> area_vector(std::uint8_t faces, const Vec<D>& l);

// Builds the loads of c.loads for the particles and grid as built (before the first step); throws
// InputError when a selection holds no boundary particle or no grid node.
template <int D>
Loads<D> build_loads(const Config& c, const Particles<D>& p, const Grid<D>& g);

extern template std::vector<std::uint8_t> exposed_faces<2>(const Particles<2>&, const Grid<2>&, int);
extern template std::vector<std::uint8_t> exposed_faces<3>(const Particles<3>&, const Grid<3>&, int);
extern template Vec<2> area_vector<2>(std::uint8_t, const Vec<2>&);
extern template Vec<3> area_vector<3>(std::uint8_t, const Vec<3>&);
extern template Loads<2> build_loads<2>(const Config&, const Particles<2>&, const Grid<2>&);
extern template Loads<3> build_loads<3>(const Config&, const Particles<3>&, const Grid<3>&);

}  // namespace tsuchi
