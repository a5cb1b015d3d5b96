// The flags `tigris ref` and `tigris run` share (docs/cli.md), and their translation
// into validated golden-model parameters.
#pragma once

#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

#include <nlohmann/json.hpp>

#include "core/flag_values.hpp"  // parse_height
#include "sw_ref/kdtree.hpp"
#include "sw_ref/search.hpp"
#include "sw_ref/work_guard.hpp"

namespace tigris {

struct SearchOptions {
  std::string cloud, queries;
  std::uint64_t seed = 1;
  std::string mode = "nn";
  int k = 10;
  double radius = 0.30;  // checked against float's range in search_params
  std::uint32_t max_nn = 0;
  std::string height = "10";
  std::string split_axis = "widest";
  std::string approx_thd;  // empty: exact search; a number in metres, or "default"
  std::string leader_scope = "first_leaf";
  std::string leader_in_flight = "wait";
  int leader_capacity = 16;
  int leader_width = 0;
  std::string dump_results, dump_schedule, schedule;
  bool redundancy = false;  // ref: the two-stage tree's redundancy under both conventions
  std::string out = "tigris-out";
  WorkLimits limits;
  std::string command_line;  // as typed, for stats.json (set by main)
};

// `replay`: also --schedule (the golden model replays a schedule; the accelerator makes its own)
// and --redundancy (tigris ref only).
void add_search_options(CLI::App& app, SearchOptions& o, bool replay = false);

// A flag naming a file the command writes (OUTPUT in --help, "role": "output" in --list-flags;
// the output core claims it) or reads (FILE, "role": "input"). --out is "out_folder".
CLI::Option* output_flag(CLI::Option* option);
CLI::Option* input_flag(CLI::Option* option);

// --config as a CLI11 transform (testbench/presets.hpp's config_path), so the flag's value is
// the file from the start: manifests, input checks and the reader all see the path.
CLI::Validator preset_or_file();

// Checks the flag combination (e.g. --k only with knn) and builds the parameters; throws
// std::invalid_argument naming the flag. `scope`, `in_flight`: the leader scope and in-flight
// policy when their flags are not given (run: from the configuration's leader block).
SearchParams search_params(const CLI::App& app, const SearchOptions& o, LeaderScope scope = LeaderScope::FirstLeaf,
                           LeaderInFlight in_flight = LeaderInFlight::Wait);

// A note on stderr when a kNN search asks for more neighbours than the cloud has.
void note_k_above_cloud(const char* command, const SearchParams& p, std::size_t points, const std::string& cloud_name);

// A command's flags for tools (`tigris COMMAND --list-flags`): {"command", "flags": [{"flag"
// (without dashes), "takes_value", "type" (CLI11's: INT, FLOAT, TEXT, ...; "" for a switch),
// "default" (as its --help shows it, "" when none), "doc"}]}, so no tool scrapes --help.
nlohmann::json flags_json(const CLI::App& command);

// The default top height (10) for a cloud of `points`: clamped to the cloud's full height, with
// a note on stderr, when nobody asked for it (`chosen` false); an explicit height is kept as is
// (and a too large one stays an error naming the full height).
int default_height_for(int height, bool chosen, std::size_t points, const std::string& cloud_name);

}  // namespace tigris
