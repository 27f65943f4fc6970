// One process, no MPI: the build without TSUCHI_MPI (communicator.hpp).
#include "tsuchi/comm/communicator.hpp"
#include "tsuchi/comm/one_process.hpp"

namespace tsuchi::comm {

bool launched() { return detail::launcher_variables_set(); }

Session::Session(int&, char**&) {}
Session::~Session() = default;

Communicator Communicator::world() { return Communicator(0, 1); }

void Communicator::barrier() const {}
double Communicator::max(double local) const { return local; }
double Communicator::min(double local) const { return local; }
std::int64_t Communicator::sum(std::int64_t local) const { return local; }
bool Communicator::all(bool local) const { return local; }
bool Communicator::any(bool local) const { return local; }
Communicator::Ranked Communicator::min_loc(Ranked local) const { return local; }
std::int64_t Communicator::exclusive_scan(std::int64_t) const { return 0; }
void Communicator::broadcast(std::string&, int) const {}
std::vector<std::string> Communicator::gather(const std::string& bytes, int) const { return {bytes}; }

std::vector<std::string> Communicator::exchange(const std::vector<std::pair<int, std::string>>& sends,
                                                const std::vector<int>& sources) const {
  return detail::exchange_with_itself(sends, sources);
}

std::string Communicator::agree(bool ok, const std::string& message) const { return ok ? std::string() : message; }

}  // namespace tsuchi::comm
