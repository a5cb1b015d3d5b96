// Pieces of the stats JSON (docs/stats.md, docs/cli.md) and output files shared by the commands.
#pragma once

#include <functional>
#include <iosfwd>
#include <string>

#include <nlohmann/json.hpp>

#include "core/out_folder.hpp"  // write_file
#include "sw_ref/accuracy.hpp"
#include "sw_ref/kdtree.hpp"
#include "sw_ref/search.hpp"

namespace tigris {

// `visits`: totals and the per-query distribution (mean, p50, p99, max) of each count.
nlohmann::json visits_json(const SearchOutput& out);
// `leaders`: leader/follower decisions of the approximate search.
nlohmann::json leaders_json(const SearchOutput& out);
// `accuracy`: approximate against exact search of the same queries.
nlohmann::json accuracy_json(const Accuracy& a);
// The tree's shape: heights, leaves, leaf-set sizes.
nlohmann::json tree_json(const KdTree& tree);
// The search parameters as configuration keys.
nlohmann::json search_config_json(const SearchParams& p, const KdTree& tree);

// The dotted path of the first number in `j` that is NaN or infinite ("" when none): JSON has
// no such numbers (they would be written as null), so a run that computes one is an error.
std::string non_finite_field(const nlohmann::json& j, const std::string& prefix = "");

}  // namespace tigris
