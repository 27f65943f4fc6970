#include "tsuchi/io/appended_file.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/atomic_file.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace tsuchi {

std::uint32_t crc32_update(std::uint32_t crc, std::string_view bytes) {
  uLong c = crc;
  // zlib takes lengths as uInt: feed large buffers in pieces.
  for (std::size_t at = 0; at < bytes.size();) {
    const std::size_t n = std::min<std::size_t>(bytes.size() - at, 1u << 30);
    c = crc32(c, reinterpret_cast<const Bytef*>(bytes.data() + at), static_cast<uInt>(n));
    at += n;
  }
  return static_cast<std::uint32_t>(c);
}

AppendedFile::~AppendedFile() {
  if (fd_ >= 0) ::close(fd_);
}

void AppendedFile::create(const std::string& path, std::string_view header) {
  path_ = path;
  // The header goes in whole under the final name (temporary file, then rename): a run killed
  // before its first rows leaves a CSV with its header, never an empty or half-written one.
  write_file_atomically(path, header);
  fd_ = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd_ < 0) throw OutputError(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
  bytes_ = written_ = header.size();
  crc_ = crc32_update(0, header);
}

void AppendedFile::resume(const std::string& path, std::uint64_t bytes, std::uint32_t crc) {
  path_ = path;
  const std::string advice =
      "restart into the output directory of the checkpointed run (-o), where its frames and CSV files are";
  fd_ = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  if (fd_ < 0) throw InputError(fmt::format("cannot continue {}: {}; {}", path, std::strerror(errno), advice));
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode) || static_cast<std::uint64_t>(st.st_size) < bytes)
    throw InputError(fmt::format("cannot continue {}: it holds {} bytes, the checkpoint covers {}; {}", path,
                                 static_cast<long long>(st.st_size), bytes, advice));
  std::vector<char> buf(1 << 20);
  std::uint32_t c = 0;
  for (std::uint64_t at = 0; at < bytes;) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(buf.size(), bytes - at));
    const ssize_t got = ::pread(fd_, buf.data(), n, static_cast<off_t>(at));
    if (got <= 0) throw InputError(fmt::format("cannot read {}: {}", path, got < 0 ? std::strerror(errno) : "too short"));
    c = crc32_update(c, std::string_view(buf.data(), static_cast<std::size_t>(got)));
    at += static_cast<std::uint64_t>(got);
  }
  if (c != crc)
    throw InputError(fmt::format("cannot continue {}: its first {} bytes are not the rows the checkpoint was "
                                 "written with (the file was rewritten by another run since); {}",
                                 path, bytes, advice));
  if (::ftruncate(fd_, static_cast<off_t>(bytes)) != 0 || ::lseek(fd_, 0, SEEK_END) < 0)
    throw OutputError(fmt::format("cannot cut {} back to the checkpoint's {} bytes: {}", path, bytes, std::strerror(errno)));
  bytes_ = written_ = bytes;
  crc_ = crc;
}

void AppendedFile::append(std::string_view row) {
  queued_.append(row);
  bytes_ += row.size();
  crc_ = crc32_update(crc_, row);
  if (queued_.size() >= (1u << 16)) flush(false);
}

void AppendedFile::flush(bool sync) {
  if (fd_ < 0) return;
  std::size_t done = 0;
  while (done < queued_.size()) {
    const ssize_t n = ::write(fd_, queued_.data() + done, queued_.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int e = n < 0 ? errno : ENOSPC;
      // No half row under the final name: back to the last complete flush.
      if (::ftruncate(fd_, static_cast<off_t>(written_)) == 0) ::lseek(fd_, 0, SEEK_END);
      throw OutputError(fmt::format("cannot write {} ({} bytes): {}; free space or choose another output.directory",
                                    path_, queued_.size(), std::strerror(e)));
    }
    done += static_cast<std::size_t>(n);
  }
  written_ += queued_.size();
  queued_.clear();
  if (sync && ::fdatasync(fd_) != 0)
    throw OutputError(fmt::format("cannot write {}: {}", path_, std::strerror(errno)));
}

}  // namespace tsuchi
