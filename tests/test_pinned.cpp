// Pinned behaviour: a fixed set of configurations on a fixed synthetic workload must keep the
// cycles, visit counts, buffer traffic and unit busy/stall cycles recorded in tests/pinned/.
// A refactor must not move them; a deliberate timing change re-records them (and says why):
//   TIGRIS_PIN_RECORD=1 ctest -R pinned   (writes tests/pinned/<config>.json in the source tree)
// Each test case simulates one configuration in NN, kNN and radius search at three top heights.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <fstream>
#include <map>
#include <string>

#include "scoreboard.hpp"
#include "simulation.hpp"
#include "sw_ref/search.hpp"
#include "sw_ref/synthetic.hpp"

using namespace tigris;
using nlohmann::json;

extern "C" int sc_main(int, char**);

namespace {

const bool kQuiet = [] { return setenv("SYSTEMC_DISABLE_COPYRIGHT_MESSAGE", "1", 1) == 0; }();

struct Workload {
  PointCloud cloud, queries;
};

// Every 2nd point of synthetic frame 0 (57,600 points), every 37th of frame 1 as queries.
const Workload& workload() {
  static const Workload w = [] {
    const SyntheticPair pair = make_synthetic_pair();
    Workload out;
    for (std::size_t i = 0; i < pair.frame0.size(); i += 2) out.cloud.push_back(pair.frame0[i]);
    for (std::size_t i = 0; i < pair.frame1.size(); i += 37) out.queries.push_back(pair.frame1[i]);
    return out;
  }();
  return w;
}

// The figures that must not move, flattened to "group.name" keys. Only this function follows
// the stats JSON's layout; the recorded values stay as they are.
std::map<std::string, std::uint64_t> figures(const SimOutcome& o, const SearchOutput& hw_visits) {
  std::map<std::string, std::uint64_t> f;
  f["cycles"] = o.cycles;
  f["visits.top"] = hw_visits.visits.top;
  f["visits.pruned"] = hw_visits.visits.pruned;
  f["visits.leaf_points"] = hw_visits.visits.leaf_points;
  f["visits.leaf_visits"] = hw_visits.visits.leaf_visits;
  for (const char* b : {"points", "queries", "query_stack", "results"})
    for (const char* n : {"reads", "writes", "read_bytes", "write_bytes", "conflict_cycles"})
      f[std::string("buffers.") + b + "." + n] = o.buffers[b][n].get<std::uint64_t>();
  for (const char* n : {"hits", "misses", "read_bytes", "fill_bytes"})
    f[std::string("buffers.node_cache.") + n] = o.buffers["node_cache"][n].get<std::uint64_t>();
  f["buffers.dram.write_bytes"] = o.buffers["dram"]["write_bytes"].get<std::uint64_t>();
  const json& ru = o.units["recursion_units"];
  f["ru.activations"] = ru["activations"];
  f["ru.busy_cycles"] = ru["busy_cycles"];
  f["ru.prune_cycles"] = ru["prune_cycles"];
  for (const char* s : {"pi_rs_dependency", "sram", "bqb_full", "result_writeback"})
    f[std::string("ru.stall.") + s] = ru["stall_cycles"][s];
  const json& su = o.units["search_units"];
  for (const char* n : {"batches", "queries", "busy_cycles", "bqb_max_occupancy"})
    f[std::string("su.") + n] = su[n];
  for (const char* s : {"issue_search", "sram", "result_writeback"})
    f[std::string("su.stall.") + s] = su["stall_cycles"][s];
  f["qdn.port_wait_cycles"] = o.units["qdn"]["port_wait_cycles"];
  f["fqq.max_occupancy"] = o.units["fqq"]["max_occupancy"];
  f["fqq.queries_in_flight"] = o.units["fqq"]["queries_in_flight"];
  f["writeback.bytes"] = o.units["result_writeback"]["bytes"];
  return f;
}

SearchParams params_of(const std::string& mode) {
  SearchParams p;
  p.mode = parse_mode(mode);
  if (p.mode == Mode::KNN) p.k = 8;
  if (p.mode == Mode::Radius) p.radius = 0.5f;
  return p;
}

// Runs `config` in every mode and height side by side; checks each against the golden model,
// then against the recorded figures (or records them).
void check_pinned(const std::string& name, const hw::AcceleratorConfig& config) {
  const Workload& w = workload();
  struct Run {
    std::string label;
    SearchParams params;
    KdTree tree;
    tlm_if::TreeImage image;
  };
  std::vector<Run> runs;
  runs.reserve(9);
  for (const char* mode : {"nn", "knn", "radius"})
    for (int h : {3, 10, -1}) {
      Run r;
      r.label = std::string(mode) + " h" + (h < 0 ? std::string("full") : std::to_string(h));
      r.params = params_of(mode);
      r.tree = build_kdtree(w.cloud, h);
      r.image = tlm_if::encode_tree_image(r.tree);
      runs.push_back(std::move(r));
    }
  std::vector<SimSetup> setups;
  for (const Run& r : runs) {
    SimSetup s;
    s.config = config;
    s.config.tree.top_height = r.tree.top_height;
    s.image = &r.image;
    s.queries = &w.queries;
    s.num_points = static_cast<std::uint32_t>(w.cloud.size());
    s.job = host_job(r.params);
    setups.push_back(s);
  }
  const std::vector<SimOutcome> out = simulate(setups);

  const std::string path = std::string(TIGRIS_TESTS_DIR) + "/pinned/" + name + ".json";
  const bool record = std::getenv("TIGRIS_PIN_RECORD") != nullptr;
  json recorded = json::object();
  if (!record) {
    std::ifstream in(path);
    REQUIRE(in.good());
    recorded = json::parse(in);
  }
  json now = json::object();
  for (std::size_t i = 0; i < runs.size(); ++i) {
    INFO(name << ", " << runs[i].label);
    REQUIRE(out[i].error.empty());
    REQUIRE(out[i].finished);
    const SearchOutput golden = search(runs[i].tree, w.queries, runs[i].params);
    const Verdict v = check_against_golden(runs[i].tree, w.queries, runs[i].params, golden, out[i].results, out[i].visits);
    if (!v.match) FAIL(v.first.front());
    const auto f = figures(out[i], out[i].visits);
    now[runs[i].label] = f;
    if (record) continue;
    REQUIRE(recorded.contains(runs[i].label));
    const auto pinned = recorded[runs[i].label].get<std::map<std::string, std::uint64_t>>();
    REQUIRE(pinned.size() == f.size());
    for (const auto& [key, value] : pinned) {
      INFO(key);
      REQUIRE(f.count(key) == 1);
      CHECK(f.at(key) == value);
    }
  }
  if (record) std::ofstream(path) << now.dump(1) << '\n';
}

hw::AcceleratorConfig units(int ru, int su, int pe) {
  hw::AcceleratorConfig c;
  c.fe.recursion_units = ru, c.be.search_units = su, c.be.pes_per_su = pe;
  return c;
}

}  // namespace

TEST_CASE("pinned: default configuration", "[hw][pinned]") { check_pinned("default", hw::AcceleratorConfig{}); }

TEST_CASE("pinned: 1 RU, 1 SU x 1 PE", "[hw][pinned]") { check_pinned("1-1-1", units(1, 1, 1)); }

TEST_CASE("pinned: 4 RU, 3 SU x 5 PE", "[hw][pinned]") { check_pinned("4-3-5", units(4, 3, 5)); }

TEST_CASE("pinned: forwarding and bypassing off", "[hw][pinned]") {
  hw::AcceleratorConfig c;
  c.fe.forwarding = c.fe.bypassing = false;
  check_pinned("no-fwd-byp", c);
}

TEST_CASE("pinned: MQMN issue", "[hw][pinned]") {
  hw::AcceleratorConfig c;
  c.be.issue_policy = hw::IssuePolicyKind::Mqmn;
  check_pinned("mqmn", c);
}

TEST_CASE("pinned: Node Cache off", "[hw][pinned]") {
  hw::AcceleratorConfig c;
  c.node_cache.bytes = 0;
  check_pinned("no-cache", c);
}
