// The accelerator model against the golden model and against the timing formulas. SystemC
// elaborates once per process (ctest runs each test case in its own), so each test case
// simulates all the configurations it compares side by side in one run.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <set>

#include <sys/resource.h>

#include "hw/area_model.hpp"
#include "hw/be/pe_array.hpp"
#include "hw/be/replacement_policy.hpp"
#include "hw/mem/banked_sram.hpp"
#include "hw_cases.hpp"
#include "sw_ref/search.hpp"
#include "test_util.hpp"
#include "testbench/scoreboard.hpp"
#include "testbench/simulation.hpp"
#include "testbench/timeline.hpp"
#include "workloads/synthetic.hpp"

using namespace tigris;
using namespace tigris::test;

extern "C" int sc_main(int, char**) { return 2; }  // the Catch2 main runs instead

namespace {

const bool kQuietSystemC = [] { return setenv("SYSTEMC_DISABLE_COPYRIGHT_MESSAGE", "1", 1) == 0; }();

}  // namespace

TEST_CASE("accelerator is bit-exact on random clouds across configurations and modes", "[hw]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 3000, 5);
  const PointCloud queries = make_queries(cloud, 300, 5);
  std::vector<Case> cases;
  const std::vector<std::pair<std::string, SearchParams>> modes = {{"nn", mode(Mode::NN)},
                                                                   {"knn5", mode(Mode::KNN, 5)},
                                                                   {"r1.0", mode(Mode::Radius, 1, 1.0f)},
                                                                   {"r1.5max3", mode(Mode::Radius, 1, 1.5f, 3)}};
  for (const auto& [mname, p] : modes) {
    for (int h : {1, 3, 8, -1}) {
      cases.push_back({mname + " 1/1/1 h" + std::to_string(h), units(1, 1, 1, h), p});
      cases.push_back({mname + " 4/3/5 h" + std::to_string(h), units(4, 3, 5, h), p});
      cases.push_back({mname + " default h" + std::to_string(h), units(64, 32, 32, h), p});
    }
    hw::AcceleratorConfig mqmn = units(8, 4, 8, 5);
    mqmn.be.issue_policy = "mqmn";
    cases.push_back({mname + " mqmn", mqmn, p});
    hw::AcceleratorConfig plain = units(8, 4, 8, 5);
    plain.fe.forwarding = plain.fe.bypassing = false;
    plain.node_cache.bytes = 0;
    cases.push_back({mname + " no forwarding, bypassing, cache", plain, p});
  }
  run_and_check(cloud, queries, cases);
}

TEST_CASE("accelerator is bit-exact on awkward clouds: duplicates, all-equal, lattice", "[hw]") {
  const PointCloud dup = make_cloud(CloudKind::Duplicates, 1500, 9);
  const PointCloud grid = make_cloud(CloudKind::Grid, 1500, 9);
  PointCloud both = dup;
  both.insert(both.end(), grid.begin(), grid.end());
  both.insert(both.end(), 40, Point3{2.0f, 2.0f, 1.0f});  // a block of identical points
  const PointCloud queries = make_queries(both, 240, 9);
  std::vector<Case> cases;
  for (int h : {0, 2, 6, -1})
    for (const SearchParams& p : {mode(Mode::NN), mode(Mode::KNN, 8), mode(Mode::Radius, 1, 1.0f)})
      cases.push_back({"h" + std::to_string(h) + " " + to_string(p.mode), units(6, 4, 4, h), p});
  run_and_check(both, queries, cases);
}

TEST_CASE("accelerator is bit-exact on the synthetic LiDAR pair for top heights 1 to full", "[hw][synthetic]") {
  const SyntheticPair pair = make_synthetic_pair();
  PointCloud queries;
  for (std::size_t i = 0; i < pair.frame1.size(); i += 23) queries.push_back(pair.frame1[i]);
  std::vector<Case> cases;
  for (int h : {1, 5, 10, 14, -1}) cases.push_back({"nn h" + std::to_string(h), units(64, 32, 32, h), mode(Mode::NN)});
  cases.push_back({"knn10 h10", units(64, 32, 32, 10), mode(Mode::KNN, 10)});
  cases.push_back({"r0.30 h10", units(64, 32, 32, 10), mode(Mode::Radius, 1, 0.30f)});
  cases.push_back({"r0.75 h12 mqmn",
                   [] {
                     auto c = units(16, 8, 16, 12);
                     c.be.issue_policy = "mqmn";
                     return c;
                   }(),
                   mode(Mode::Radius, 1, 0.75f)});
  run_and_check(pair.frame0, queries, cases);
}

TEST_CASE("tiny queues finish without deadlock and stay bit-exact", "[hw]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 2000, 12);
  const PointCloud queries = make_queries(cloud, 400, 12);
  std::vector<Case> cases;
  hw::AcceleratorConfig full_bqb = units(16, 4, 8, 6);
  full_bqb.be.bqb_entries = 1;  // many queries in flight, one BE Query Buffer entry per SU
  cases.push_back({"bqb 1", full_bqb, mode(Mode::KNN, 3)});
  for (int bqb : {1, 2}) {
    hw::AcceleratorConfig c = units(16, 4, 8, 6);
    c.be.bqb_entries = bqb;
    c.fe.fqq_bytes = 8;  // one FQQ entry: one query in flight
    cases.push_back({"bqb " + std::to_string(bqb) + " fqq 1", c, mode(Mode::KNN, 3)});
  }
  hw::AcceleratorConfig stack = units(16, 4, 8, 6);
  stack.sram.query_stack.bytes = 6 * 8 * 3;  // three queries' stacks
  cases.push_back({"query stack for 3 queries", stack, mode(Mode::NN)});
  const auto out = run_and_check(cloud, queries, cases);
  CHECK(out[0].units["recursion_units"]["stall_cycles"]["bqb_full"].get<std::uint64_t>() > 0);
  CHECK(out[0].units["search_units"]["bqb_max_occupancy"].get<std::uint64_t>() == 1);
  CHECK(out[1].units["fqq"]["queries_in_flight"].get<std::uint64_t>() == 1);
  CHECK(out[3].units["fqq"]["queries_in_flight"].get<std::uint64_t>() == 3);
}

