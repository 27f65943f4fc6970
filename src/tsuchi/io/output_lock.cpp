#include "tsuchi/io/output_lock.hpp"

#include "tsuchi/core/errors.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace tsuchi {

namespace {

[[noreturn]] void refuse_busy(const std::string& dir, int fd) {
  char text[32] = {};
  const ssize_t n = ::pread(fd, text, sizeof text - 1, 0);
  const long pid = n > 0 ? std::strtol(text, nullptr, 10) : 0;
  throw OutputError(fmt::format(
      "the output directory {} is in use by another tsuchi run ({}); wait for it to end, or give this run "
      "another directory with -o",
      dir, pid > 0 ? fmt::format("process id {}", pid) : std::string("process id not yet written")));
}

}  // namespace

void DirectoryLock::refuse_if_held(const std::string& dir) {
  const std::string path = dir + "/" + file_name;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return;  // no lock file: nobody holds it
  if (::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK) {
    try {
      refuse_busy(dir, fd);
    } catch (...) {
      ::close(fd);
      throw;
    }
  }
  ::close(fd);  // drops the shared lock, if taken
}

DirectoryLock::DirectoryLock(const std::string& dir) : path_(dir + "/" + file_name) {
  for (int attempt = 0;; ++attempt) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw OutputError(fmt::format("cannot create the lock file {}: {}", path_, std::strerror(errno)));
    // Another run's refuse_if_held() holds the lock for a moment: try for 0.1 s before giving up.
    int e = 0;
    for (int tries = 0; tries < 10; ++tries) {
      e = ::flock(fd_, LOCK_EX | LOCK_NB) == 0 ? 0 : errno;
      if (e != EWOULDBLOCK) break;
      ::usleep(10000);
    }
    if (e != 0) {
      // A file system without locks (some network mounts): run unguarded rather than not at all.
      if (e == ENOLCK || e == EOPNOTSUPP || e == ENOSYS) break;
      const int fd = fd_;
      fd_ = -1;
      if (e != EWOULDBLOCK) {
        ::close(fd);
        throw OutputError(fmt::format("cannot lock {}: {}", path_, std::strerror(e)));
      }
      try {
        refuse_busy(dir, fd);
      } catch (...) {
        ::close(fd);
        throw;
      }
    }
    // The holder before us may have removed the file between our open and our lock: then the lock
    // is on a file nobody else will see; take the one now under the name.
    struct stat held {}, named {};
    if (::fstat(fd_, &held) == 0 && ::stat(path_.c_str(), &named) == 0 && held.st_ino == named.st_ino &&
        held.st_dev == named.st_dev)
      break;
    ::close(fd_);
    fd_ = -1;
    if (attempt > 100) throw OutputError(fmt::format("cannot lock {}: it keeps being replaced", path_));
  }
  const std::string pid = fmt::format("{}\n", static_cast<long>(::getpid()));
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
    const int e = errno;
    ::close(fd_);
    fd_ = -1;
    throw OutputError(fmt::format("cannot write {}: {}", path_, std::strerror(e)));
  }
}

DirectoryLock::~DirectoryLock() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());  // while still held, so no other run can hold a lock on a file that is gone
  ::close(fd_);
}

}  // namespace tsuchi
