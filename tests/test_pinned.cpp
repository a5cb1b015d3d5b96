// Pinned behaviour: a fixed set of configurations on a fixed synthetic workload must keep the
// cycles, visit counts, buffer traffic and unit busy/stall cycles recorded in tests/pinned/.
// A refactor must not move them; a deliberate timing change re-records them (and says why):
//   TIGRIS_PIN_RECORD=1 ctest -R pinned -j1   (rewrites tests/pinned/<config>.json in the source tree)
// Every (configuration, mode, top height) is its own test case, so each accelerator is alone in
// its simulation: accelerators side by side share SystemC's event queue, whose order for
// same-time events then couples their figures.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <string>

#include "sw_ref/search.hpp"
#include "testbench/scoreboard.hpp"
#include "testbench/simulation.hpp"
#include "workloads/synthetic.hpp"

using namespace tigris;
using nlohmann::json;

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

struct Pin {
  std::string config_name;  // file tests/pinned/<config_name>.json
  hw::AcceleratorConfig config;
  std::string mode;
  int height;
  bool approximate = false;  // at the default threshold, with config.leader's scope and in-flight policy
  std::string label() const { return mode + " h" + (height < 0 ? std::string("full") : std::to_string(height)); }
};

hw::AcceleratorConfig units(int ru, int su, int pe) {
  hw::AcceleratorConfig c;
  c.fe.recursion_units = ru, c.be.search_units = su, c.be.pes_per_su = pe;
  return c;
}

std::vector<Pin> pins() {
  std::vector<std::pair<std::string, hw::AcceleratorConfig>> configs;
  configs.emplace_back("default", hw::AcceleratorConfig{});
  configs.emplace_back("1-1-1", units(1, 1, 1));
  configs.emplace_back("4-3-5", units(4, 3, 5));
  hw::AcceleratorConfig plain;
  plain.fe.forwarding = plain.fe.bypassing = false;
  configs.emplace_back("no-fwd-byp", plain);
  hw::AcceleratorConfig mqmn;
  mqmn.be.issue_policy = "mqmn";
  configs.emplace_back("mqmn", mqmn);
  hw::AcceleratorConfig no_cache;
  no_cache.node_cache.bytes = 0;
  configs.emplace_back("no-cache", no_cache);
  std::vector<Pin> out;
  for (const auto& [name, cfg] : configs)
    for (const char* mode : {"nn", "knn", "radius"})
      for (int h : {3, 10, -1}) out.push_back({name, cfg, mode, h});
  // Approximate search, each reading (recorded when first_leaf came): a canonical
  // tree has no leaf sets, so only the two-stage heights.
  hw::AcceleratorConfig finished_only, every_leaf;
  finished_only.leader.in_flight = LeaderInFlight::FinishedOnly;
  every_leaf.leader.scope = LeaderScope::EveryLeaf;
  for (const auto& [name, cfg] :
       {std::pair{"approx-first-leaf", hw::AcceleratorConfig{}}, std::pair{"approx-finished-only", finished_only},
        std::pair{"approx-every-leaf", every_leaf}})
    for (const char* mode : {"nn", "knn", "radius"})
      for (int h : {3, 10}) out.push_back({name, cfg, mode, h, true});
  return out;
}

