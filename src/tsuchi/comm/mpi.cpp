// Several processes: MPI_COMM_WORLD (communicator.hpp), compiled when CMake finds MPI.
#include "tsuchi/comm/communicator.hpp"
#include "tsuchi/comm/one_process.hpp"

#include <mpi.h>

#include <climits>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace tsuchi::comm {

namespace {

// The tag of exchange()'s messages; the other operations are collectives, which take no tag.
constexpr int exchange_tag = 4242;

bool mpi_running() {
  int up = 0, down = 0;
  MPI_Initialized(&up);
  MPI_Finalized(&down);
  return up && !down;
}

int count_of(std::size_t bytes) {
  if (bytes > static_cast<std::size_t>(INT_MAX))
    throw std::length_error("a message of more than 2^31 bytes between processes");  // a chunked send when a model needs it
  return static_cast<int>(bytes);
}

}  // namespace

bool launched() { return detail::launcher_variables_set(); }

Session::Session(int& argc, char**& argv) {
  if (!launched()) return;
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  started_ = true;
}

Session::~Session() {
  if (started_ && mpi_running()) MPI_Finalize();
}

Communicator Communicator::world() {
  if (!mpi_running()) return Communicator(0, 1);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return Communicator(rank, size);
}

void Communicator::barrier() const {
  if (size_ > 1) MPI_Barrier(MPI_COMM_WORLD);
}

double Communicator::max(double local) const {
  if (size_ == 1) return local;
  double r = local;
  MPI_Allreduce(&local, &r, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return r;
}

double Communicator::min(double local) const {
  if (size_ == 1) return local;
  double r = local;
  MPI_Allreduce(&local, &r, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
  return r;
}

std::int64_t Communicator::sum(std::int64_t local) const {
  if (size_ == 1) return local;
  std::int64_t r = local;
  MPI_Allreduce(&local, &r, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  return r;
}

bool Communicator::all(bool local) const {
  if (size_ == 1) return local;
  int in = local ? 1 : 0, r = in;
  MPI_Allreduce(&in, &r, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
  return r != 0;
}

bool Communicator::any(bool local) const {
  if (size_ == 1) return local;
  int in = local ? 1 : 0, r = in;
  MPI_Allreduce(&in, &r, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
  return r != 0;
}

Communicator::Ranked Communicator::min_loc(Ranked local) const {
  if (size_ == 1) return local;
  // MPI's MINLOC pairs take an int index; a 64-bit key takes two steps: the least value, then the
  // least key among the processes that hold it.
  const double least = min(local.value);
  const std::int64_t mine = local.value == least ? local.key : INT64_MAX;
  std::int64_t key = mine;
  MPI_Allreduce(&mine, &key, 1, MPI_INT64_T, MPI_MIN, MPI_COMM_WORLD);
  return {least, key};
}

std::int64_t Communicator::exclusive_scan(std::int64_t local) const {
  if (size_ == 1) return 0;
  std::int64_t r = 0;
  MPI_Exscan(&local, &r, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  return rank_ == 0 ? 0 : r;  // MPI leaves rank 0's result undefined
}

void Communicator::broadcast(std::string& bytes, int root) const {
  if (size_ == 1) return;
  std::uint64_t n = bytes.size();
  MPI_Bcast(&n, 1, MPI_UINT64_T, root, MPI_COMM_WORLD);
  bytes.resize(static_cast<std::size_t>(n));
  if (n > 0) MPI_Bcast(bytes.data(), count_of(bytes.size()), MPI_BYTE, root, MPI_COMM_WORLD);
}

std::vector<std::string> Communicator::gather(const std::string& bytes, int root) const {
  if (size_ == 1) return {bytes};
  const int n = count_of(bytes.size());
  std::vector<int> counts(rank_ == root ? static_cast<std::size_t>(size_) : 0);
  MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, root, MPI_COMM_WORLD);
  std::vector<int> starts(counts.size());
  std::size_t total = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) starts[r] = count_of(total), total += static_cast<std::size_t>(counts[r]);
  std::string all(total, '\0');
  MPI_Gatherv(bytes.data(), n, MPI_BYTE, all.data(), counts.data(), starts.data(), MPI_BYTE, root, MPI_COMM_WORLD);
  std::vector<std::string> out;
  for (std::size_t r = 0; r < counts.size(); ++r) out.push_back(all.substr(static_cast<std::size_t>(starts[r]), static_cast<std::size_t>(counts[r])));
  return out;
}

std::vector<std::string> Communicator::exchange(const std::vector<std::pair<int, std::string>>& sends,
                                                const std::vector<int>& sources) const {
  if (size_ == 1) return detail::exchange_with_itself(sends, sources);  // alone (MPI perhaps not started)
  std::vector<MPI_Request> requests(sends.size());
  for (std::size_t k = 0; k < sends.size(); ++k)
    MPI_Isend(sends[k].second.data(), count_of(sends[k].second.size()), MPI_BYTE, sends[k].first, exchange_tag,
              MPI_COMM_WORLD, &requests[k]);
  std::vector<std::string> got;
  for (const int s : sources) {
    MPI_Status st;
    MPI_Probe(s, exchange_tag, MPI_COMM_WORLD, &st);
    int n = 0;
    MPI_Get_count(&st, MPI_BYTE, &n);
    std::string bytes(static_cast<std::size_t>(n), '\0');
    MPI_Recv(bytes.data(), n, MPI_BYTE, s, exchange_tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    got.push_back(std::move(bytes));
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  return got;
}

std::string Communicator::agree(bool ok, const std::string& message) const {
  if (size_ == 1) return ok ? std::string() : message;
  // The lowest failing rank, then its message to all.
  const int mine = ok ? INT_MAX : rank_;
  int first = mine;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (first == INT_MAX) return {};
  std::string text = rank_ == first ? message : std::string();
  broadcast(text, first);
  return "process " + std::to_string(first) + ": " + text;
}

}  // namespace tsuchi::comm
