#include "tsuchi/core/memory_limit.hpp"

#include "tsuchi/core/cgroup.hpp"

#include <fmt/format.h>

#include <sys/resource.h>

#include <cstdio>
#include <cstring>
#include <string>

namespace tsuchi {

namespace {

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

void tighten(MemoryLimit& m, double bytes, std::string what) {
  if (bytes < 0.0) bytes = 0.0;
  if (m.bytes == 0.0 || bytes < m.bytes) m.bytes = bytes, m.what = std::move(what);
}

constexpr double GB = 1e9;

// cgroup v2: memory.max of the process's group and of every parent (a limit set on a parent
// binds the children).
void cgroup_v2(MemoryLimit& m) {
  for (const std::string& dir : cgroup_v2_dirs()) {
    double limit = 0.0, used = 0.0;
    if (!read_cgroup_number(dir + "/memory.max", limit)) continue;
    read_cgroup_number(dir + "/memory.current", used);
    tighten(m, limit - used,
            fmt::format("left under the cgroup memory limit ({}/memory.max = {:.3g} GB, {:.3g} GB in use)", dir,
                        limit / GB, used / GB));
  }
}

// cgroup v1: the memory controller's limit of the group and its parents (a value near 2^63
// means none; a hierarchical limit on a parent binds the children).
void cgroup_v1(MemoryLimit& m) {
  for (const std::string& dir : cgroup_v1_dirs("memory")) {
    double limit = 0.0, used = 0.0;
    if (!read_cgroup_number(dir + "/memory.limit_in_bytes", limit) || !(limit < 1e18)) continue;
    read_cgroup_number(dir + "/memory.usage_in_bytes", used);
    tighten(m, limit - used,
            fmt::format("left under the cgroup memory limit ({}/memory.limit_in_bytes = {:.3g} GB, {:.3g} GB in use)",
                        dir, limit / GB, used / GB));
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