TEST_CASE("edge cases: one point, k larger than the cloud, radius with no hits", "[hw]") {
  const PointCloud one = {{1.0f, 2.0f, 3.0f}};
  const PointCloud queries = {{1.0f, 2.0f, 3.0f}, {-4.0f, 0.5f, 9.0f}, {100.0f, 0.0f, 0.0f}};
  const PointCloud few = make_cloud(CloudKind::Uniform, 9, 3);
  run_and_check(one, queries,
                {{"nn h0", units(2, 2, 2, 0), mode(Mode::NN)},
                 {"knn5 h1", units(2, 2, 2, 1), mode(Mode::KNN, 5)},
                 {"radius h1", units(2, 2, 2, 1), mode(Mode::Radius, 1, 0.5f)},
                 {"knn 20 of 9", units(3, 2, 4, 2), mode(Mode::KNN, 20), &few},
                 {"radius none", units(3, 2, 4, -1), mode(Mode::Radius, 1, 1e-3f), &few}});
}

TEST_CASE("a large k: heap-ordered slots stay bit-exact (k = 300 of 700 points, and k = all)", "[hw]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 700, 4);
  const PointCloud queries = make_queries(cloud, 60, 4);
  run_and_check(cloud, queries,
                {{"knn300 default", units(64, 32, 32, 5), mode(Mode::KNN, 300)},
                 {"knn700 1/1/1", units(1, 1, 1, 3), mode(Mode::KNN, 700)}});
}

TEST_CASE("RU timing: forwarding saves the 3 PI->RS stall cycles per node, bypassing 2 per pruned node",
          "[hw][timing]") {
  // One query on the canonical tree and one RU: the whole job is one top-tree walk.
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 1000, 3);
  const PointCloud queries = {{0.3f, -0.2f, 0.5f}};
  std::vector<Case> cases;
  for (bool fwd : {true, false})
    for (bool byp : {true, false}) {
      hw::AcceleratorConfig c = units(1, 1, 1, -1);
      c.fe.forwarding = fwd, c.fe.bypassing = byp;
      cases.push_back({std::string(fwd ? "fwd" : "nofwd") + (byp ? " byp" : " nobyp"), c, mode(Mode::KNN, 4)});
    }
  const auto out = run_and_check(cloud, queries, cases);
  const std::uint64_t top = out[0].visits.per_query[0].top, pruned = out[0].visits.per_query[0].pruned;
  REQUIRE(top > 10);
  REQUIRE(pruned > 5);
  const auto& cost = hw::CostTable{};
  // With forwarding and bypassing the RU retires one node per cycle and drops a pruned one in two.
  const auto& ru = out[0].units["recursion_units"];
  CHECK(ru["busy_cycles"].get<std::uint64_t>() == cost.ru_fetch_query + top * cost.ru_node +
                                                      pruned * cost.ru_prune_at_rn + cost.ru_drain +
                                                      cost.result_writeback);
  CHECK(out[2].cycles - out[0].cycles == 3 * top);     // forwarding off
  CHECK(out[1].cycles - out[0].cycles == 2 * pruned);  // bypassing off
  CHECK(out[3].cycles - out[0].cycles == 3 * top + 2 * pruned);
}

TEST_CASE("SU timing: a Node Set of N points past B PEs takes N + B - 1 + 3 cycles", "[hw][timing]") {
  CHECK(hw::PeArray::stream_cycles(100, 32, 3) == 134);
  CHECK(hw::PeArray::stream_cycles(1, 1, 3) == 4);
  CHECK(hw::PeArray::stream_cycles(0, 5, 3) == 0);
  // Brute force (h = 0): every query scans the one leaf set of all N points.
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 700, 4);
  const PointCloud queries = make_queries(cloud, 90, 4);
  // One query: the job's cycles grow one for one with N (the stream is the critical path).
  const PointCloud small(cloud.begin(), cloud.begin() + 300);
  const PointCloud one_query = {{0.1f, 0.2f, 0.3f}};
  const std::vector<Case> cases = {{"8 PEs", units(4, 1, 8, 0), mode(Mode::NN)},
                                   {"1 PE", units(4, 1, 1, 0), mode(Mode::NN)},
                                   {"1 query, 300 points", units(1, 1, 4, 0), mode(Mode::NN), &small, &one_query},
                                   {"1 query, 700 points", units(1, 1, 4, 0), mode(Mode::NN), nullptr, &one_query}};
  const auto out = run_and_check(cloud, queries, cases);
  for (std::size_t i = 0; i < 2; ++i) {
    const auto& su = out[i].units["search_units"];
    const std::uint64_t batches = su["batches"], served = su["queries"];
    CHECK(served == queries.size());
    // Each batch streams all 700 points: sum over batches of (N + B - 1 + 3), nothing stalls.
    CHECK(su["busy_cycles"].get<std::uint64_t>() == batches * (700 - 1 + 3) + served);
    CHECK(su["stall_cycles"]["sram"].get<std::uint64_t>() == 0);
  }
  CHECK(out[1].units["search_units"]["batches"].get<std::uint64_t>() == queries.size());
  CHECK(out[0].units["search_units"]["batches"].get<std::uint64_t>() < queries.size());
  CHECK(out[3].cycles - out[2].cycles == 700 - 300);
}

TEST_CASE("QDN sends each leaf visit to Search Unit leaf mod #SU", "[hw]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 3000, 17);
  const PointCloud queries = make_queries(cloud, 300, 17);
  const auto out = run_and_check(cloud, queries, {{"3 SUs", units(8, 3, 4, 5), mode(Mode::KNN, 6)}});
  const SearchOutput golden = search(build_kdtree(cloud, 5), queries, mode(Mode::KNN, 6));
  std::vector<std::uint64_t> expect(3, 0);
  for (const ScheduleEntry& e : golden.schedule) ++expect[e.leaf % 3];
  std::vector<std::uint64_t> served;
  for (const auto& su : out[0].units["search_units"]["per_unit"]) served.push_back(su["queries"]);
  CHECK(served == expect);
}

