#pragma once
// Error kinds a run can end with; each maps to its own exit code of the `tsuchi` program.
#include <stdexcept>
#include <string>

namespace tsuchi {

// The input file (or a command-line override) is wrong: names file, line and key.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The simulation itself cannot go on (a particle left the grid, a non-finite state, ...).
struct RunError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Writing results failed (disk full, directory not writable, ...).
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

namespace exit_code {
inline constexpr int ok = 0;
inline constexpr int usage = 1;
inline constexpr int input = 2;
inline constexpr int run = 3;
inline constexpr int output = 4;
inline constexpr int internal = 5;  // anything else (out of memory, a bug)
}  // namespace exit_code

}  // namespace tsuchi
