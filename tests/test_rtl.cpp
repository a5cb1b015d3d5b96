// The RTL cross-check held in CI (label `rtl`): every job run with the transaction-level
// Recursion Unit and with the Verilated RTL one (fe.recursion_unit_model = rtl) on small
// workloads. Both are checked against the golden model; their cycles, every RU statistic and
// each query's walk cycles must be equal (docs/validation.md: the model claims them exact).
#include <catch2/catch.hpp>

#include <cstdlib>

#include "hw_cases.hpp"
#include "test_util.hpp"
#include "testbench/config.hpp"

using namespace tigris;
using namespace tigris::test;

extern "C" int sc_main(int, char**) { return 2; }  // the Catch2 main runs instead

namespace {

const bool kQuietSystemC = [] { return setenv("SYSTEMC_DISABLE_COPYRIGHT_MESSAGE", "1", 1) == 0; }();

// Each query's walk cycles (every activation, first request to last access complete).
struct WalkCycles final : hw::JobObserver {
  std::vector<std::uint64_t> per_query;
  void ru_walk(std::uint32_t, std::uint32_t query, std::uint64_t begin, std::uint64_t end) override {
    if (query >= per_query.size()) per_query.resize(query + 1);
    per_query[query] += end - begin;
  }
};

// Runs each configuration as TLM and RTL side by side and compares them.
void cross_check(const PointCloud& cloud, const PointCloud& queries, const std::vector<Case>& configs) {
  std::vector<Case> cases;
  std::vector<std::unique_ptr<WalkCycles>> walks;
  for (const Case& c : configs)
    for (const char* model : {"tlm", "rtl"}) {
      Case m = c;
      m.name += std::string(" ") + model;
      m.config.fe.recursion_unit_model = model;
      validate_config(m.config);
      walks.push_back(std::make_unique<WalkCycles>());
      m.observers.push_back(walks.back().get());
      cases.push_back(m);
    }
  const std::vector<SimOutcome> out = run_and_check(cloud, queries, cases);
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const SimOutcome &tlm = out[2 * i], &rtl = out[2 * i + 1];
    INFO(configs[i].name);
    CHECK(rtl.cycles == tlm.cycles);
    CHECK(rtl.units["recursion_units"] == tlm.units["recursion_units"]);
    CHECK(rtl.buffers == tlm.buffers);
    CHECK(rtl.energy == tlm.energy);
    const auto &a = walks[2 * i]->per_query, &b = walks[2 * i + 1]->per_query;
    REQUIRE(a.size() == b.size());
    std::size_t first = 0;
    while (first < a.size() && a[first] == b[first]) ++first;
    INFO("first query whose walk cycles differ: " << first);
    CHECK(first == a.size());
  }
}

std::vector<Case> matrix(const std::vector<std::pair<std::string, SearchParams>>& modes, int height) {
  std::vector<Case> cases;
  for (const auto& [name, params] : modes)
    for (int rus : {1, 8, 64})
      for (bool opt : {true, false})
        for (int top : {0, 6}) {
          hw::AcceleratorConfig c = units(rus, 4, 8, height);
          c.fe.forwarding = c.fe.bypassing = opt;
          c.fe.top_levels_replicated = top;
          cases.push_back(
              {name + " " + std::to_string(rus) + " RU" + (opt ? "" : " no fwd/byp") + " top " + std::to_string(top), c,
               params});
        }
  return cases;
}

}  // namespace

TEST_CASE("RTL RU: NN, kNN and radius, 1/8/64 RUs, forwarding and bypassing on/off, top levels 0/6", "[rtl]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 4000, 42);
  const PointCloud queries = make_queries(cloud, 600, 42);
  cross_check(cloud, queries,
              matrix({{"nn", mode(Mode::NN)}, {"knn8", mode(Mode::KNN, 8)}, {"r1.0", mode(Mode::Radius, 1, 1.0f)}}, 8));
}

TEST_CASE("RTL RU: approximate search, awkward clouds, a full-height tree and the paper's machine", "[rtl]") {
  const PointCloud cloud = make_cloud(CloudKind::Duplicates, 3000, 7);
  const PointCloud queries = make_queries(cloud, 500, 7);
  std::vector<Case> cases;
  cases.push_back({"approx nn", units(8, 4, 8, 6), approximate(mode(Mode::NN), 1.2f)});
  cases.push_back({"approx knn", units(64, 32, 32, 6), approximate(mode(Mode::KNN, 5), 1.2f)});
  cases.push_back({"approx radius", units(8, 4, 8, 6), approximate(mode(Mode::Radius, 1, 1.0f), 0.4f)});
  cases.push_back({"full height nn", units(8, 4, 8, -1), mode(Mode::NN)});
  cases.push_back({"brute force knn", units(8, 4, 8, 0), mode(Mode::KNN, 3)});
  cases.push_back({"paper's machine knn", hw::AcceleratorConfig{}, mode(Mode::KNN, 8)});
  cross_check(cloud, queries, cases);
}
