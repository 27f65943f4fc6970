#pragma once
// How much more memory this process may take, and what sets that bound. A model that needs more
// than the machine has free, or more than the process is allowed (a shell's `ulimit -v`, a batch
// scheduler's cgroup limit), is refused before it allocates, naming the bound; a bad_alloc deep in
// the set-up, or the kernel's OOM killer, says nothing of the cause (issue 41, defect 10: a 13 GB
// model under an 8 GB `ulimit -v` ran to "internal error: std::bad_alloc").
#include <string>

namespace tsuchi {

struct MemoryLimit {
  double bytes = 0.0;  // what may still be taken; 0 when nothing is known (not Linux)
  std::string what;    // the bound that sets it, as a phrase: "of memory available (MemAvailable)"
};

// The tightest of: MemAvailable (/proc/meminfo); the memory limit of the process's cgroup and of
// each parent (v2 memory.max, v1 memory.limit_in_bytes; core/cgroup.hpp) less what that group
// uses; the address-space limit (RLIMIT_AS, `ulimit -v`) less the process's address space; the
// data limit (RLIMIT_DATA, `ulimit -d`) less its data segment.
MemoryLimit memory_limit();

}  // namespace tsuchi
