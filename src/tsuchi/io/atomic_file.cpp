#include "tsuchi/io/atomic_file.hpp"

#include "tsuchi/core/errors.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sys/stat.h>
#include <unistd.h>

namespace tsuchi {

namespace {

namespace fs = std::filesystem;

// ".NAME.tmp.PID" beside the target: hidden from ParaView's file dialog and globbing, and the PID
// tells a later run whether the writer is still alive.
std::string temporary_name(const std::string& path) {
  const fs::path p(path);
  return (p.parent_path() / fmt::format(".{}.tmp.{}", p.filename().string(), static_cast<long>(::getpid()))).string();
}

}  // namespace

std::string non_regular_file_kind(const std::string& path) {
  struct ::stat st {};
  if (::stat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode)) return {};  // a new name, or a file
  return S_ISDIR(st.st_mode)    ? "a directory"
         : S_ISCHR(st.st_mode)  ? "a character device"
         : S_ISBLK(st.st_mode)  ? "a block device"
         : S_ISFIFO(st.st_mode) ? "a named pipe"
         : S_ISSOCK(st.st_mode) ? "a socket"
                                : "not a regular file";
}

void refuse_unless_regular_file(const std::string& path, const std::string& what) {
  const std::string kind = non_regular_file_kind(path);
  if (kind.empty()) return;
  throw OutputError(fmt::format("cannot write {}{}: it is {}, and tsuchi writes a new file and renames it over the "
                                "old one, which would replace it; give the name of a regular file or a new one",
                                what.empty() ? "" : what + " ", path, kind));
}

void write_file_atomically(const std::string& path, std::string_view contents) {
  refuse_unless_regular_file(path, "");
  const std::string tmp = temporary_name(path);
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw OutputError(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
  const bool written = std::fwrite(contents.data(), 1, contents.size(), f) == contents.size();
  int err = written ? 0 : errno;
  const bool flushed = std::fflush(f) == 0;
  if (!err && !flushed) err = errno;
  // On disk before the rename, so that a crash of the machine cannot leave a renamed empty file.
  const bool synced = ::fsync(::fileno(f)) == 0;
  if (!err && !synced) err = errno;
  const bool closed = std::fclose(f) == 0;
  if (!err && !closed) err = errno;
  if (!written || !flushed || !synced || !closed) {
    std::remove(tmp.c_str());
    throw OutputError(fmt::format("cannot write {} ({} bytes): {}; free space or choose another output.directory",
                                  path, contents.size(), std::strerror(err)));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int e = errno;
    std::remove(tmp.c_str());
    throw OutputError(fmt::format("cannot rename {} to {}: {}", tmp, path, std::strerror(e)));
  }
}

namespace {

// Creates `dir` with its parents if need be, and checks that it is writable; `what` names it in
// the message ("the output directory out/").
void create_writable_directory(const fs::path& dir, const std::string& what) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw OutputError(fmt::format("cannot create {}: {}", what, ec.message()));
  if (::access(dir.c_str(), W_OK) != 0)
    throw OutputError(fmt::format("{} is not writable: {}", what, std::strerror(errno)));
}

}  // namespace

void prepare_output_directory(const std::string& dir) {
  std::error_code ec;
  if (fs::is_symlink(fs::symlink_status(dir, ec)) && !fs::exists(dir, ec))
    throw OutputError(fmt::format("cannot create the output directory {}: it is a symbolic link to {}, which does not "
                                  "exist; create that directory or remove the link",
                                  dir, fs::read_symlink(dir, ec).string()));
  create_writable_directory(dir, fmt::format("the output directory {}", dir));
  // Temporary files of a run that was killed mid-write; those of a live process are left alone.
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    const auto at = name.rfind(".tmp.");
    if (name.empty() || name[0] != '.' || at == std::string::npos) continue;
    const long pid = std::strtol(name.c_str() + at + 5, nullptr, 10);
    if (pid > 0 && (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH)) fs::remove(entry.path(), ec);
  }
}

void prepare_checkpoint_directory(const std::string& checkpoint_file) {
  fs::path dir = fs::path(checkpoint_file).parent_path();
  if (dir.empty()) dir = ".";
  create_writable_directory(dir, fmt::format("the directory {} of the checkpoint file {}", dir.string(), checkpoint_file));
}

}  // namespace tsuchi
