#pragma once
// Error kinds a run can end with; each maps to its own exit code of the `tsuchi` program, so a
// script driving a study can tell a typo from a blown-up run from a full disk.
#include <stdexcept>
#include <string>

namespace tsuchi {

// The input file (or a command-line override, or a checkpoint) is wrong: names file, line and key.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// What went wrong in the simulation itself.
enum class Fault {
  Other,           // e.g. a stress-controlled element test past its peak
  NonFinite,       // NaN or Inf in a particle's stress, velocity, volume or mass
  LeftGrid,        // a particle crossed the edge of the background grid
  VolumeCollapse,  // a particle's volume went to zero or below in one step
  UnstableStep,    // a fixed time step above the stable (Courant 1) limit
};

// The simulation cannot go on. `fault` picks the exit code; the message says where and what to try.
struct RunError : std::runtime_error {
  RunError(const std::string& message, Fault kind = Fault::Other) : std::runtime_error(message), fault(kind) {}
  Fault fault;
  double suggested_dt = 0.0;  // a fixed time.dt above the stable limit: the one the message suggests
};

// Writing results failed (disk full, directory not writable, ...).
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// SIGINT or SIGTERM arrived; the run saved its state and stopped.
struct Interrupted : std::runtime_error {
  Interrupted(const std::string& message, int signal_number) : std::runtime_error(message), signal(signal_number) {}
  int signal;
};

namespace exit_code {
inline constexpr int ok = 0;
inline constexpr int usage = 1;
inline constexpr int input = 2;
inline constexpr int run = 3;        // a run fault not listed below
inline constexpr int output = 4;
inline constexpr int internal = 5;   // anything else (out of memory, a bug)
inline constexpr int non_finite = 6;
inline constexpr int left_grid = 7;
inline constexpr int volume_collapse = 8;
inline constexpr int unstable_step = 9;
// Interrupted by signal s: 128 + s, the shell's convention (130 for SIGINT, 143 for SIGTERM).

inline int of(Fault f) {
  switch (f) {
    case Fault::NonFinite: return non_finite;
    case Fault::LeftGrid: return left_grid;
    case Fault::VolumeCollapse: return volume_collapse;
    case Fault::UnstableStep: return unstable_step;
    case Fault::Other: break;
  }
  return run;
}
}  // namespace exit_code

}  // namespace tsuchi
