#include "report.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <unistd.h>

#include "sw_ref/accuracy.hpp"
#include "sw_ref/stats.hpp"

namespace tigris {

namespace {

nlohmann::json dist_json(const Distribution& d) {
  return {{"mean", d.mean}, {"p50", d.p50}, {"p99", d.p99}, {"max", d.max}};
}

nlohmann::json per_query(std::vector<std::uint64_t> values) { return dist_json(distribution(std::move(values))); }

}  // namespace

nlohmann::json visits_json(const SearchOutput& out) {
  nlohmann::json j = visits_json<nlohmann::json>(out.visits);
  // Per counter, its distribution over the queries; "nodes": distance computations of any kind,
  // what a search unit or recursion unit pays for.
  std::vector<std::vector<std::uint64_t>> columns;
  std::vector<std::uint64_t> nodes;
  nodes.reserve(out.per_query.size());
  for (const QueryVisits& q : out.per_query) {
    std::size_t c = 0;
    for_each_count(q, [&](const char*, std::uint32_t x) {
      if (c == columns.size()) columns.emplace_back().reserve(out.per_query.size());
      columns[c++].push_back(x);
    });
    nodes.push_back(std::uint64_t{q.top} + q.leaf_points + q.follower_points + q.leader_checks);
  }
  nlohmann::json& pq = j["per_query"] = nlohmann::json::object();
  std::size_t c = 0;
  for_each_count(QueryVisits{}, [&](const char* name, std::uint32_t) {
    pq[name] = per_query(c < columns.size() ? std::move(columns[c]) : std::vector<std::uint64_t>{});
    ++c;
  });
  pq["nodes"] = per_query(std::move(nodes));
  return j;
}

nlohmann::json leaders_json(const SearchOutput& out) {
  return {{"leaders", out.leaders.leaders},
          {"followers", out.leaders.followers},
          {"leader_buffer_full", out.leaders.leader_buffer_full}};
}

nlohmann::json accuracy_json(const Accuracy& a) {
  nlohmann::json j = {
      {"queries", a.queries}, {"exact_matches", a.exact_matches}, {"exact_match_fraction", a.exact_match_fraction()}};
  if (a.mode != Mode::Radius) {
    j["mean_extra_distance_m"] = a.mean_extra_m;
    j["max_extra_distance_m"] = a.max_extra_m;
    j["missing_neighbors"] = a.missing;
  } else {
    j["recall"] = a.recall();
    j["precision"] = a.precision();
    j["exact_hits"] = a.exact_hits;
    j["returned_hits"] = a.returned_hits;
  }
  return j;
}

nlohmann::json tree_json(const KdTree& t) {
  std::uint32_t nonempty = 0, largest = 0;
  for (std::uint32_t j = 0; j < t.num_leaves(); ++j) {
    nonempty += t.leaf_size(j) > 0;
    largest = std::max(largest, t.leaf_size(j));
  }
  return {{"points", t.num_points},
          {"top_height", t.top_height},
          {"full_height", t.full_height},
          {"split_axis", to_string(t.split)},
          {"top_nodes", t.top.size()},
          {"leaves", t.num_leaves()},
          {"nonempty_leaves", nonempty},
          {"leaf_set_mean", nonempty ? static_cast<double>(t.leaf_index.size()) / nonempty : 0.0},
          {"leaf_set_max", largest}};
}

nlohmann::json search_config_json(const SearchParams& p, const KdTree& tree) {
  nlohmann::json j;
  j["tree"] = {{"top_height", tree.top_height}, {"split_axis", to_string(tree.split)}};
  j["search"] = {{"mode", to_string(p.mode)}, {"k", p.effective_k()}};
  if (p.mode == Mode::Radius) {
    j["search"]["radius"] = p.radius;
    j["search"]["max_nn"] = p.max_nn;
  }
  j["approx"] = {{"enabled", p.approximate}};
  if (p.approximate) {
    j["approx"]["thd"] = p.approx_thd;
    j["approx"]["leader_result_width"] = p.effective_leader_width();
    j["leader"] = {{"capacity_per_leaf", p.leader_capacity}};
  }
  return j;
}

std::string non_finite_field(const nlohmann::json& j, const std::string& prefix) {
  if (j.is_number_float() && !std::isfinite(j.get<double>())) return prefix.empty() ? "(value)" : prefix;
  if (j.is_object())
    for (const auto& [k, v] : j.items())
      if (std::string f = non_finite_field(v, prefix.empty() ? k : prefix + "." + k); !f.empty()) return f;
  if (j.is_array())
    for (std::size_t i = 0; i < j.size(); ++i)
      if (std::string f = non_finite_field(j[i], prefix + "[" + std::to_string(i) + "]"); !f.empty()) return f;
  return "";
}

}  // namespace tigris