TEST_CASE("SRAM banks: bursts spread over banks, overlapping accesses queue, ports cap the rate", "[hw][timing]") {
  hw::SramConfig c{4096, 4, 4, 2, 16};
  const hw::EnergyTable prices;
  hw::EnergyMeter meter(prices);
  const hw::Clock clock{sc_core::sc_time(2, sc_core::SC_NS)};
  hw::BankedSram sram("sram", c, clock, meter);
  tlm_if::AccessProfile burst;
  burst.bytes = 128;                            // 8 words of 16 bytes
  CHECK(sram.charge(10, burst) == 10 + 2 + 2);  // 2 words per bank, then the latency
  CHECK(sram.charge(10, burst) == 10 + 4 + 2);  // the same banks are busy until 12
  CHECK(sram.stats().counters_json()["conflict_cycles"] == 2);
  const std::uint64_t same_bank[] = {0, 64, 128, 192};  // all in bank 0
  tlm_if::AccessProfile scatter;
  scatter.scatter = same_bank, scatter.scatter_count = 4, scatter.scatter_size = 16;
  CHECK(sram.charge(100, scatter) == 100 + 4 + 2);  // serialised on one bank
  scatter.scatter_size = 32;                        // two words each: banks 0 and 1
  CHECK(sram.charge(200, scatter) == 200 + 4 + 2);
  CHECK(sram.stats().counters_json()["reads"] == 8 + 8 + 4 + 8);
  // An in-order pipeline: the second access waits a cycle for bank 0, and so does every later one.
  const tlm_if::PipelineAccess walk[] = {{0, 16, 0}, {64, 16, 0}, {16, 4, 1}};
  tlm_if::AccessProfile ordered;
  ordered.pipeline = walk, ordered.pipeline_count = 3, ordered.bytes = 36;
  CHECK(sram.charge(300, ordered) == 300 + 1 + 1 + 1 + 2);                  // offset 1, stalled 1, then the latency
  CHECK(sram.stats().counters_json()["conflict_cycles"] == 2 + 3 + 2 + 1);  // + the stall
  hw::SramConfig narrow{4096, 4, 1, 0, 16};
  hw::BankedSram port("port", narrow, clock, meter);
  CHECK(port.charge(0, burst) == 8);  // one port: a word per cycle
  // Ports are shared across requests (units): two single-word reads of different banks in the
  // same cycle take the two ports of a 2-port buffer; a third waits a cycle.
  hw::SramConfig two_ports{4096, 4, 2, 0, 16};
  hw::BankedSram shared("shared", two_ports, clock, meter);
  tlm_if::AccessProfile word;
  word.bytes = 16;
  for (std::uint64_t bank : {0, 1}) {
    word.first_byte = bank * 16;
    CHECK(shared.charge(50, word) == 51);
  }
  word.first_byte = 2 * 16;  // a free bank, but no free port in cycle 50
  CHECK(shared.charge(50, word) == 52);
}

TEST_CASE("jobs that do not fit are rejected with the reason", "[hw]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 500, 2);
  const PointCloud queries = make_queries(cloud, 20, 2);
  const KdTree tree = build_kdtree(cloud, 6);
  const tlm_if::TreeImage image = tlm_if::encode_tree_image(tree);
  SimSetup stack;
  stack.config.sram.query_stack.bytes = 40;  // less than one stack of 6 entries x 8 bytes
  stack.image = &image, stack.queries = &queries, stack.num_points = 500;
  SimSetup points = stack;
  points.config = hw::AcceleratorConfig{};
  points.config.sram.points.bytes = 4096;
  const auto out = simulate({stack, points});
  CHECK_THAT(out[0].error, Catch::Contains("Query Stack Buffer"));
  CHECK_FALSE(out[0].finished);
  CHECK_THAT(out[1].error, Catch::Contains("Point Buffer"));
  CHECK_FALSE(out[1].finished);
}

namespace {

// One accelerator alone in the simulation (accelerators side by side share SystemC's event
// queue, whose same-time order then couples them): the job run three times.
void check_repeatable(const SearchParams& params) {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 2500, 21);
  const PointCloud queries = make_queries(cloud, 300, 21);
  const KdTree tree = build_kdtree(cloud, 6);
  const tlm_if::TreeImage image = tlm_if::encode_tree_image(tree);
  SimSetup s;
  s.config = units(8, 4, 4, 6);
  s.config.sram.results.bytes = 4096;   // a small stream area ...
  s.config.dram.bytes_per_cycle = 0.7;  // ... drained slowly, in fractional cycles: backpressure
  s.image = &image, s.queries = &queries, s.num_points = 2500;
  s.job = host_job(params);
  s.job.runs = 3;
  const SimOutcome out = simulate({s}).front();
  INFO(out.error << out.deadlock);
  REQUIRE(out.finished);
  REQUIRE(out.runs.size() == 3);
  const SearchOutput golden = search(tree, queries, params);
  for (const RunRecord& r : out.runs) {
    CHECK(check_against_golden(tree, queries, params, golden, r.results, r.visits).match);
    CHECK(r.cycles == out.runs[0].cycles);
    CHECK(r.stats == out.runs[0].stats);  // every counter reset at START, no state left behind
    CHECK(r.visits.schedule == out.runs[0].visits.schedule);
  }
  const auto& units = out.runs[0].stats["units"];
  CHECK(units["recursion_units"]["stall_cycles"]["result_writeback"].get<std::uint64_t>() +
            units["search_units"]["stall_cycles"]["result_writeback"].get<std::uint64_t>() >
        0);
}

}  // namespace

TEST_CASE("a kNN job run three times on one accelerator: identical cycles, results, visits, stats", "[hw]") {
  check_repeatable(mode(Mode::KNN, 4));
}

TEST_CASE("a radius job run three times on one accelerator: identical cycles, results, visits, stats", "[hw]") {
  check_repeatable(mode(Mode::Radius, 1, 1.2f));
}

