#pragma once
// The control groups (Linux cgroups) this process runs in: where a batch scheduler, a container or
// systemd sets its memory limit and CPU quota. A limit set on a parent group binds the children,
// so a bound is the tightest over the process's own group and every parent up to the mount point.
#include <string>
#include <vector>

namespace tsuchi {

// cgroup v2 (the unified hierarchy, /sys/fs/cgroup): the directory of the process's group, then
// of each parent up to the mount point. In a container whose /proc/self/cgroup path is not under
// the mount, the mount's own directory only; none when there is no unified hierarchy.
std::vector<std::string> cgroup_v2_dirs();

// cgroup v1: the directories of `controller` ("memory", "cpu") for the process's group, each
// parent and the hierarchy's root (/sys/fs/cgroup/CONTROLLER), the group's first.
std::vector<std::string> cgroup_v1_dirs(const std::string& controller);

// The first number of a one-line cgroup file ("max", a negative number and a missing file: none).
bool read_cgroup_number(const std::string& path, double& out);

}  // namespace tsuchi
