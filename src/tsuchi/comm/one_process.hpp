#pragma once
// What serial.cpp and mpi.cpp share: the one-process answers of communicator.hpp.
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace tsuchi::comm::detail {

// The variables a launcher sets: Open MPI's mpirun, PMIx (srun, prun) and PMI (MPICH's hydra).
inline bool launcher_variables_set() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(v)) return true;
  return false;
}

// exchange() alone: what this process sent itself, once per listed source (which must be rank 0).
inline std::vector<std::string> exchange_with_itself(const std::vector<std::pair<int, std::string>>& sends,
                                                     const std::vector<int>& sources) {
  std::vector<std::string> got;
  for (const int s : sources) {
    if (s != 0) throw std::logic_error("exchange: a source rank other than 0 in a one-process run");
    std::string mine;
    for (const auto& [to, bytes] : sends)
      if (to == 0) mine = bytes;
    got.push_back(std::move(mine));
  }
  return got;
}

}  // namespace tsuchi::comm::detail