TEST_CASE("the paper's accounting: the write-back off the critical path, its bytes free of DRAM energy",
          "[hw][timing]") {
  // A radius job whose results outrun a slow channel: the physical machine waits for it; off
  // the critical path nobody waits, as on a channel of unbounded bandwidth and no latency (the
  // same cycles, but for the last record's drain: at most one cycle), and every byte still moves.
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 2500, 21);
  const PointCloud queries = make_queries(cloud, 300, 21);
  hw::AcceleratorConfig channel = units(8, 4, 4, 6);
  channel.sram.results.bytes = 4096;
  channel.dram.bytes_per_cycle = 0.7;
  hw::AcceleratorConfig off = channel;
  off.dram.writeback = hw::Writeback::OffCriticalPath;
  off.energy.charge_result_dram = false;
  hw::AcceleratorConfig wide = channel;
  wide.dram.bytes_per_cycle = 1e6;
  wide.dram.latency_cycles = 0;
  const SearchParams r = mode(Mode::Radius, 1, 1.2f);
  const auto out = run_and_check(cloud, queries, {{"channel", channel, r}, {"off", off, r}, {"wide", wide, r}});
  const auto waited = [](const SimOutcome& o) {
    return o.units["recursion_units"]["stall_cycles"]["result_writeback"].get<std::uint64_t>() +
           o.units["search_units"]["stall_cycles"]["result_writeback"].get<std::uint64_t>();
  };
  CHECK(waited(out[0]) > 0);
  CHECK(waited(out[1]) == 0);
  CHECK(out[1].cycles < out[0].cycles);
  CHECK(out[1].cycles <= out[2].cycles);
  CHECK(out[2].cycles <= out[1].cycles + 1);
  const auto bytes = [](const SimOutcome& o) { return o.buffers["dram"]["write_bytes"].get<std::uint64_t>(); };
  CHECK(bytes(out[1]) == bytes(out[0]));
  CHECK(bytes(out[1]) > 0);
  CHECK(out[0].energy["dram"].get<double>() == Approx(bytes(out[0]) * hw::EnergyTable{}.dram_pj_per_byte));
  CHECK(out[1].energy["dram"].get<double>() == 0.0);
}

TEST_CASE("Result Buffer words follow sram.results.word_bytes", "[hw][timing]") {
  // kNN k=1 slots are 16 bytes: two 8-byte words or one 16-byte word per slot access.
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 1500, 8);
  const PointCloud queries = make_queries(cloud, 120, 8);
  hw::AcceleratorConfig wide = units(4, 2, 4, 5);
  wide.sram.results.word_bytes = 16;
  const auto out = run_and_check(
      cloud, queries,
      {{"8-byte words", units(4, 2, 4, 5), mode(Mode::KNN, 1)}, {"16-byte words", wide, mode(Mode::KNN, 1)}});
  const auto& narrow_r = out[0].buffers["results"];
  const auto& wide_r = out[1].buffers["results"];
  CHECK(narrow_r["reads"].get<std::uint64_t>() == 2 * wide_r["reads"].get<std::uint64_t>());
  CHECK(narrow_r["writes"].get<std::uint64_t>() == 2 * wide_r["writes"].get<std::uint64_t>());
  CHECK(narrow_r["read_bytes"] == wide_r["read_bytes"]);
}

namespace {

// Replays a script on a replacement policy: a number inserts that leaf, "h" + number reads it,
// "e" evicts; returns the victims in order.
std::vector<std::uint32_t> victims(hw::ReplacementPolicy& p, const std::vector<std::string>& script) {
  std::vector<std::uint32_t> out;
  for (const std::string& op : script) {
    if (op == "e")
      out.push_back(p.evict());
    else if (op == "reset")
      p.reset();
    else if (op[0] == 'h')
      p.hit(static_cast<std::uint32_t>(std::stoul(op.substr(1))));
    else
      p.inserted(static_cast<std::uint32_t>(std::stoul(op)), 64);
  }
  return out;
}

}  // namespace

TEST_CASE("Node Cache replacement: LRU evicts the least recently read, FIFO the oldest fill", "[hw][node_cache]") {
  const std::vector<std::string> script = {"1",     "2",  "3",  "h1", "e",        // LRU 2, FIFO 1
                                           "4",     "h3", "e",  "e",              // LRU 1 4, FIFO 2 3
                                           "5",     "h3", "h5", "h3", "e", "e",   // LRU 5 3, FIFO 4 5
                                           "reset", "7",  "8",  "h7", "e", "e"};  // LRU 8 7, FIFO 7 8
  const std::vector<std::uint32_t> lru = {2, 1, 4, 5, 3, 8, 7}, fifo = {1, 2, 3, 4, 5, 7, 8};
  // The factory follows node_cache.policy, by the names the policies registered.
  const auto make = [](const char* name) {
    hw::AcceleratorConfig c;
    c.node_cache.policy = name;
    return hw::make_replacement_policy(c);
  };
  CHECK(victims(*make("lru"), script) == lru);
  CHECK(victims(*make("fifo"), script) == fifo);
  // Without hits the two agree: both evict in fill order.
  const std::vector<std::string> no_hits = {"9", "4", "6", "e", "2", "e", "e", "e"};
  CHECK(victims(*make("lru"), no_hits) == std::vector<std::uint32_t>{9, 4, 6, 2});
  CHECK(victims(*make("fifo"), no_hits) == std::vector<std::uint32_t>{9, 4, 6, 2});
}

namespace {

struct CacheCounts {
  std::uint64_t hits = 0, misses = 0, evictions = 0;
  bool operator==(const CacheCounts& o) const {
    return hits == o.hits && misses == o.misses && evictions == o.evictions;
  }
};
std::ostream& operator<<(std::ostream& os, const CacheCounts& c) {
  return os << "{hits " << c.hits << ", misses " << c.misses << ", evictions " << c.evictions << "}";
}

// An independent model of the Node Cache: whole Node Sets of `capacity` bytes, looked up in
// the schedule's order, evicting the front of `order` (fill order; LRU moves a hit to the back).
CacheCounts replay_cache(const KdTree& tree, const Schedule& schedule, std::uint64_t capacity, bool fifo) {
  CacheCounts c;
  std::vector<std::uint32_t> order;
  std::uint64_t used = 0;
  const auto bytes = [&](std::uint32_t leaf) {
    return std::uint64_t{tree.leaf_size(leaf)} * sizeof(tlm_if::PointEntry);
  };
  for (const ScheduleEntry& e : schedule) {
    const auto it = std::find(order.begin(), order.end(), e.leaf);
    if (it != order.end()) {
      ++c.hits;
      if (!fifo) order.erase(it), order.push_back(e.leaf);
      continue;
    }
    ++c.misses;
    if (bytes(e.leaf) > capacity) continue;
    while (used + bytes(e.leaf) > capacity) {
      used -= bytes(order.front());
      order.erase(order.begin());
      ++c.evictions;
    }
    order.push_back(e.leaf);
    used += bytes(e.leaf);
  }
  return c;
}

}  // namespace

