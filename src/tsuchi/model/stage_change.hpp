#pragma once
// How a staged run changes its model at the start of a stage (docs/stages.md). The particles keep
// their state from one stage to the next; what a stage changes is applied in place:
//   - bodies removed (excavation) lose their particles, and surface loads their share on them;
//     a region of `remove` takes the particles whose centre its shape holds at the stage's start
//     (a cut in layers, a tunnel's advance); they take their stress with them, so the new face is
//     free and the load it carried is released;
//   - bodies added (fill, construction) get theirs from Model::dormant, made with the rest at the
//     start with their initial stress, and join the step; a region of `add` wakes the waiting
//     particles of its body that its shape holds (a fill in lifts);
//   - displacements and strains reset to zero (PLAXIS's habit), so that later outputs show what
//     the later stages caused;
//   - the materials, the step settings, gravity, the boundary, the loads and the bodies' prescribed
//     motions are rebuilt from the stage's input where the stage changes them. A function of time
//     that a stage sets runs on the stage's clock: f(t - t_start).
#include "tsuchi/model/model.hpp"

#include <cstdint>
#include <vector>

namespace tsuchi {

// Moves the particles of `bodies` from `from` to the end of `to` (its state columns declared like
// `from`'s when it has none), keeping the order of both.
template <int D>
void move_bodies(Particles<D>& from, Particles<D>& to, const std::vector<std::int32_t>& bodies);

// The particle changes at the start of stage k of `run`: removals, additions, reset.
template <int D>
void change_particles(Model<D>& m, const Config& run, std::size_t k);

// The rest of stage k's input that the stage changes, applied to the model at time t0.
template <int D>
void reconfigure(Model<D>& m, const Config& run, std::size_t k, double t0);

// Both, as at the start of stage k at time t0: the one way a stage begins, in a run, on a restart's
// replay and in check_stages.
template <int D>
void begin_stage(Model<D>& m, const Config& run, std::size_t k, double t0) {
  change_particles(m, run, k);
  reconfigure(m, run, k, t0);
}

// For a restart in stage k: a model built for the first stage (build_model) brought to stage k,
// with starts[j] the start time of stage j; the checkpoint then replaces its particles and loads.
template <int D>
void restore_stage(Model<D>& m, const Config& run, std::size_t k, const std::vector<double>& starts);

// Every later stage applied in turn to a copy of the model as built: the errors a stage would
// meet at its start (a load box that selects no particle, a node set with no node, a recorder's
// node set gone) found before the run, naming the stage. The particles are those of the start.
template <int D>
void check_stages(const Model<D>& m, const Config& run);

// Whether contact acts in some stage of `run` (the model's own, or a later stage's pairs and
// frictional faces): global.csv then has its contact_nodes column from the start.
template <int D>
bool contact_in_some_stage(const Model<D>& m, const Config& run);

extern template void check_stages<2>(const Model<2>&, const Config&);
extern template bool contact_in_some_stage<2>(const Model<2>&, const Config&);
extern template bool contact_in_some_stage<3>(const Model<3>&, const Config&);
extern template void check_stages<3>(const Model<3>&, const Config&);
extern template void move_bodies<2>(Particles<2>&, Particles<2>&, const std::vector<std::int32_t>&);
extern template void move_bodies<3>(Particles<3>&, Particles<3>&, const std::vector<std::int32_t>&);
extern template void change_particles<2>(Model<2>&, const Config&, std::size_t);
extern template void change_particles<3>(Model<3>&, const Config&, std::size_t);
extern template void reconfigure<2>(Model<2>&, const Config&, std::size_t, double);
extern template void reconfigure<3>(Model<3>&, const Config&, std::size_t, double);
extern template void restore_stage<2>(Model<2>&, const Config&, std::size_t, const std::vector<double>&);
extern template void restore_stage<3>(Model<3>&, const Config&, std::size_t, const std::vector<double>&);

}  // namespace tsuchi
