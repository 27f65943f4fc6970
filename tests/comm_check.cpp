// The communicator (comm/communicator.hpp) on however many processes run this program: alone (the
// one-process path, also of an MPI build not launched by mpirun) and under `mpirun -np 2` and
// `-np 3` (ctest: comm_mpi_2, comm_mpi_3). Each check computes what every rank must see from the
// rank count alone. Its own main: MPI starts before the tests and ends after them.
#include "tsuchi/comm/communicator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace {

using tsuchi::comm::Communicator;

TEST(Communicator, ReductionsSeeEveryProcess) {
  const Communicator c = Communicator::world();
  const int n = c.size(), r = c.rank();
  ASSERT_GE(n, 1);
  ASSERT_LT(r, n);
  EXPECT_EQ(c.max(static_cast<double>(r)), n - 1.0);
  EXPECT_EQ(c.min(static_cast<double>(r) + 0.5), 0.5);
  EXPECT_EQ(c.sum(r + 1), std::int64_t{n} * (n + 1) / 2);
  // Beyond 2^53, where a sum of doubles would round: integers add exactly.
  EXPECT_EQ(c.sum((std::int64_t{1} << 60) + r), std::int64_t{n} * (std::int64_t{1} << 60) + std::int64_t{n} * (n - 1) / 2);
  EXPECT_TRUE(c.all(true));
  EXPECT_FALSE(c.all(r != n - 1));
  EXPECT_TRUE(c.any(r == n - 1));
  EXPECT_FALSE(c.any(false));
  EXPECT_EQ(c.exclusive_scan(r + 1), std::int64_t{r} * (r + 1) / 2);
}

TEST(Communicator, MinLocTakesTheLeastKeyOfTheLeastValue) {
  const Communicator c = Communicator::world();
  const int n = c.size(), r = c.rank();
  // Odd ranks hold 1.0, even ranks 2.0; keys fall with the rank, and are beyond 2^31.
  const std::int64_t big = std::int64_t{1} << 40;
  const Communicator::Ranked got = c.min_loc({r % 2 ? 1.0 : 2.0, big - r});
  if (n == 1) {
    EXPECT_EQ(got.value, 2.0);
    EXPECT_EQ(got.key, big);
  } else {
    const int last_odd = (n - 1) % 2 ? n - 1 : n - 2;
    EXPECT_EQ(got.value, 1.0);
    EXPECT_EQ(got.key, big - last_odd);
  }
  // Ties: every process holds the same value; the least key wins.
  const Communicator::Ranked tie = c.min_loc({-0.25, 7 + (r + 1) % n});
  EXPECT_EQ(tie.value, -0.25);
  EXPECT_EQ(tie.key, 7);
}

TEST(Communicator, BytesGoWhereTheyAreSent) {
  const Communicator c = Communicator::world();
  const int n = c.size(), r = c.rank();
  std::string word = r == n - 1 ? std::string("from the last\0with a NUL", 24) : std::string();
  c.broadcast(word, n - 1);
  EXPECT_EQ(word, std::string("from the last\0with a NUL", 24));

  const std::vector<std::string> all = c.gather(std::string(static_cast<std::size_t>(r), 'a' + static_cast<char>(r)), 0);
  if (r == 0) {
    ASSERT_EQ(all.size(), static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) EXPECT_EQ(all[static_cast<std::size_t>(k)], std::string(static_cast<std::size_t>(k), 'a' + static_cast<char>(k)));
  } else {
    EXPECT_TRUE(all.empty());
  }

  // A ring: each process sends to the next and hears from the previous (itself when alone).
  const int next = (r + 1) % n, previous = (r + n - 1) % n;
  const std::vector<std::string> got = c.exchange({{next, "from " + std::to_string(r)}}, {previous});
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0], "from " + std::to_string(previous));
  // Nothing sent, nothing heard: an empty exchange is a no-op on every process.
  EXPECT_TRUE(c.exchange({}, {}).empty());
}

TEST(Communicator, AgreeGivesEveryProcessTheFirstFailure) {
  const Communicator c = Communicator::world();
  const int n = c.size(), r = c.rank();
  EXPECT_EQ(c.agree(true, "unused"), "");
  const std::string verdict = c.agree(r == 0, "fault on " + std::to_string(r));
  if (n == 1)
    EXPECT_EQ(verdict, "");
  else
    EXPECT_EQ(verdict, "process 1: fault on 1");
  EXPECT_EQ(c.agree(false, "all fail, " + std::to_string(r)), n == 1 ? "all fail, 0" : "process 0: all fail, 0");
}

}  // namespace

int main(int argc, char** argv) {
  tsuchi::comm::Session session(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  // Under mpirun every process runs the tests and prints its own report (a failure seen only on
  // rank 2 shows there).
  const int failed = RUN_ALL_TESTS();
  // Every process's verdict: a failure on rank 2 must fail the run that rank 0 prints.
  return tsuchi::comm::Communicator::world().any(failed != 0) ? 1 : 0;
}