TEST_CASE("a Node Cache of four Node Sets under lru and fifo: bit-exact, each policy's own evictions",
          "[hw][node_cache]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 3000, 21);
  const PointCloud queries = make_queries(cloud, 300, 21);
  const int height = 5;
  const KdTree tree = build_kdtree(cloud, height);
  std::uint32_t largest = 0;
  for (std::uint32_t l = 0; l < tree.num_leaves(); ++l) largest = std::max(largest, tree.leaf_size(l));
  // Every Node Set fits (no bypass), four at a time: misses beyond the cold ones are evictions.
  const std::uint64_t capacity = 4 * std::uint64_t{largest} * sizeof(tlm_if::PointEntry);
  std::vector<Case> cases;
  for (const auto kind : {"lru", "fifo"}) {
    // One PE per SU: every batch is one query, so the recorded schedule is the cache's lookup
    // order (SUs look up the shared cache as they issue, and record the visit right after).
    hw::AcceleratorConfig c = units(8, 4, 1, height);
    c.node_cache.bytes = capacity;
    c.node_cache.policy = kind;
    cases.push_back({kind, c, mode(Mode::KNN, 4)});
  }
  const auto out = run_and_check(cloud, queries, cases);
  std::vector<std::uint64_t> hits;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    INFO(cases[i].name);
    const bool fifo = cases[i].config.node_cache.policy == "fifo";
    const nlohmann::json& nc = out[i].buffers["node_cache"];
    CHECK(nc["policy"] == cases[i].name);
    const Schedule& schedule = out[i].visits.schedule;
    const CacheCounts got{nc["hits"].get<std::uint64_t>(), nc["misses"].get<std::uint64_t>(),
                          nc["evictions"].get<std::uint64_t>()};
    CHECK(out[i].units["search_units"]["batches"].get<std::uint64_t>() == schedule.size());
    CHECK(got.hits + got.misses == schedule.size());
    std::set<std::uint32_t> distinct;
    for (const ScheduleEntry& e : schedule) distinct.insert(e.leaf);
    CHECK(distinct.size() > 4);
    CHECK(got.hits > 0);
    CHECK(got.evictions > 0);
    CHECK(got.misses > distinct.size());     // Node Sets were evicted and read again
    CHECK(got.misses - got.evictions <= 4);  // what is left in the cache at the end
    // The cache behaves exactly as its policy says on this lookup order, and not as the other
    // policy would: the workload tells the two apart.
    CHECK(got == replay_cache(tree, schedule, capacity, fifo));
    CHECK_FALSE(got == replay_cache(tree, schedule, capacity, !fifo));
    hits.push_back(got.hits);
  }
  CHECK(hits[0] != hits[1]);
}

TEST_CASE("latency: one per query, within the job's cycles, and BQB waits one per leaf visit", "[hw]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 2000, 61);
  const PointCloud queries = make_queries(cloud, 200, 61);
  const PointCloud one_query = {{0.5f, 0.25f, 0.0f}};
  const auto out = run_and_check(cloud, queries,
                                 {{"many", units(4, 2, 4, 5), mode(Mode::KNN, 4)},
                                  {"one", units(1, 1, 1, 5), mode(Mode::NN), nullptr, &one_query}});
  for (const SimOutcome& o : out) {
    const auto& q = o.latency["query"];
    CHECK(q["count"].get<std::size_t>() == o.visits.per_query.size());
    CHECK(q["max"].get<std::uint64_t>() <= o.cycles);
    CHECK(q["p50"].get<std::uint64_t>() <= q["p99"].get<std::uint64_t>());
    CHECK(q["mean"].get<double>() > 0);
    CHECK(o.latency["bqb_wait"]["count"].get<std::uint64_t>() == o.visits.visits.leaf_visits);
  }
  // Alone, the query never waits for a PE, and the job ends when its results reach DRAM.
  CHECK(out[1].latency["bqb_wait"]["max"].get<std::uint64_t>() == 0);
  CHECK(out[0].latency["bqb_wait"]["max"].get<std::uint64_t>() > 0);
}

TEST_CASE("a stuck machine is reported with its state, not hung or half-judged", "[hw]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 1500, 62);
  const PointCloud queries = make_queries(cloud, 100, 62);
  const KdTree tree = build_kdtree(cloud, 4);
  const tlm_if::TreeImage image = tlm_if::encode_tree_image(tree);
  SimSetup s = one_setup(image, queries, cloud.size(), units(4, 2, 4, 4), mode(Mode::NN));
  // Scanned queries vanish instead of going back to the front-end: nothing is pending, work is left.
  s.test_hook = [](hw::TigrisAccelerator& a) { a.front_end_for_test().drop_reinserted_for_test(true); };
  const SimOutcome o = simulate({s}).front();
  CHECK_FALSE(o.finished);
  CHECK(o.error.empty());
  INFO(o.deadlock);
  CHECK_THAT(o.deadlock, Catch::Contains("queries finished 0 of 100"));
  CHECK_THAT(o.deadlock, Catch::Contains("held by no queue or unit (lost)"));
}

namespace {

// Runs one setup with a timeline attached; returns the trace.
nlohmann::json timeline_of(const PointCloud& cloud, const PointCloud& queries, int height, hw::AcceleratorConfig config,
                           std::uint32_t shown) {
  const KdTree tree = build_kdtree(cloud, height);
  const tlm_if::TreeImage image = tlm_if::encode_tree_image(tree);
  config.tree.top_height = height;
  TimelineRecorder timeline(1000.0 / config.clock_mhz, shown);
  SimSetup s = one_setup(image, queries, cloud.size(), config, mode(Mode::NN));
  s.observers.push_back(&timeline);
  const SimOutcome o = simulate({s}).front();
  REQUIRE(o.finished);
  return nlohmann::json::parse(timeline.trace().dump());  // through text, as a viewer reads it
}

}  // namespace

