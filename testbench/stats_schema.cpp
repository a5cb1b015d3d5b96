#include "stats_schema.hpp"

#include <algorithm>
#include <tuple>
#include <utility>

#include "config.hpp"
#include "config/key_table.hpp"
#include "hw/top.hpp"
#include "run_report.hpp"
#include "stat_formulas.hpp"

namespace tigris {

namespace {

using nlohmann::json;

struct Section {
  const char* id;
  const char* title;   // the heading of its table in docs/stats.md
  const char* prefix;  // the fields it holds, by path prefix ("" for the run's own)
};

const std::vector<Section>& sections() {
  static const std::vector<Section> table = {
      {"run", "The run and its inputs", ""},
      {"visits", "Visits: the accelerator's own counts", "visits"},
      {"units", "Units: busy and stall cycles", "units"},
      {"buffers", "Buffers: traffic and contention", "buffers"},
      {"energy", "Energy, power and area", "energy_pj power_w area_mm2"},
      {"latency", "Latency", "latency_cycles"},
      {"bottleneck", "Bottleneck", "bottleneck"},
      {"approx", "Approximate search", "leaders accuracy"},
      {"tree", "The tree", "tree"},
      {"config", "Configuration echo", "config"},
  };
  return table;
}

// The section of a path: the one whose prefix names its first component, else the run's.
std::string section_of(const std::string& path) {
  const std::string head = path.substr(0, path.find_first_of(".["));
  for (const Section& s : sections()) {
    const std::string p = std::string(" ") + s.prefix + " ";
    if (!head.empty() && p.find(" " + head + " ") != std::string::npos) return s.id;
  }
  return "run";
}

// The fields that are neither counters, derived nor configuration keys: what the run, the
// golden check, the observers and the energy and area models write.
struct Row {
  const char* path;
  const char* unit;
  const char* meaning;
};
// The run's own fields: what ran, on what, with which verdict.
const std::vector<Row>& run_fields() {
  static const std::vector<Row> table = {
      {"command", "text", "`run`"},
      {"command_line", "text", "the full command line as typed, so the run can be repeated"},
      {"commit", "text",
       "the source tree's commit the binary was built from (`-dirty`: with local changes; "
       "`unknown`: built without git)"},
      {"config_sha256", "text",
       "SHA-256 of `config` as JSON: the configuration's digest, also in the VCD's "
       "`$comment`, the `.gtkw` and the timeline's `otherData.run`"},
      {"inputs[].role", "text",
       "what the input is: `cloud` (the tree's points), `queries`, or `config` (the `--config` file)"},
      {"inputs[].path", "text", "the file's path as given (file inputs only)"},
      {"inputs[].bytes", "bytes", "the file's size (file inputs only)"},
      {"inputs[].sha256", "text", "SHA-256 of the file's contents, hex (file inputs only)"},
      {"inputs[].builtin", "text", "the built-in workload used instead of a file, e.g. `synthetic:frame0 (seed 1)`"},
      {"inputs[].same_as", "text", "`cloud`: the queries are the cloud itself (`--cloud` without `--queries`)"},
      {"workload.cloud", "text", "the tree cloud: its path, or the built-in frame's name"},
      {"workload.queries", "text", "the query set: its path, the built-in frame's name, or `FILE (the cloud itself)`"},
      {"workload.points", "count", "points in the tree cloud"},
      {"queries", "count", "queries searched"},
      {"cycles", "cycles",
       "the job's cycles, from START to the done interrupt (the last result record reached DRAM); with sampled "
       "simulation (`sampling.sampled`) the estimate, as are every unit, buffer and energy figure below"},
      {"cycles_ci95[]", "cycles",
       "95% confidence interval of `cycles` [low, high]: the estimate's, or [cycles, cycles] when every query was "
       "simulated"},
      {"sampling.requested", "text", "`sim.sampling` as set: `off`, `auto` or the share of queries to simulate"},
      {"sampling.sampled", "bool", "true when part of the queries were simulated and the rest estimated"},
      {"sampling.why", "text", "not sampled: why every query was simulated (off, approximate search, too short)"},
      {"sampling.queries", "count", "the job's queries"},
      {"sampling.simulated", "count", "queries simulated in detail"},
      {"sampling.checked", "count",
       "queries checked bit for bit against the golden model (every simulated one; the rest take its results)"},
      {"sampling.cycles_ci95[]", "cycles", "as `cycles_ci95`"},
      {"sampling.in_flight", "count",
       "queries the job holds in flight at most (its Query Stack / Result Buffer slots)"},
      {"sampling.fill", "count", "sampled: the job's first queries, simulated before the first window"},
      {"sampling.drain", "count", "sampled: the job's last queries, simulated after the last window"},
      {"sampling.windows", "count", "sampled: stretches of consecutive queries simulated between fill and drain"},
      {"sampling.warm_per_window", "count", "sampled: queries simulated before each window but the first"},
      {"sampling.measured_per_window", "count", "sampled: queries per window"},
      {"sampling.simulated_cycles", "cycles", "sampled: cycles of the simulated stream"},
      {"sampling.fill_cycles", "cycles", "sampled: the stream's cycles up to the first window's first admission"},
      {"sampling.drain_cycles", "cycles", "sampled: the stream's cycles from the drain's first admission to done"},
      {"sampling.segment_cycles_per_query[]", "cycles",
       "sampled: cycles per query of each segment of the stream (a window and the next one's warming)"},
      {"sampling.energy_pj_ci95[]", "pJ", "sampled: 95% confidence interval of `energy_pj.total`"},
      {"sampling.auxiliary", "text",
       "sampled: what the stream's cycles are scaled by to the job's: `queries`, or the golden model's "
       "`result_records`, `leaf_points` or `top_nodes` of the queries, whichever gives the narrowest interval"},
      {"sampling.relative_half_width", "fraction",
       "the cycles interval's half width over `cycles` (0 when every query was simulated)"},
      {"verdict", "text", "`match` (every query's results and visit counts equal the golden model's) or `mismatch`"},
      {"mismatches.results", "count", "queries whose results differ from the golden model's"},
      {"mismatches.visits", "count", "queries whose visit counts differ from the golden model's"},
      {"mismatches.first[]", "text",
       "descriptions of the first (at most five) mismatching queries, both answers shown"},
      {"wall_seconds.golden", "s", "host time of the golden model's exact search of the same queries"},
      {"wall_seconds.simulation", "s",
       "host time of the simulation, SystemC elaboration to the last result, statistics included"},
      {"visits.top", "count", "top-tree nodes visited (one `dist2` each) by the Recursion Units"},
      {"visits.pruned", "count", "popped far children pruned (`plane2 > bound`)"},
      {"visits.leaf_points", "count", "leaf-set points scanned by the PEs (exact scans)"},
      {"visits.follower_points", "count", "leader-list entries scanned by followers (approximate search; else 0)"},
      {"visits.leader_checks", "count", "query-to-leader distances of the Leader Check (approximate search; else 0)"},
      {"visits.leaf_visits", "count", "non-empty leaf visits (rows of the schedule)"},
      {"visits.per_query.*.mean", "count",
       "mean over queries of that per-query count: `top`, `pruned`, `leaf_points`, `follower_points`, `leader_checks`, "
       "`leaf_visits`, and `nodes` = top + leaf points + follower points + leader checks (every distance a query "
       "costs)"},
      {"visits.per_query.*.p50", "count", "median (nearest-rank) of that per-query count"},
      {"visits.per_query.*.p99", "count", "99th percentile (nearest-rank) of that per-query count"},
      {"visits.per_query.*.max", "count", "largest per-query value"},
      {"units.recursion_units.count", "count", "Recursion Units (`fe.recursion_units`)"},
      {"units.search_units.count", "count", "Search Units (`be.search_units`)"},
      {"units.search_units.pes_per_su", "count", "PEs per Search Unit"},
      {"units.search_units.issue_policy", "text", "the Search Units' issue policy (`be.issue_policy`)"},
      {"buffers.node_cache.policy", "text", "the Node Cache's replacement policy (`node_cache.policy`)"},
  };
  return table;
}

// Energy by component and by unit, area by block.
const std::vector<Row>& energy_area_fields() {
  static const std::vector<Row> table = {
      {"energy_pj.pe", "pJ", "PE distance computations (Node Set and list scans) and Leader Check distances"},
      {"energy_pj.ru", "pJ", "RU node operations, and reads of replicated top levels (`fe.top_levels_replicated`)"},
      {"energy_pj.sram_read", "pJ", "reads of the Point, Query, Query Stack and Result Buffers"},
      {"energy_pj.sram_write", "pJ", "writes of those buffers"},
      {"energy_pj.node_cache", "pJ", "Node Cache reads and fills"},
      {"energy_pj.leader_buffer", "pJ", "Leader Buffer reads and writes"},
      {"energy_pj.dram", "pJ", "DRAM bytes: result write-back, leader lists kept in DRAM"},
      {"energy_pj.leakage", "pJ", "`leakage_pj_per_mm2_cycle` x `area_mm2.total` x cycles"},
      {"energy_pj.total", "pJ", "the sum of the components above"},
      {"energy_pj.by_unit.search_units", "pJ", "the total spent by the Search Units' PEs (lines `pe.*`)"},
      {"energy_pj.by_unit.recursion_units", "pJ", "spent by the Recursion Units (lines `ru.*`)"},
      {"energy_pj.by_unit.points", "pJ", "Point Buffer reads and writes"},
      {"energy_pj.by_unit.queries", "pJ", "Query Buffer reads and writes"},
      {"energy_pj.by_unit.query_stack", "pJ", "Query Stack Buffer reads and writes"},
      {"energy_pj.by_unit.results", "pJ", "Result Buffer reads and writes"},
      {"energy_pj.by_unit.node_cache", "pJ", "Node Cache"},
      {"energy_pj.by_unit.leader_buffer", "pJ", "Leader Buffer"},
      {"energy_pj.by_unit.dram", "pJ", "DRAM"},
      {"energy_pj.by_unit.leakage", "pJ", "leakage (as `energy_pj.leakage`)"},
      {"area_mm2.sram", "mm2", "all on-chip storage (the blocks under `by_block.sram`)"},
      {"area_mm2.logic", "mm2", "RUs, PEs and issue logic"},
      {"area_mm2.total", "mm2", "sram + logic"},
      {"area_mm2.by_block.sram.points", "mm2", "Point Buffer"},
      {"area_mm2.by_block.sram.queries", "mm2", "Query Buffer"},
      {"area_mm2.by_block.sram.query_stack", "mm2", "Query Stack Buffer"},
      {"area_mm2.by_block.sram.results", "mm2", "Result Buffer"},
      {"area_mm2.by_block.sram.fqq", "mm2", "FE Query Queue (one bank)"},
      {"area_mm2.by_block.sram.bqb", "mm2", "all SUs' BE Query Buffers (`be.bqb_entries` x `be.bqb_entry_bytes` each)"},
      {"area_mm2.by_block.sram.node_cache", "mm2", "Node Cache (one bank per SU; 0 when `node_cache.bytes` is 0)"},
      {"area_mm2.by_block.sram.leader_buffer", "mm2",
       "Leader Buffer (2^top height x `leader.capacity_per_leaf` x 12 bytes; 0 for the canonical tree)"},
      {"area_mm2.by_block.sram.top_level_replicas", "mm2",
       "every RU's registers for `fe.top_levels_replicated` levels (0 by default)"},
      {"area_mm2.by_block.logic.recursion_units", "mm2", "RUs x `area.ru_mm2`"},
      {"area_mm2.by_block.logic.pes", "mm2", "SUs x PEs per SU x `area.pe_mm2`"},
      {"area_mm2.by_block.logic.issue_logic", "mm2", "SUs x `area.issue_logic_mm2`"},
  };
  return table;
}

// Query latency, BQB waits and what bounded the run.
const std::vector<Row>& latency_bottleneck_fields() {
  static const std::vector<Row> table = {
      {"latency_cycles.query.count", "count", "queries measured (all; sampled simulation: the simulated ones)"},
      {"latency_cycles.query.mean", "cycles",
       "mean query latency: from admission (a Query Stack slot taken) to its last results entering the write-back "
       "stream"},
      {"latency_cycles.query.p50", "cycles", "median query latency"},
      {"latency_cycles.query.p99", "cycles", "99th percentile query latency"},
      {"latency_cycles.query.max", "cycles", "longest query latency"},
      {"latency_cycles.bqb_wait.count", "count", "leaf visits measured"},
      {"latency_cycles.bqb_wait.mean", "cycles",
       "mean wait of a leaf visit from its arrival in a BE Query Buffer to the start of its batch"},
      {"latency_cycles.bqb_wait.p50", "cycles", "median BQB wait"},
      {"latency_cycles.bqb_wait.p99", "cycles", "99th percentile BQB wait"},
      {"latency_cycles.bqb_wait.max", "cycles", "longest BQB wait"},
      {"bottleneck.bound", "text", "`front-end`, `back-end` or `result write-back`"},
      {"bottleneck.unit", "text", "the bounding unit kind: `recursion_units` or `search_units`"},
      {"bottleneck.occupancy", "fraction",
       "the share of that kind's unit-cycles busy or stalled on its own (busy_cycles + stall cycles; "
       "`pi_rs_dependency` not added again; `bqb_full` and `result_writeback` waits on other blocks left out)"},
      {"bottleneck.cause", "text",
       "the largest part of that occupancy: `busy` or one of its own stall causes (`sram stall`, `issue_search stall`, "
       "...; `result_writeback stall` when write-back bound)"},
      {"bottleneck.share", "fraction", "that part's share of the kind's unit-cycles"},
      {"bottleneck.runner_up.unit", "text", "the other unit kind"},
      {"bottleneck.runner_up.occupancy", "fraction", "its occupancy"},
      {"bottleneck.runner_up.cause", "text", "the largest part of its occupancy"},
      {"bottleneck.runner_up.share", "fraction", "that part's share"},
      {"bottleneck.cycles_over_lower_bound", "ratio", "cycles / `lower_bound_cycles`"},
      {"bottleneck.sram_hot_spot.buffer", "text",
       "when the bounding kind's `sram stall` is 10% of its cycles or more: "
       "the buffer it waits for (the most `conflict_cycles` among the kind's buffers: `points`, `queries`, "
       "`query_stack`, `results`)"},
      {"bottleneck.sram_hot_spot.title", "text", "that buffer's name in the paper, e.g. `Point Buffer`"},
      {"bottleneck.sram_hot_spot.conflict_cycles", "cycles", "its `conflict_cycles`"},
      {"bottleneck.sram_hot_spot.banks", "count", "its banks"},
      {"bottleneck.sram_hot_spot.hottest_banks[].bank", "index",
       "a bank with at least twice a fair share of the "
       "buffer's conflict cycles (at most three, hottest first; no `hottest_banks` when none has)"},
      {"bottleneck.sram_hot_spot.hottest_banks[].conflict_cycles", "cycles", "its `banks.conflict_cycles` entry"},
      {"bottleneck.sram_hot_spot.hottest_banks[].share", "fraction", "its share of the buffer's conflict cycles"},
      {"bottleneck.sram_hot_spot.hottest_banks[].holds", "text",
       "Point Buffer: what most walks read there: its "
       "first top-tree node below `fe.top_levels_replicated` (`the top tree's root`, `the top tree's level L, "
       "node N`) or `leaf sets`"},
      {"bottleneck.summary", "text",
       "the printed line, e.g. `front-end (RU) bound: RUs 94% occupied: sram stall 49%, busy 45%; "
       "waiting on other blocks 1%: bqb_full stall 1%; ...`"},
  };
  return table;
}

// Leader decisions, approximate search's accuracy and the tree's shape.
const std::vector<Row>& search_outcome_fields() {
  static const std::vector<Row> table = {
      {"leaders.leaders", "count", "exact scans that joined the Leader Buffer"},
      {"leaders.followers", "count", "follower visits"},
      {"leaders.leader_buffer_full", "count", "exact scans that found their leaf's leaders full"},
      {"accuracy.queries", "count", "queries compared"},
      {"accuracy.exact_matches", "count", "queries whose results equal exact search's (index and `dist2`)"},
      {"accuracy.exact_match_fraction", "fraction", "exact_matches / queries"},
      {"accuracy.mean_extra_distance_m", "m", "NN/kNN: mean over neighbour ranks of sqrt(dist2) - sqrt(exact dist2)"},
      {"accuracy.max_extra_distance_m", "m", "NN/kNN: the largest such difference"},
      {"accuracy.missing_neighbors", "count", "NN/kNN: ranks the exact list holds and the approximate one does not"},
      {"accuracy.recall", "fraction", "radius: true hits / exact hits, pooled over queries"},
      {"accuracy.precision", "fraction", "radius: true hits / returned hits"},
      {"accuracy.exact_hits", "count", "radius: hits of exact search"},
      {"accuracy.returned_hits", "count", "radius: hits returned by approximate search"},
      {"tree.points", "count", "points in the tree"},
      {"tree.top_height", "count", "top-tree height h (levels)"},
      {"tree.full_height", "count", "ceil(log2(n + 1)): the canonical tree's height"},
      {"tree.split_axis", "text", "`widest` or `round-robin`"},
      {"tree.top_nodes", "count", "2^h - 1"},
      {"tree.leaves", "count", "2^h leaf sets (0 for the canonical tree)"},
      {"tree.nonempty_leaves", "count", "leaf sets holding points"},
      {"tree.leaf_set_mean", "ratio", "mean points per non-empty leaf set"},
      {"tree.leaf_set_max", "count", "largest leaf set"},
  };
  return table;
}

// What the run measured beyond the statistics tree: energy, area, latency, the bound, the tree.
const std::vector<Row>& measured_fields() {
  static const std::vector<Row> table = [] {
    std::vector<Row> all;
    for (const auto* part : {&energy_area_fields(), &latency_bottleneck_fields(), &search_outcome_fields()})
      all.insert(all.end(), part->begin(), part->end());
    return all;
  }();
  return table;
}

// The search and approximation settings of the run, beside the accelerator's keys in `config`.
const std::vector<Row>& search_config_fields() {
  static const std::vector<Row> table = {
      {"config.search.mode", "text", "`nn`, `knn` or `radius`"},
      {"config.search.k", "count", "neighbours per query (1 for NN)"},
      {"config.search.radius", "m", "radius search only: the radius"},
      {"config.search.max_nn", "count", "radius search only: hits kept per query (0: all)"},
      {"config.approx.enabled", "bool", "approximate (leader/follower) search on"},
      {"config.approx.thd", "m", "approximate search only: the leader threshold"},
      {"config.approx.leader_result_width", "count",
       "approximate search only: the leader result width R in effect (`--leader-width`, 0 meaning k; used by nn and "
       "knn)"},
  };
  return table;
}

// Sorting key within a section: units and buffers by block (in placement order), then the
// block's own fields, its counters, its derived fields, its per-unit counters.
enum Origin { kOther, kCounter, kDerived, kPerUnit };
struct Keyed {
  StatField f;
  std::size_t section, block;
  int origin;
  std::size_t order;
};

std::string counter_meaning(const hw::Counter& c, std::size_t groups) {
  if (groups < 2) return c.description();
  return c.description() +
         (c.merge() == hw::Counter::Merge::Max ? "; the largest of any unit" : "; summed over the units");
}

}  // namespace

std::vector<StatField> stats_schema() {
  std::vector<Keyed> rows;
  std::vector<std::string> blocks;  // placement paths, in order
  const auto block_of = [&](const std::string& path) {
    std::size_t best = blocks.size(), len = 0;
    for (std::size_t i = 0; i < blocks.size(); ++i)
      if (path.compare(0, blocks[i].size(), blocks[i]) == 0 && blocks[i].size() > len &&
          (path.size() == blocks[i].size() || path[blocks[i].size()] == '.'))
        best = i, len = blocks[i].size();
    return best;
  };
  const auto section_index = [](const std::string& id) {
    for (std::size_t i = 0; i < sections().size(); ++i)
      if (id == sections()[i].id) return i;
    return sections().size();
  };
  const auto add = [&](std::string path, std::string unit, std::string meaning, std::string formula, int origin) {
    StatField f{section_of(path), path, std::move(unit), std::move(meaning), std::move(formula)};
    const std::size_t s = section_index(f.section);
    rows.push_back({std::move(f), s, 0, origin, rows.size()});
  };

  // The counters, where run_stats_json puts them, from an accelerator of the default
  // configuration (every group exists in any configuration).
  const hw::TigrisAccelerator accel("stats_schema", hw::AcceleratorConfig{});
  for (const Placement& p : placements()) {
    const auto groups = accel.stats().find(p.kind);
    if (groups.empty()) continue;
    const bool by_name = std::string(p.path).find("{name}") != std::string::npos;
    for (const hw::StatGroup* g : groups) {
      const std::string at = placed_at(p, *g);
      if (std::find(blocks.begin(), blocks.end(), at) == blocks.end()) blocks.push_back(at);
      const std::string title = g->description().empty() ? "" : g->description() + ": ";
      for (const hw::Counter* c : g->counters()) {
        add(at + "." + c->name(), c->unit(), title + counter_meaning(*c, by_name ? 1 : groups.size()), "", kCounter);
        if (p.per_unit)
          add(at + ".per_unit[]." + c->name(), c->unit(), "per unit, in id order: " + c->description(), "", kPerUnit);
      }
      for (const hw::CounterArray* a : g->arrays())
        add(at + "." + a->name() + "[]", a->unit(),
            title + a->description() + (by_name ? "" : "; summed over the units"), "", kCounter);
      if (!by_name) break;  // the groups of a kind share their counters
    }
  }
  for (const std::vector<Row>* table : {&run_fields(), &measured_fields(), &search_config_fields()})
    for (const Row& r : *table) add(r.path, r.unit, r.meaning, "", kOther);
  for (const DerivedStat& d : derived_stats()) add(d.path, d.unit, d.meaning, d.formula, kDerived);
  for (const config::Key& k : config::keys<hw::AcceleratorConfig>()) {
    std::string unit = k.spec.unit;
    if (unit == "-") unit = k.type == config::Type::Bool ? "bool" : k.type == config::Type::Enum ? "text" : "number";
    add("config." + k.name, unit, k.spec.doc, "", kOther);
  }
  for (Keyed& k : rows) k.block = block_of(k.f.path);
  std::stable_sort(rows.begin(), rows.end(), [](const Keyed& a, const Keyed& b) {
    return std::make_tuple(a.section, a.block, a.origin, a.order) <
           std::make_tuple(b.section, b.block, b.origin, b.order);
  });
  std::vector<StatField> out;
  for (Keyed& k : rows) out.push_back(std::move(k.f));
  return out;
}

json stats_schema_json() {
  json secs = json::array();
  for (const Section& s : sections()) secs.push_back({{"id", s.id}, {"title", s.title}});
  json fields = json::array();
  for (const StatField& f : stats_schema()) {
    json j = {{"section", f.section}, {"path", f.path}, {"unit", f.unit}, {"meaning", f.meaning}};
    if (!f.formula.empty()) j["formula"] = f.formula;
    fields.push_back(j);
  }
  return {{"sections", secs}, {"fields", fields}};
}

}  // namespace tigris
