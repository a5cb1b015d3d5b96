// Random stall injection (MatchLib style; docs/model.md): every hand-off may be held
// back; results and visit counts must stay bit-exact and the machine must never deadlock, also
// with queues of one entry. A matrix of seeds x rates x tiny queues x exact and approximate
// search (ctest label `matrix`; skip with `ctest -LE matrix`).
#include <catch2/catch.hpp>

#include "hw_cases.hpp"
#include "test_util.hpp"

using namespace tigris;
using namespace tigris::test;

namespace {

// Every seed x rate x search on `tiny` (a machine with some queue cut to one entry).
void stall_matrix(const std::string& name, const hw::AcceleratorConfig& tiny) {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 1500, 71);
  const PointCloud queries = make_queries(cloud, 150, 71);
  const std::vector<std::pair<std::string, SearchParams>> searches = {
      {"nn", mode(Mode::NN)},
      {"radius", mode(Mode::Radius, 1, 1.0f)},
      {"approx knn", approximate(mode(Mode::KNN, 4), 1.0f)},
      {"approx radius", approximate(mode(Mode::Radius, 1, 1.0f), 0.4f)}};
  std::vector<Case> cases;
  for (const auto& [sname, p] : searches) {
    cases.push_back({name + " " + sname + " no stalls", tiny, p});
    for (std::uint64_t seed : {1, 2, 3})
      for (double rate : {0.1, 0.5}) {
        hw::AcceleratorConfig c = tiny;
        c.stall.rate = rate, c.stall.seed = seed;
        cases.push_back({name + " " + sname + " seed " + std::to_string(seed) + " rate " + std::to_string(rate), c, p});
      }
  }
  const auto out = run_and_check(cloud, queries, cases);  // bit-exact, finished, no deadlock
  for (std::size_t i = 0; i < cases.size(); i += 7) {
    INFO(cases[i].name);
    for (std::size_t j = i + 1; j < i + 7; ++j) CHECK(out[j].cycles > out[i].cycles);  // stalls cost cycles
  }
}

hw::AcceleratorConfig machine() { return units(4, 3, 4, 5); }

}  // namespace

TEST_CASE("stall matrix: BE Query Buffers of one entry", "[stall]") {
  auto c = machine();
  c.be.bqb_entries = 1;
  stall_matrix("bqb1", c);
}

TEST_CASE("stall matrix: an FE Query Queue of one entry (one query in flight)", "[stall]") {
  auto c = machine();
  c.fe.fqq_bytes = static_cast<std::uint64_t>(c.fe.fqq_entry_bytes);
  stall_matrix("fqq1", c);
}

TEST_CASE("stall matrix: a Query Stack Buffer for one query", "[stall]") {
  auto c = machine();
  c.sram.query_stack.bytes = 5 * 8;  // top height 5 x 8-byte entries
  stall_matrix("stack1", c);
}

TEST_CASE("stall matrix: a Query Stack Buffer for three queries, every queue tiny", "[stall]") {
  auto c = machine();
  c.sram.query_stack.bytes = 3 * 5 * 8;
  c.be.bqb_entries = 1;
  c.be.pes_per_su = 1;
  stall_matrix("stack3 all tiny", c);
}