TEST_CASE("timeline: trace-event JSON, sampled queries, slices ordered per track, flows paired", "[hw][timeline]") {
  {
    const PointCloud cloud = make_cloud(CloudKind::Uniform, 3000, 63);
    const PointCloud queries = make_queries(cloud, 400, 63);
    hw::AcceleratorConfig c = units(8, 4, 8, 0);
    c.be.issue_policy = "mqmn";  // overlapping batches need lanes
    const auto t = timeline_of(cloud, queries, 5, c, 100);
    REQUIRE(t.contains("traceEvents"));
    std::map<std::pair<int, std::uint64_t>, std::vector<std::pair<double, double>>> tracks;
    std::map<std::uint64_t, int> flows;
    std::set<std::uint64_t> queries_seen;
    for (const auto& e : t["traceEvents"]) {
      const std::string ph = e.at("ph");
      REQUIRE(e.contains("pid"));
      if (ph == "X") {
        REQUIRE(e.at("dur").get<double>() >= 0);
        const double ts = e["ts"].get<double>(), dur = e["dur"].get<double>();
        tracks[{e["pid"].get<int>(), e["tid"].get<std::uint64_t>()}].push_back({ts, ts + dur});
        if (e["args"].contains("query")) queries_seen.insert(e["args"]["query"].get<std::uint64_t>());
      } else if (ph == "s" || ph == "f") {
        flows[e.at("id").get<std::uint64_t>()] += ph == "s" ? 1 : 10;
      } else if (ph == "C") {  // whole-machine counters: mean levels, never negative
        for (const auto& [k, v] : e.at("args").items()) CHECK(v.get<double>() >= 0);
      } else {
        REQUIRE((ph == "M" || ph == "b" || ph == "e"));
      }
    }
    // Sampling: every 4th of 400 queries.
    CHECK(queries_seen.size() == 100);
    for (std::uint64_t q : queries_seen) CHECK(q % 4 == 0);
    // On every track slices come in order and never overlap (nested or disjoint).
    for (auto& [track, slices] : tracks) {
      std::sort(slices.begin(), slices.end());
      for (std::size_t i = 1; i < slices.size(); ++i) CHECK(slices[i].first >= slices[i - 1].second - 1e-9);
    }
    for (const auto& [id, n] : flows) CHECK(n == 11);  // one start and one finish each
    CHECK(flows.size() > 100);
  }
}

TEST_CASE("timeline: one query, brute force, 1 RU / 1 SU / 1 PE, every slice as the cost table says",
          "[hw][timeline]") {
  {
    const PointCloud cloud = make_cloud(CloudKind::Uniform, 200, 64);
    const PointCloud one = {{0.5f, 0.5f, 0.5f}};
    const auto t = timeline_of(cloud, one, 0, units(1, 1, 1, 0), 10);
    std::vector<nlohmann::json> x;
    std::size_t flow_starts = 0;
    for (const auto& e : t["traceEvents"]) {
      if (e["ph"] == "X") x.push_back(e);
      flow_starts += e["ph"] == "s";
    }
    std::sort(x.begin(), x.end(), [](const nlohmann::json& a, const nlohmann::json& b) {
      return a["ts"].get<double>() < b["ts"].get<double>();
    });
    REQUIRE(x.size() == 5);  // walk, QDN hop, batch, final walk, write-back
    CHECK(x[0]["name"] == "walk q0");
    CHECK(x[1]["pid"] == 2);
    CHECK(x[2]["name"] == "leaf 0");
    CHECK(x[3]["name"] == "walk q0");
    CHECK(x[4]["pid"] == 4);
    CHECK(flow_starts == 4);  // walk -> hop -> batch -> walk -> write-back
    const double ns = 2.0;    // 500 MHz
    // QDN: cost.qdn_latency 1 cycle; batch: associative search 1 + issue 1, then 200 + 1 - 1 + 3.
    CHECK(x[1]["dur"].get<double>() * 1000 == Approx(1 * ns));
    CHECK(x[2]["dur"].get<double>() * 1000 == Approx((2 + 203) * ns));
    CHECK(x[2]["args"]["stream_entries"] == 200);
    CHECK(x[1]["ts"].get<double>() == Approx(x[0]["ts"].get<double>() + x[0]["dur"].get<double>()));
  }
}

TEST_CASE("same-cycle arbitration: side by side, alone or built in reverse, identical figures", "[hw][timing]") {
  // The fourth copy times its buffer accesses through b_transport instead of the buffers'
  // direct TimingTarget: the two ways must give the same figures too.
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 4000, 65);
  const PointCloud queries = make_queries(cloud, 1500, 65);
  const KdTree tree = build_kdtree(cloud, 6);
  const tlm_if::TreeImage image = tlm_if::encode_tree_image(tree);
  // Per mode, four copies of one accelerator in one SystemC run, the second built in reverse.
  std::vector<SimSetup> setups;
  for (const SearchParams& p : {mode(Mode::KNN, 4), mode(Mode::Radius, 1, 1.0f)}) {
    hw::AcceleratorConfig c = units(16, 8, 8, 6);
    c.sram.points.ports = 8;  // fewer ports than banks: the port calendar is shared
    SimSetup s = one_setup(image, queries, cloud.size(), c, p);
    SimSetup reversed = s;
    reversed.reverse_construction = true;
    SimSetup transport = s;
    transport.test_hook = [](hw::TigrisAccelerator& a) { a.time_through_transport_for_test(); };
    setups.insert(setups.end(), {s, reversed, s, transport});
  }
  const auto out = simulate(setups);
  for (const SimOutcome& o : out) REQUIRE(o.finished);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const SimOutcome& first = out[i / 4 * 4];
    INFO("setup " << i);
    CHECK(out[i].cycles == first.cycles);
    CHECK(out[i].units == first.units);
    CHECK(out[i].buffers == first.buffers);
    CHECK(out[i].latency == first.latency);
    CHECK(out[i].visits.schedule == first.visits.schedule);
  }
  CHECK(out[0].cycles != out[4].cycles);  // the two modes are different jobs
}

