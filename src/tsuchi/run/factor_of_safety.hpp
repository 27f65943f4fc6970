#pragma once
// The factor of safety by strength reduction (`tsuchi fos FILE`; Dawson, Roth and Drescher 1999;
// Griffiths and Lane 1999). The input's analysis runs first (its stages up to [fos].stage), which
// leaves the ground in equilibrium. Each trial then starts from that state with the strength of
// every material that has the hook (Mohr-Coulomb family, material/strength_reduction.hpp) divided
// by a factor F, and steps under the same settings until one of
//   equilibrium:  the unbalanced-force ratio falls below fos.unbalanced_force_ratio  -> stands;
//   collapse:     a particle has moved more than fos.displacement_limit since the trial began -> fails;
//   step limit:   fos.max_steps -> fails, unless the largest displacement grew by less than 1 % of
//                 the displacement limit over the last fifth of the steps (at rest, on a plastic
//                 zone's floor of the ratio) -> stands.
// F is bracketed (the upper end doubled until a trial fails) and the bracket narrowed by rounds of
// fos.trials_at_once trials spread evenly inside it (bisection for 1) until its width is below
// fos.tolerance of its lower end. A round's trials run side by side on the threads there are; what
// is tried never depends on the thread count, so the result is the same on any machine.
#include "tsuchi/model/config.hpp"
#include "tsuchi/model/model.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace tsuchi {

struct FosTrial {
  int index = 0;            // in the order tried
  double factor = 0.0;
  bool failed = false;
  std::string reason;       // "equilibrium", "displacement", "max_steps", "at rest at max_steps"
  std::int64_t steps = 0;
  double unbalanced_force_ratio = 0.0;
  double max_displacement = 0.0;  // m, since the trial began
  double late_growth = 0.0;       // m, the growth of max_displacement over the last fifth of max_steps
  double wall_seconds = 0.0;
};

struct FosResult {
  double lower = 0.0, upper = 0.0;  // the last trial that stood and the first that failed
  double factor = 0.0;              // their mean
  // Not empty when the search's verdicts were set by the step budget rather than by the ground:
  // the factor is then only a bound (at least `lower`), and this says why and what to change.
  std::string bound;
  std::vector<FosTrial> trials;
  std::string directory;            // where trials.csv and the frames went
};

struct FosOptions {
  std::string output_directory;     // the run's; the search writes into its fos/ subdirectory
  bool quiet = false;
  std::function<void(const FosTrial&)> on_trial;
  std::function<void(const std::string&)> on_note;  // the analysis' stages, as they end
};

// `model` is build_model(config), which the analysis runs on. Throws InputError for an input
// without [fos] or without a material whose strength is reduced.
template <int D>
FosResult factor_of_safety(const Config& config, Model<D> model, const FosOptions& options);

extern template FosResult factor_of_safety<2>(const Config&, Model<2>, const FosOptions&);
extern template FosResult factor_of_safety<3>(const Config&, Model<3>, const FosOptions&);

}  // namespace tsuchi
