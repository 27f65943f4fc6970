#pragma once
// Whole-file writes that never leave a half-written file under the final name: the contents go to
// a temporary file in the same directory, which is flushed and then renamed over the target
// (rename within one file system is atomic on POSIX).
#include <string>
#include <string_view>

namespace tsuchi {

// Throws OutputError naming the path and the system's reason on any failure, and when `path`
// exists and is not a regular file (a device such as /dev/null, a pipe, a directory), which the
// rename would replace.
void write_file_atomically(const std::string& path, std::string_view contents);

// "a character device", "a named pipe", ... when `path` exists and is not a regular file; empty
// when it is one or does not exist.
std::string non_regular_file_kind(const std::string& path);

// Throws OutputError when `path` exists and is not a regular file: what write_file_atomically
// refuses, to be checked before a run rather than at its first write. `what` names the file in
// the message ("the output file"; may be empty).
void refuse_unless_regular_file(const std::string& path, const std::string& what);

// Creates the directory (and parents) if needed; throws OutputError if it cannot be written to.
void prepare_output_directory(const std::string& dir);

// Creates the directory a checkpoint file goes into (when missing) and checks that it can be
// written to; throws OutputError.
void prepare_checkpoint_directory(const std::string& checkpoint_file);

}  // namespace tsuchi