// The figures that must not move, flattened to "group.name" keys. Only this function follows
// the stats JSON's layout; the recorded values stay as they are.
std::map<std::string, std::uint64_t> figures(const SimOutcome& o, bool approximate) {
  const VisitTotals& visits = o.visits.visits;
  const LeaderTotals& leaders = o.visits.leaders;
  std::map<std::string, std::uint64_t> f;
  f["cycles"] = o.cycles;
  f["visits.top"] = visits.top;
  f["visits.pruned"] = visits.pruned;
  f["visits.leaf_points"] = visits.leaf_points;
  f["visits.leaf_visits"] = visits.leaf_visits;
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
  for (const char* n : {"batches", "queries", "busy_cycles", "bqb_max_occupancy"}) f[std::string("su.") + n] = su[n];
  for (const char* s : {"issue_search", "sram", "result_writeback"})
    f[std::string("su.stall.") + s] = su["stall_cycles"][s];
  f["qdn.port_wait_cycles"] = o.units["qdn"]["port_wait_cycles"];
  f["fqq.max_occupancy"] = o.units["fqq"]["max_occupancy"];
  f["fqq.queries_in_flight"] = o.units["fqq"]["queries_in_flight"];
  f["writeback.bytes"] = o.buffers["dram"]["write_bytes"];
  if (approximate) {
    f["visits.follower_points"] = visits.follower_points;
    f["visits.leader_checks"] = visits.leader_checks;
    f["leaders.leaders"] = leaders.leaders;
    f["leaders.followers"] = leaders.followers;
    f["leaders.leader_buffer_full"] = leaders.leader_buffer_full;
    for (const char* n : {"read_bytes", "write_bytes", "list_bytes", "dram_lists"})
      f[std::string("buffers.leader_buffer.") + n] = o.buffers["leader_buffer"][n].get<std::uint64_t>();
  }
  return f;
}

// Simulates one pin; checks it against the golden model, then against the recorded figures
// (or records them).
void check_pin(const Pin& pin) {
  const Workload& w = workload();
  SearchParams params;
  params.mode = parse_mode(pin.mode);
  if (params.mode == Mode::KNN) params.k = 8;
  if (params.mode == Mode::Radius) params.radius = 0.5f;
  if (pin.approximate) {
    params.approximate = true;
    params.approx_thd = default_approx_thd(params);
    params.leader_scope = pin.config.leader.scope;
    params.leader_in_flight = pin.config.leader.in_flight;
  }
  const KdTree tree = build_kdtree(w.cloud, pin.height);
  const tlm_if::TreeImage image = tlm_if::encode_tree_image(tree);
  SimSetup s;
  s.config = pin.config;
  s.config.tree.top_height = tree.top_height;
  s.image = &image;
  s.queries = &w.queries;
  s.num_points = static_cast<std::uint32_t>(w.cloud.size());
  s.job = host_job(params);
  const SimOutcome out = simulate({s}).front();
  INFO(pin.config_name << ", " << pin.label() << ": " << out.error);
  REQUIRE(out.error.empty());
  REQUIRE(out.finished);
  const SearchOutput golden = search(tree, w.queries, params);
  const Verdict v = check_against_golden(tree, w.queries, params, golden, out.results, out.visits);
  if (!v.match) FAIL(v.first.front());
  const auto f = figures(out, pin.approximate);

  const std::string path = std::string(TIGRIS_TESTS_DIR) + "/pinned/" + pin.config_name + ".json";
  json recorded = json::object();
  if (std::ifstream in(path); in.good()) recorded = json::parse(in);
  if (std::getenv("TIGRIS_PIN_RECORD")) {  // read-modify-write: record with ctest -j1
    recorded[pin.label()] = f;
    std::ofstream(path) << recorded.dump(1) << '\n';
    return;
  }
  REQUIRE(recorded.contains(pin.label()));
  const auto pinned = recorded[pin.label()].get<std::map<std::string, std::uint64_t>>();
  REQUIRE(pinned.size() == f.size());
  for (const auto& [key, value] : pinned) {
    INFO(key);
    REQUIRE(f.count(key) == 1);
    CHECK(f.at(key) == value);
  }
}

// One Catch2 test case per pin (ctest runs each in its own process).
struct PinInvoker final : Catch::ITestInvoker {
  explicit PinInvoker(Pin p) : pin(std::move(p)) {}
  void invoke() const override { check_pin(pin); }
  Pin pin;
};

const bool kRegistered = [] {
  static std::vector<std::string> names;  // Catch keeps references to the names
  static std::vector<std::unique_ptr<Catch::AutoReg>> regs;
  const std::vector<Pin> all = pins();
  names.reserve(all.size());
  for (const Pin& p : all) {
    names.push_back("pinned: " + p.config_name + ", " + p.label());
    regs.push_back(std::make_unique<Catch::AutoReg>(new PinInvoker(p), CATCH_INTERNAL_LINEINFO, Catch::StringRef(),
                                                    Catch::NameAndTags(names.back(), "[hw][pinned]")));
  }
  return true;
}();

}  // namespace
