#include "tsuchi/io/atomic_file.hpp"

#include "tsuchi/core/errors.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <unistd.h>

namespace tsuchi {

void write_file_atomically(const std::string& path, std::string_view contents) {
  const std::string tmp = fmt::format("{}.tmp{}", path, static_cast<long>(::getpid()));
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw OutputError(fmt::format("cannot write {}: {}", tmp, std::strerror(errno)));
  const bool written = std::fwrite(contents.data(), 1, contents.size(), f) == contents.size();
  const int err_write = errno;
  const bool flushed = std::fflush(f) == 0;
  const bool closed = std::fclose(f) == 0;
  if (!written || !flushed || !closed) {
    std::remove(tmp.c_str());
    throw OutputError(fmt::format("cannot write {}: {}", path, std::strerror(written ? errno : err_write)));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    std::remove(tmp.c_str());
    throw OutputError(fmt::format("cannot rename {} to {}: {}", tmp, path, std::strerror(err)));
  }
}

void prepare_output_directory(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw OutputError(fmt::format("cannot create the output directory {}: {}", dir, ec.message()));
  if (::access(dir.c_str(), W_OK) != 0)
    throw OutputError(fmt::format("the output directory {} is not writable: {}", dir, std::strerror(errno)));
}

}  // namespace tsuchi
