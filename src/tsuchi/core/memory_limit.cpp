#include "tsuchi/core/memory_limit.hpp"

#include <fmt/format.h>

#include <sys/resource.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

namespace tsuchi {

namespace {

// The first number of a one-line file ("max" and a missing file give nothing).
bool read_number(const std::string& path, double& out) {
  std::ifstream f(path);
  std::string word;
  if (!(f >> word)) return false;
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  if (end == word.c_str() || *end != '\0' || !(v >= 0.0)) return false;
  out = v;
  return true;
}

// A "Key:   123 kB" line of /proc/self/status or /proc/meminfo, in bytes.
bool read_kb(const char* file, const char* key, double& out) {
  std::FILE* f = std::fopen(file, "r");
  if (!f) return false;
  char line[256];
  bool found = false;
  const std::size_t n = std::strlen(key);
  while (std::fgets(line, sizeof line, f))
    if (std::strncmp(line, key, n) == 0 && line[n] == ':') {
      double kb = 0.0;
      found = std::sscanf(line + n + 1, "%lf", &kb) == 1;
      out = kb * 1024.0;
      break;
    }
  std::fclose(f);
  return found;
}

// The process's cgroup path in the hierarchy whose controller list holds `controller` ("" for the
// unified v2 hierarchy, line "0::/path").
std::string cgroup_path(const std::string& controller) {
  std::ifstream f("/proc/self/cgroup");
  std::string line;
  while (std::getline(f, line)) {
    const auto a = line.find(':'), b = line.find(':', a + 1);
    if (a == std::string::npos || b == std::string::npos) continue;
    const std::string list = line.substr(a + 1, b - a - 1);
    if (controller.empty() ? (line.compare(0, a, "0") == 0 && list.empty())
                           : ("," + list + ",").find("," + controller + ",") != std::string::npos)
      return line.substr(b + 1);
  }
  return {};
}

void tighten(MemoryLimit& m, double bytes, std::string what) {
  if (bytes < 0.0) bytes = 0.0;
  if (m.bytes == 0.0 || bytes < m.bytes) m.bytes = bytes, m.what = std::move(what);
}

constexpr double GB = 1e9;

// cgroup v2: memory.max of the process's cgroup and of every parent up to the mount point (a
// limit set on a parent binds the children); in a container whose /proc/self/cgroup path is not
// under the mount, only the mount's own files.
void cgroup_v2(MemoryLimit& m) {
  const std::string root = "/sys/fs/cgroup";
  std::string path = cgroup_path("");
  for (;;) {
    const std::string dir = root + (path == "/" ? "" : path);
    double limit = 0.0, used = 0.0;
    if (read_number(dir + "/memory.max", limit)) {
      read_number(dir + "/memory.current", used);
      tighten(m, limit - used,
              fmt::format("left under the cgroup memory limit ({}/memory.max = {:.3g} GB, {:.3g} GB in use)", dir,
                          limit / GB, used / GB));
    }
    if (path.empty() || path == "/") break;
    const auto cut = path.rfind('/');
    path = cut == 0 || cut == std::string::npos ? "/" : path.substr(0, cut);
  }
}

// cgroup v1: the memory controller's limit (a value near 2^63 means none).
void cgroup_v1(MemoryLimit& m) {
  const std::string root = "/sys/fs/cgroup/memory";
  const std::string path = cgroup_path("memory");
  for (const std::string& dir : {root + path, root}) {
    double limit = 0.0, used = 0.0;
    if (!read_number(dir + "/memory.limit_in_bytes", limit)) continue;
    if (limit < 1e18) {
      read_number(dir + "/memory.usage_in_bytes", used);
      tighten(m, limit - used,
              fmt::format("left under the cgroup memory limit ({}/memory.limit_in_bytes = {:.3g} GB, {:.3g} GB in use)",
                          dir, limit / GB, used / GB));
    }
    break;
  }
}

void resource_limit(MemoryLimit& m, int resource, const char* status_key, const char* name) {
  rlimit r{};
  if (getrlimit(resource, &r) != 0 || r.rlim_cur == RLIM_INFINITY) return;
  double used = 0.0;
  read_kb("/proc/self/status", status_key, used);
  const double limit = static_cast<double>(r.rlim_cur);
  tighten(m, limit - used, fmt::format("left under the {} of this process ({} = {:.3g} GB, {:.3g} GB in use)", name,
                                       resource == RLIMIT_AS ? "ulimit -v" : "ulimit -d", limit / GB, used / GB));
}

}  // namespace

MemoryLimit memory_limit() {
  MemoryLimit m;
  double avail = 0.0;
  if (read_kb("/proc/meminfo", "MemAvailable", avail))
    tighten(m, avail, "of memory available (MemAvailable in /proc/meminfo)");
  cgroup_v2(m);
  cgroup_v1(m);
  resource_limit(m, RLIMIT_AS, "VmSize", "address-space limit");
  resource_limit(m, RLIMIT_DATA, "VmData", "data-segment limit");
  return m;
}

}  // namespace tsuchi
