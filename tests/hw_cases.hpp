// Accelerator test cases simulated side by side and checked against the golden model (shared
// by the hardware test files; SystemC elaborates once per process, so a test case simulates all
// the configurations it compares in one run).
#pragma once

#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "sw_ref/search.hpp"
#include "testbench/scoreboard.hpp"
#include "testbench/simulation.hpp"

namespace tigris::test {

struct Case {
  std::string name;
  hw::AcceleratorConfig config;
  SearchParams params;
  const PointCloud* cloud = nullptr;  // this case's own workload, when not the shared one
  const PointCloud* queries = nullptr;
  std::vector<hw::JobObserver*> observers = {};  // attached to this case's job
};

// Simulates every case on (cloud, queries) in one run; checks each against the golden model.
inline std::vector<SimOutcome> run_and_check(const PointCloud& shared_cloud, const PointCloud& shared_queries,
                                             const std::vector<Case>& cases) {
  std::vector<KdTree> trees;
  std::vector<tlm_if::TreeImage> images;
  trees.reserve(cases.size());
  images.reserve(cases.size());
  std::vector<SimSetup> setups;
  for (const Case& c : cases) {
    const PointCloud& cloud = c.cloud ? *c.cloud : shared_cloud;
    const PointCloud& queries = c.queries ? *c.queries : shared_queries;
    trees.push_back(build_kdtree(cloud, c.config.tree.top_height));
    images.push_back(tlm_if::encode_tree_image(trees.back()));
    SimSetup s;
    s.config = c.config;
    s.image = &images.back();
    s.queries = &queries;
    s.num_points = static_cast<std::uint32_t>(cloud.size());
    s.job = host_job(c.params);
    s.observers = c.observers;
    setups.push_back(s);
  }
  std::vector<SimOutcome> out = simulate(setups);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    INFO("case " << cases[i].name << ": " << out[i].error << out[i].deadlock);
    const PointCloud& queries = cases[i].queries ? *cases[i].queries : shared_queries;
    REQUIRE(out[i].error.empty());
    REQUIRE(out[i].deadlock.empty());
    REQUIRE(out[i].finished);
    SearchParams p = cases[i].params;
    p.leader_capacity = cases[i].config.leader.capacity_per_leaf;  // the hardware's, as tigris run does
    const SearchOutput golden = search(trees[i], queries, p);
    const Verdict v = check_against_golden(trees[i], queries, p, golden, out[i].results, out[i].visits);
    if (!v.match) FAIL(cases[i].name << ": " << v.first.front());
  }
  return out;
}

// `p` as approximate search with threshold `thd` (metres).
inline SearchParams approximate(SearchParams p, float thd) {
  p.approximate = true;
  p.approx_thd = thd;
  return p;
}

// One accelerator's setup: `image` of a cloud of `points`, searched by `queries` as `params`.
inline SimSetup one_setup(const tlm_if::TreeImage& image, const PointCloud& queries, std::size_t points,
                          const hw::AcceleratorConfig& config, const SearchParams& params) {
  SimSetup s;
  s.config = config;
  s.image = &image;
  s.queries = &queries;
  s.num_points = static_cast<std::uint32_t>(points);
  s.job = host_job(params);
  return s;
}

inline SearchParams mode(Mode m, int k = 1, float r = 0.0f, std::uint32_t max_nn = 0) {
  SearchParams p;
  p.mode = m, p.k = k, p.radius = r, p.max_nn = max_nn;
  return p;
}

inline hw::AcceleratorConfig units(int ru, int su, int pe, int height) {
  hw::AcceleratorConfig c;
  c.fe.recursion_units = ru, c.be.search_units = su, c.be.pes_per_su = pe;
  c.tree.top_height = height;
  return c;
}

}  // namespace tigris::test
