#include "tsuchi/core/cgroup.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace tsuchi {

namespace {

// The process's group path in the hierarchy whose controller list holds `controller` ("" for the
// unified v2 hierarchy, line "0::/path"); empty when there is none.
std::string cgroup_path(const std::string& controller, bool& found) {
  std::ifstream f("/proc/self/cgroup");
  std::string line;
  found = false;
  while (std::getline(f, line)) {
    const auto a = line.find(':'), b = line.find(':', a + 1);
    if (a == std::string::npos || b == std::string::npos) continue;
    const std::string list = line.substr(a + 1, b - a - 1);
    if (controller.empty() ? (line.compare(0, a, "0") == 0 && list.empty())
                           : ("," + list + ",").find("," + controller + ",") != std::string::npos) {
      found = true;
      return line.substr(b + 1);
    }
  }
  return {};
}

}  // namespace

std::vector<std::string> cgroup_v2_dirs() {
  const std::string root = "/sys/fs/cgroup";
  bool found = false;
  std::string path = cgroup_path("", found);
  std::vector<std::string> dirs;
  std::error_code ec;
  if (!std::filesystem::exists(root + "/cgroup.controllers", ec)) return dirs;  // not a v2 mount
  for (;;) {
    const std::string dir = root + (path == "/" ? "" : path);
    if (std::filesystem::is_directory(dir, ec)) dirs.push_back(dir);
    if (path.empty() || path == "/") break;
    const auto cut = path.rfind('/');
    path = cut == 0 || cut == std::string::npos ? "/" : path.substr(0, cut);
  }
  if (dirs.empty() || dirs.back() != root) dirs.push_back(root);
  return dirs;
}

std::vector<std::string> cgroup_v1_dirs(const std::string& controller) {
  const std::string root = "/sys/fs/cgroup/" + controller;
  bool found = false;
  std::string path = cgroup_path(controller, found);
  std::vector<std::string> dirs;
  std::error_code ec;
  if (!std::filesystem::is_directory(root, ec)) return dirs;
  while (found && !path.empty() && path != "/") {
    if (std::filesystem::is_directory(root + path, ec)) dirs.push_back(root + path);
    const auto cut = path.rfind('/');
    path = cut == 0 || cut == std::string::npos ? "/" : path.substr(0, cut);
  }
  dirs.push_back(root);
  return dirs;
}

bool read_cgroup_number(const std::string& path, double& out) {
  std::ifstream f(path);
  std::string word;
  if (!(f >> word)) return false;
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  if (end == word.c_str() || *end != '\0' || !(v >= 0.0)) return false;
  out = v;
  return true;
}

}  // namespace tsuchi