TEST_CASE("top-level replicas: bit-exact, their node reads leave the Point Buffer for RU registers", "[hw][timing]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 3000, 66);
  const PointCloud queries = make_queries(cloud, 400, 66);
  std::vector<Case> cases;
  for (int n : {0, 2, 4, 20}) {                   // 20: more levels than the tree has, the whole top tree
    hw::AcceleratorConfig c = units(8, 4, 1, 6);  // one PE: Node Set reads do not depend on timing
    c.node_cache.bytes = 0;
    c.fe.top_levels_replicated = std::min(n, 16);
    cases.push_back({"replicated " + std::to_string(n), c, mode(Mode::KNN, 3)});
  }
  const auto out = run_and_check(cloud, queries, cases);
  const hw::EnergyTable prices;
  const auto read_bytes = [](const SimOutcome& o) { return o.buffers["points"]["read_bytes"].get<std::uint64_t>(); };
  std::uint64_t previous = read_bytes(out[0]) + 1;
  for (std::size_t i = 0; i < out.size(); ++i) {
    INFO(cases[i].name);
    const std::uint64_t moved = read_bytes(out[0]) - read_bytes(out[i]);
    CHECK(read_bytes(out[i]) < previous);  // each level more takes reads off the Point Buffer
    previous = read_bytes(out[i]);
    CHECK(moved % sizeof(tlm_if::PointEntry) == 0);
    // The RU's energy grows by the register reads only.
    CHECK(out[i].energy["ru"].get<double>() - out[0].energy["ru"].get<double>() ==
          Approx(static_cast<double>(moved) * prices.register_pj_per_byte));
  }
  // All 6 levels replicated: the RUs read no top-tree node from the Point Buffer, only the
  // leaf directory (4 bytes per leaf visit) beside the SUs' Node Sets (16 bytes per point).
  const std::uint64_t dir_and_sets = out[3].visits.visits.leaf_visits * 4 + out[3].visits.visits.leaf_points * 16;
  CHECK(read_bytes(out[3]) == dir_and_sets);
  // Area: every RU holds 2^N - 1 nodes of 16 bytes in registers.
  CHECK(hw::area_of(cases[2].config).of("top_level_replicas") ==
        Approx(8 * 15 * 16 / 1024.0 * cases[2].config.area.register_mm2_per_kib));
  CHECK(hw::area_of(cases[0].config).of("top_level_replicas") == 0.0);
}

TEST_CASE("wake-ups far ahead: bit-exact, and the event loop's memory does not grow with the distance",
          "[hw][timing]") {
  // A node costing a million cycles puts every RU's wake-up tens of millions of cycles ahead,
  // far past the scheduler's ring of near cycles (hw/scheduler.hpp): they wait in its heap.
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 3000, 67);
  const PointCloud queries = make_queries(cloud, 300, 67);
  hw::AcceleratorConfig slow = units(8, 4, 4, 6), fast = slow;
  slow.cost.ru_node = 1000000;
  rusage before{};
  getrusage(RUSAGE_SELF, &before);
  const auto out =
      run_and_check(cloud, queries, {{"slow nodes", slow, mode(Mode::KNN, 4)}, {"default", fast, mode(Mode::KNN, 4)}});
  rusage after{};
  getrusage(RUSAGE_SELF, &after);
  CHECK(out[0].cycles > 1000000 * out[0].visits.visits.top / 8);  // the RUs' walks alone
  CHECK(out[0].visits.visits.top == out[1].visits.visits.top);    // the same searches
  // A ring sized to the furthest wake-up would hold tens of millions of cycles (hundreds of MB).
  CHECK(after.ru_maxrss - before.ru_maxrss < 64 * 1024);  // KiB
}

TEST_CASE("scan thread: one or two host threads give the same results and figures", "[hw][timing]") {
  // NN/kNN scans of an exact search may run on a second host thread (hw/host/threaded_scans.hpp).
  // A query stack of a few slots brings each query back to an RU right after its scan, so the
  // walk often has to wait for the worker; a large one lets the worker fall far behind.
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 3000, 68);
  const PointCloud queries = make_queries(cloud, 800, 68);
  const KdTree tree = build_kdtree(cloud, 6);
  const tlm_if::TreeImage image = tlm_if::encode_tree_image(tree);
  std::vector<SimSetup> setups;  // pairs side by side in one SystemC run: 1 thread, 2 threads
  std::vector<std::string> names;
  for (const SearchParams& p : {mode(Mode::NN), mode(Mode::KNN, 6)}) {
    for (std::uint64_t stack_bytes : {std::uint64_t{3 * 6 * 8}, std::uint64_t{1} << 20}) {
      hw::AcceleratorConfig c = units(16, 8, 8, 6);
      c.sram.query_stack.bytes = stack_bytes;  // 3 slots of 6 entries, or thousands
      SimSetup one = one_setup(image, queries, cloud.size(), c, p), two = one;
      one.sim_threads = 1;
      two.sim_threads = 2;
      setups.insert(setups.end(), {one, two});
      names.push_back("k " + std::to_string(p.k) + ", query stack " + std::to_string(stack_bytes) + " bytes");
    }
  }
  const auto out = simulate(setups);
  for (std::size_t i = 0; i < names.size(); ++i) {
    const SimOutcome& a = out[2 * i];
    const SimOutcome& b = out[2 * i + 1];
    const SearchOutput golden = search(tree, queries, setups[2 * i].job.k == 1 ? mode(Mode::NN) : mode(Mode::KNN, 6));
    INFO(names[i]);
    REQUIRE(a.finished);
    REQUIRE(b.finished);
    CHECK(first_difference(golden.results, a.results).value_or("") == "");
    CHECK(first_difference(a.results, b.results).value_or("") == "");
    CHECK(a.cycles == b.cycles);
    CHECK(a.units == b.units);
    CHECK(a.buffers == b.buffers);
    CHECK(a.latency == b.latency);
    CHECK(a.visits.schedule == b.visits.schedule);
  }
  CHECK(out[0].cycles != out[2].cycles);  // the query stack's size matters
}

