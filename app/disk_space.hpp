#pragma once
// Sizes as a user reads them, and the space free where the output goes (the output size said
// beside the memory estimate in the summary).
#include <fmt/format.h>

#include <sys/statvfs.h>

#include <filesystem>
#include <string>

namespace tsuchi::app {

// 1234567 -> "1.23 MB": decimal units, three digits.
inline std::string byte_size(double bytes) {
  const char* units[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
  int k = 0;
  while (bytes >= 999.5 && k < 6) bytes /= 1000.0, ++k;
  return fmt::format("{:.3g} {}", bytes, units[k]);
}

// Bytes an unprivileged writer may still put on the file system that holds `path`, or of its
// nearest existing parent when `path` does not exist yet (an output directory made by the run);
// -1 when that cannot be told.
inline double free_space(const std::string& path) {
  std::error_code ec;
  std::filesystem::path p = std::filesystem::absolute(path.empty() ? "." : path, ec);
  if (ec) return -1.0;
  for (;;) {
    struct statvfs s{};
    if (::statvfs(p.c_str(), &s) == 0) return static_cast<double>(s.f_bavail) * static_cast<double>(s.f_frsize);
    if (!p.has_parent_path() || p.parent_path() == p) return -1.0;
    p = p.parent_path();
  }
}

}  // namespace tsuchi::app
