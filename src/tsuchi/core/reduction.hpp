#pragma once
// Whole-model reductions: every quantity that combines all particles or nodes into one number goes
// through these functions after its local loop - the stable time step (max), the recorders (sum,
// min, max), the global quantities (sums) and the fault checks (the first faulty particle). On one
// process they return their argument. Under MPI (comm/communicator.hpp) max, min, all and first are
// all-reduces, exact in any order; a sum of doubles is not: partial sums per process, added in
// rank order, are reproducible for one process count only. To give the bits of one process on
// any count, a distributed sum folds its terms in the single process's order
// (docs/issue42-design.md, sections 2 and 6.1).
#include <cstdint>

namespace tsuchi::reduce {

inline double sum(double local) { return local; }
inline double max(double local) { return local; }
inline double min(double local) { return local; }
inline bool all(bool local) { return local; }
// The lowest of the non-negative values (particle indices or ids), -1 when none is.
inline std::int64_t first(std::int64_t local) { return local; }

}  // namespace tsuchi::reduce