// No unit is busy and stalled for more cycles than the job has: under MQMN a Search Unit runs
// several batches at once and each cycle counts once, under the first state any batch is in
// (busy, then sram, result_writeback, issue_search stalls). For every unit kind, issue policy
// and search mode, exact and approximate, with a slow write-back so that every stall occurs
// (the accelerators side by side in one simulation: SystemC elaborates once per process).
TEST_CASE("every unit's busy and stall cycles fit in the job's cycles", "[hw][stats]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 3000, 5);
  const PointCloud queries = make_queries(cloud, 400, 5);
  const KdTree tree = build_kdtree(cloud, 6);
  const tlm_if::TreeImage image = tlm_if::encode_tree_image(tree);
  std::vector<SimSetup> setups;
  std::vector<std::string> labels;
  for (const auto policy : {"mqsn", "mqmn"})
    for (const SearchParams& params :
         {mode(Mode::NN), mode(Mode::KNN, 4), mode(Mode::Radius, 1, 1.5f), approximate(mode(Mode::NN), 0.6f),
          approximate(mode(Mode::Radius, 1, 1.5f), 0.6f)}) {
      setups.push_back(one_setup(image, queries, cloud.size(), units(4, 4, 8, 6), params));
      setups.back().config.be.issue_policy = policy;
      setups.back().config.sram.results.bytes = 4096;  // a small stream area drained slowly
      setups.back().config.dram.bytes_per_cycle = 0.5;
      labels.push_back(std::string(policy) + " " + to_string(params.mode) + (params.approximate ? " approx" : ""));
    }
  const std::vector<SimOutcome> outs = simulate(setups);
  std::uint64_t writeback_seen = 0;
  for (std::size_t i = 0; i < outs.size(); ++i) {
    const SimOutcome& out = outs[i];
    INFO(labels[i] << " " << out.error << out.deadlock);
    REQUIRE(out.finished);
    for (const char* kind : {"recursion_units", "search_units"})
      for (const nlohmann::json& u : out.units[kind]["per_unit"]) {
        std::uint64_t used = u["busy_cycles"].get<std::uint64_t>();
        for (const auto& [cause, n] : u["stall_cycles"].items()) used += n.get<std::uint64_t>();
        INFO(kind << ": " << u.dump());
        CHECK(used <= out.cycles);
        writeback_seen += u["stall_cycles"]["result_writeback"].get<std::uint64_t>();
      }
  }
  CHECK(writeback_seen > 0);  // the write-back really pushed back somewhere
}

// Every policy a build has registered, bit-exact against the golden model in every search mode,
// exact and approximate; a small Node Cache so that replacement policies evict. A new policy
// file is tested here without an edit.
TEST_CASE("every registered issue and replacement policy is bit-exact", "[hw][policies]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 2500, 31);
  const PointCloud queries = make_queries(cloud, 300, 31);
  const std::vector<std::pair<std::string, SearchParams>> modes = {{"nn", mode(Mode::NN)},
                                                                   {"knn4", mode(Mode::KNN, 4)},
                                                                   {"r1.2", mode(Mode::Radius, 1, 1.2f)},
                                                                   {"approx nn", approximate(mode(Mode::NN), 0.6f)}};
  std::vector<Case> cases;
  for (const auto& issue : hw::IssuePolicies::entries())
    for (const auto& replacement : hw::ReplacementPolicies::entries())
      for (const auto& [mname, p] : modes) {
        hw::AcceleratorConfig c = units(8, 4, 8, 5);
        c.be.issue_policy = issue.name;
        c.node_cache.policy = replacement.name;
        c.node_cache.bytes = 4096;  // a few Node Sets: evictions
        cases.push_back({issue.name + " " + replacement.name + " " + mname, c, p});
      }
  REQUIRE(cases.size() >= 2 * 2 * modes.size());
  const auto out = run_and_check(cloud, queries, cases);
  std::uint64_t evictions = 0;
  for (const SimOutcome& o : out) evictions += o.buffers["node_cache"]["evictions"].get<std::uint64_t>();
  CHECK(evictions > 0);
}

TEST_CASE("largest_first evicts the biggest Node Set, the least recently used among equals", "[hw][node_cache]") {
  hw::AcceleratorConfig c;
  c.node_cache.policy = "largest_first";
  const auto p = hw::make_replacement_policy(c);
  p->inserted(1, 640), p->inserted(2, 1280), p->inserted(3, 640), p->inserted(4, 1280);
  p->hit(2);
  CHECK(p->evict() == 4);  // 2 and 4 are the largest; 4 was used longer ago
  CHECK(p->evict() == 2);
  p->hit(1);
  CHECK(p->evict() == 3);  // equal sizes: 3 is older than the read of 1
  CHECK(p->evict() == 1);
  p->reset();
  p->inserted(9, 16);
  CHECK(p->evict() == 9);
}

// cache_first serves resident Node Sets first: on a workload whose queries revisit leaves, the
// Node Cache hits more often than under MQSN, with the same results.
TEST_CASE("cache_first raises the Node Cache's hit rate over mqsn, bit-exact", "[hw][policies]") {
  const SyntheticPair pair = make_synthetic_pair();
  PointCloud queries;
  for (std::size_t i = 0; i < pair.frame1.size(); i += 29) queries.push_back(pair.frame1[i]);
  std::vector<Case> cases;
  for (const char* issue : {"mqsn", "cache_first"}) {
    hw::AcceleratorConfig c = units(32, 8, 16, 10);
    c.be.issue_policy = issue;
    cases.push_back({issue, c, mode(Mode::Radius, 1, 0.5f)});
  }
  const auto out = run_and_check(pair.frame0, queries, cases);
  const auto rate = [](const SimOutcome& o) {
    const auto& nc = o.buffers["node_cache"];
    const double h = nc["hits"].get<double>(), m = nc["misses"].get<double>();
    return h / (h + m);
  };
  INFO("hit rate mqsn " << rate(out[0]) << ", cache_first " << rate(out[1]));
  CHECK(rate(out[1]) > rate(out[0]));
}
