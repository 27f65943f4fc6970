#pragma once
// Whole-model reductions: every quantity that combines all particles or nodes into one number goes
// through these functions after its local loop - the stable time step (max), the recorders (sum,
// min, max), the global quantities (sums) and the fault checks (the first faulty particle). On one
// process they return their argument. A run distributed over processes implements them as an
// all-reduce of each process's partial result; the sums must then combine the partial results in
// a fixed order (by rank) to stay bitwise reproducible.
#include <cstdint>

namespace tsuchi::reduce {

inline double sum(double local) { return local; }
inline double max(double local) { return local; }
inline double min(double local) { return local; }
inline bool all(bool local) { return local; }
// The lowest of the non-negative values (particle indices or ids), -1 when none is.
inline std::int64_t first(std::int64_t local) { return local; }

}  // namespace tsuchi::reduce
