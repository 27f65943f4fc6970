#pragma once
// Whole-file writes that never leave a half-written file under the final name: the contents go to
// a temporary file in the same directory, which is flushed and then renamed over the target
// (rename within one file system is atomic on POSIX).
#include <string>
#include <string_view>

namespace tsuchi {

// Throws OutputError naming the path and the system's reason on any failure.
void write_file_atomically(const std::string& path, std::string_view contents);

// Creates the directory (and parents) if needed; throws OutputError if it cannot be written to.
void prepare_output_directory(const std::string& dir);

// Creates the directory a checkpoint file goes into (when missing) and checks that it can be
// written to; throws OutputError.
void prepare_checkpoint_directory(const std::string& checkpoint_file);

}  // namespace tsuchi
