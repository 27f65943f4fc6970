#pragma once
// The processes of a run and the few collective operations the layers above need (issue 42): the
// lowest layer, with one implementation per build. serial.cpp is one process and no MPI (every
// collective returns its argument); mpi.cpp, compiled when CMake finds MPI (TSUCHI_MPI), wraps
// MPI_COMM_WORLD. The layers above call these functions and never MPI itself, so the build
// without MPI is the same code with one rank (docs/issue42-design.md, section 4).
//
// Every operation is collective: each process of the communicator must call it, in the same
// order. A process that meets an error inside a collective phase says so through agree() rather
// than throwing alone, which would leave the others waiting.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace tsuchi::comm {

// MPI for the life of the program: started when a launcher (mpirun, mpiexec, srun) started the
// process, so that a plain `tsuchi run` neither starts MPI nor pays for it. Only the main thread
// communicates (MPI_THREAD_FUNNELED): between the OpenMP regions, never inside them.
class Session {
 public:
  Session(int& argc, char**& argv);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

 private:
  bool started_ = false;  // MPI was started here (a launched process of an MPI build): ended here
};

// Whether the environment says a launcher started this process (Open MPI's, PMIx or PMI's variables).
bool launched();

class Communicator {
 public:
  // Every process of the run (one without MPI, or before a Session has started it).
  static Communicator world();

  int rank() const { return rank_; }
  int size() const { return size_; }

  void barrier() const;
  // Exact on any number of processes: a maximum or minimum of doubles is one of the arguments,
  // whatever the order they are compared in (the first of +0 and -0 aside: both compare equal).
  double max(double local) const;
  double min(double local) const;
  // Integers add exactly in any order.
  std::int64_t sum(std::int64_t local) const;
  bool all(bool local) const;
  bool any(bool local) const;
  // The least value over the processes, and of the processes holding it the least key: the
  // first faulty particle by id, the limiting particle of the time step. The values are numbers
  // (MPI leaves the minimum with a NaN undefined).
  struct Ranked {
    double value = 0.0;
    std::int64_t key = 0;
  };
  Ranked min_loc(Ranked local) const;
  // The sum of `local` over the processes of lower rank (0 on rank 0): where each process's share
  // of a numbering starts.
  std::int64_t exclusive_scan(std::int64_t local) const;

  // `bytes` of process `root` on every process.
  void broadcast(std::string& bytes, int root) const;
  // At `root`, each process's bytes in rank order; elsewhere, empty.
  std::vector<std::string> gather(const std::string& bytes, int root) const;
  // Sparse point-to-point exchange: sends each (rank, bytes) of `sends`, at most one per rank,
  // and returns, in the order of `sources`, what each of those ranks sent to this one. A process
  // may send to itself. Every send must be matched by its receiver listing the sender in
  // `sources`, and every source must send.
  std::vector<std::string> exchange(const std::vector<std::pair<int, std::string>>& sends,
                                    const std::vector<int>& sources) const;

  // A collective verdict: "" when every process is `ok`, else, on every process, the message of
  // the lowest-ranked process that was not (prefixed by its rank when there are several).
  std::string agree(bool ok, const std::string& message) const;

 private:
  Communicator(int rank, int size) : rank_(rank), size_(size) {}
  int rank_ = 0, size_ = 1;
};

}  // namespace tsuchi::comm
