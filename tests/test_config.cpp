// The JSON configuration and --set (testbench/config.*): round trips, the paper file, and one
// test per kind of error, each checking that the message names its source and key.
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "hw/job.hpp"
#include "testbench/config.hpp"

using nlohmann::json;
using tigris::hw::AcceleratorConfig;
namespace fs = std::filesystem;

namespace {

// The names a policy key accepts, as error messages list them: every registered policy, so a
// new policy file changes no test here.
template <class Registry>
std::string registered() {
  std::string s;
  for (const auto& e : Registry::entries()) s += (s.empty() ? "`" : ", `") + e.name + "`";
  return s;
}
// Asked when a test runs: the policies register during start-up, in no set order with this file.
std::string issue_names() { return registered<tigris::hw::IssuePolicies>(); }
std::string replacement_names() { return registered<tigris::hw::ReplacementPolicies>(); }

// The message of the std::invalid_argument f throws; fails the test when it throws nothing.
std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  FAIL("no std::invalid_argument thrown");
  return {};
}

void flatten(const json& j, const std::string& prefix, std::map<std::string, json>& out) {
  for (const auto& [name, v] : j.items()) {
    const std::string path = prefix.empty() ? name : prefix + "." + name;
    if (v.is_object())
      flatten(v, path, out);
    else
      out[path] = v;
  }
}

std::map<std::string, json> flat(const json& j) {
  std::map<std::string, json> out;
  flatten(j, "", out);
  return out;
}

bool same(const AcceleratorConfig& a, const AcceleratorConfig& b) {
  return tigris::config_to_json(a) == tigris::config_to_json(b);
}

// A file in the temp folder, unique per process (ctest runs test cases in parallel processes).
struct TempFile {
  fs::path path;
  TempFile(const std::string& name, const std::string& text)
      : path(fs::temp_directory_path() / ("tigris_cfg_" + std::to_string(::getpid()) + "_" + name)) {
    std::ofstream(path) << text;
  }
  ~TempFile() { fs::remove(path); }
};

std::string paper_json() { return (fs::path(TIGRIS_TESTS_DIR).parent_path() / "presets" / "paper.json").string(); }

AcceleratorConfig applied(const json& j) {
  AcceleratorConfig cfg;
  tigris::apply_config_json(cfg, j, "test.json");
  return cfg;
}

}  // namespace

TEST_CASE("config: every key is a scalar of config_to_json and the defaults round-trip", "[config]") {
  const AcceleratorConfig defaults;
  const json j = tigris::config_to_json(defaults);
  const auto keys = tigris::config_keys();
  std::set<std::string> from_json;
  for (const auto& [k, v] : flat(j)) from_json.insert(k);
  CHECK(from_json == std::set<std::string>(keys.begin(), keys.end()));
  CHECK(from_json.size() == keys.size());
  CHECK(j["tree"]["top_height"] == 10);
  CHECK(j["sram"]["points"]["bytes"] == 2097152u);

  AcceleratorConfig other;
  tigris::apply_setting(other, "fe.recursion_units=7");
  tigris::apply_setting(other, "sram.results.banks=3");
  REQUIRE_FALSE(same(other, defaults));
  tigris::apply_config_json(other, j, "defaults");
  CHECK(same(other, defaults));
  CHECK_NOTHROW(tigris::validate_config(defaults));
}

TEST_CASE("config: every key maps to its own field", "[config]") {
  // Give every key a distinct non-default value; two keys sharing a field would lose one.
  json changed = tigris::config_to_json(AcceleratorConfig{});
  int i = 0;
  for (const auto& key : tigris::config_keys()) {
    std::string p = "/" + key;
    for (auto& c : p)
      if (c == '.') c = '/';
    json& v = changed[json::json_pointer(p)];
    ++i;
    if (v.is_boolean())
      v = !v.get<bool>();
    else if (v.is_number_unsigned())
      v = v.get<std::uint64_t>() * 2 + 64 * static_cast<unsigned>(i);
    else if (v.is_number_integer())
      v = key == "tree.top_height" ? 12 : key == "fe.top_levels_replicated" ? 3 : v.get<int>() + i;
    else if (v.is_number_float())
      v = key == "result_buffer.slot_fraction"     ? 0.25
          : key == "result_buffer.leader_fraction" ? 0.125
          : key == "stall.rate"                    ? 0.375
          : key == "energy.sram_size_exponent"     ? 1.5
                                                   : v.get<double>() * 2 + 0.25 * i;
    else if (v == "widest")
      v = "round-robin";
    else if (v == "mqsn")
      v = "mqmn";
    else if (v == "lru")
      v = "fifo";
    else if (v == "first_leaf")
      v = "every_leaf";
    else if (v == "wait")
      v = "finished_only";
    else if (v == "channel")
      v = "off_critical_path";
    else if (v == "spill")
      v = "resident";
    else if (v == "off")
      v = 0.5;
    else if (v == "tlm" && tigris::hw::RecursionUnitModels::find("rtl"))
      v = "rtl";
    else if (v == "tlm")
      continue;  // a build without the RTL RU has one value only
    else
      FAIL("no change for " << key);
  }
  const AcceleratorConfig cfg = applied(changed);
  CHECK(tigris::config_to_json(cfg) == changed);
  CHECK(cfg.fe.forwarding == false);
  CHECK(cfg.be.issue_policy == std::string("mqmn"));
  CHECK(cfg.node_cache.policy == std::string("fifo"));
  CHECK(cfg.tree.split_axis == tigris::SplitRule::RoundRobin);
  CHECK(cfg.leader.scope == tigris::LeaderScope::EveryLeaf);
  CHECK(cfg.leader.in_flight == tigris::LeaderInFlight::FinishedOnly);
  CHECK(cfg.dram.writeback == tigris::hw::Writeback::OffCriticalPath);
  CHECK(cfg.result_buffer.leader_lists == tigris::hw::LeaderLists::Resident);
  CHECK_FALSE(cfg.energy.charge_result_dram);
  AcceleratorConfig valid = cfg;
  valid.fe.recursion_unit_model = "tlm";  // the RTL RU refuses the changed cost.ru_* (tested below)
  CHECK_NOTHROW(tigris::validate_config(valid));
  if (cfg.fe.recursion_unit_model == "rtl")
    CHECK_THROWS_WITH(tigris::validate_config(cfg), Catch::Contains("'fe.recursion_unit_model' 'rtl' needs"));
  AcceleratorConfig again;
  tigris::apply_config_json(again, tigris::config_to_json(cfg), "echo");
  CHECK(same(again, cfg));
}

TEST_CASE("config: paper.json writes out every hardware key and loads to exactly the defaults", "[config]") {
  AcceleratorConfig cfg;
  tigris::apply_setting(cfg, "be.issue_policy=mqmn");
  tigris::apply_config_file(cfg, paper_json());
  CHECK(same(cfg, AcceleratorConfig{}));

  std::ifstream in(paper_json());
  const json file = json::parse(in);
  std::set<std::string> in_file;
  for (const auto& [k, v] : flat(file))
    if (k.rfind("//", 0) != 0) in_file.insert(k);
  std::set<std::string> hardware;  // sim.* is how the simulator runs, chosen by the command
  for (const auto& k : tigris::config_keys())
    if (k.rfind("sim.", 0) != 0) hardware.insert(k);
  CHECK(in_file == hardware);
}

TEST_CASE("config: a partial file changes only its keys and // members are comments", "[config]") {
  const TempFile f("partial.json", R"({"// note": "x", "fe": {"recursion_units": 32, "//": 1},
                                      "sram": {"points": {"bytes": 4194304}}, "clock_mhz": 1000})");
  AcceleratorConfig cfg;
  tigris::apply_config_file(cfg, f.path.string());
  AcceleratorConfig expected;
  expected.fe.recursion_units = 32;
  expected.sram.points.bytes = 4194304;
  expected.clock_mhz = 1000.0;
  CHECK(same(cfg, expected));
}

TEST_CASE("config: unknown keys are errors naming the source, with a suggestion", "[config]") {
  AcceleratorConfig cfg;
  CHECK(error_of([&] {
          tigris::apply_config_json(cfg, json::parse(R"({"fe": {"recursion_unit": 32}})"), "my.json");
        }) == "my.json: unknown key 'fe.recursion_unit' (did you mean 'fe.recursion_units'?)");
  CHECK(error_of([&] {
          tigris::apply_config_json(cfg, json::parse(R"({"sram": {"pointz": {"bytes": 1}}})"), "a.json");
        }) == "a.json: unknown key 'sram.pointz' (did you mean 'sram.points'?)");
  CHECK(error_of([&] { tigris::apply_config_json(cfg, json::parse(R"({"recursion_units": 32})"), "a.json"); }) ==
        "a.json: unknown key 'recursion_units' (did you mean 'fe.recursion_units'?)");
  const std::string far =
      error_of([&] { tigris::apply_config_json(cfg, json::parse(R"({"zzzzzzzzzz": 1})"), "a.json"); });
  CHECK(far == "a.json: unknown key 'zzzzzzzzzz' (tigris run --list-config lists every key)");
  CHECK(same(cfg, AcceleratorConfig{}));
}

TEST_CASE("config: wrong JSON types are errors naming the key", "[config]") {
  const auto err = [](const char* text) { return error_of([&] { applied(json::parse(text)); }); };
  CHECK(err(R"({"fe": {"recursion_units": 1.5}})") == "test.json: 'fe.recursion_units' must be an integer, got 1.5");
  CHECK(err(R"({"fe": {"recursion_units": "32"}})") ==
        "test.json: 'fe.recursion_units' must be an integer, got \"32\"");
  CHECK(err(R"({"fe": {"forwarding": 1}})") == "test.json: 'fe.forwarding' must be true or false, got 1");
  CHECK(err(R"({"clock_mhz": "500"})") == "test.json: 'clock_mhz' must be a number, got \"500\"");
  CHECK(err(R"({"clock_mhz": {"x": 1}})") == "test.json: 'clock_mhz' must be a number, got an object");
  CHECK(err(R"({"node_cache": {"bytes": 1.5}})") == "test.json: 'node_cache.bytes' must be an integer, got 1.5");
  CHECK(err(R"({"tree": {"top_height": null}})") ==
        "test.json: 'tree.top_height' must be an integer or \"full\", got null");
  CHECK(err(R"({"be": {"issue_policy": 1}})") ==
        "test.json: 'be.issue_policy' must be one of " + issue_names() + ", got 1");
  CHECK(err(R"({"fe": 3})") ==
        "test.json: 'fe' is a block and must be a JSON object of its keys (e.g. "
        "'fe.recursion_units'), got 3");
  CHECK(err(R"([1, 2])") == "test.json: a configuration must be a JSON object nested by block, got an array");
  // A whole number is a fine value for a number key.
  CHECK(applied(json::parse(R"({"clock_mhz": 2})")).clock_mhz == 2.0);
  CHECK(applied(json::parse(R"({"dram": {"bytes_per_cycle": 51.2}})")).dram.bytes_per_cycle == 51.2);
}

TEST_CASE("config: out-of-range values and bad enum values are errors naming the key", "[config]") {
  const auto err = [](const char* text) { return error_of([&] { applied(json::parse(text)); }); };
  CHECK(err(R"({"fe": {"recursion_units": 0}})") == "test.json: 'fe.recursion_units' = 0 is out of range (1..4096)");
  CHECK(err(R"({"clock_mhz": 0})") == "test.json: 'clock_mhz' = 0 is out of range (1..100000)");
  CHECK(err(R"({"clock_mhz": -5.5})") == "test.json: 'clock_mhz' = -5.5 is out of range (1..100000)");
  CHECK(err(R"({"tree": {"top_height": 31}})") ==
        "test.json: 'tree.top_height' = 31 is out of range (`full` (-1), -1..30)");
  CHECK(err(R"({"tree": {"top_height": -2}})").find("'tree.top_height' = -2 is out of range") != std::string::npos);
  CHECK(err(R"({"node_cache": {"bytes": -1}})") == "test.json: 'node_cache.bytes' = -1 is out of range (>= 0)");
  CHECK(err(R"({"sram": {"points": {"bytes": 0}}})") ==
        "test.json: 'sram.points.bytes' = 0 is out of range (1..268435456)");
  CHECK(err(R"({"sram": {"queries": {"banks": 0}}})") ==
        "test.json: 'sram.queries.banks' = 0 is out of range (1..4096)");
  CHECK(err(R"({"cost": {"ru_node": 0}})") == "test.json: 'cost.ru_node' = 0 is out of range (1..1000000)");
  CHECK(err(R"({"cost": {"ru_drain": -1}})") == "test.json: 'cost.ru_drain' = -1 is out of range (0..1000000)");
  CHECK(err(R"({"energy": {"dram_pj_per_byte": -0.5}})") ==
        "test.json: 'energy.dram_pj_per_byte' = -0.5 is out of range (0..1000000)");
  CHECK(err(R"({"area": {"sram_bank_mm2": -1}})") == "test.json: 'area.sram_bank_mm2' = -1 is out of range (0..10000)");
  CHECK(err(R"({"be": {"pes_per_su": 99999999999}})").find("'be.pes_per_su' = 99999999999 is out of range") !=
        std::string::npos);
  CHECK(err(R"({"be": {"issue_policy": "MQSN"}})") ==
        "test.json: 'be.issue_policy' must be one of " + issue_names() + ", got \"MQSN\"");
  CHECK(err(R"({"tree": {"split_axis": "x"}})") ==
        "test.json: 'tree.split_axis' must be one of `widest`, `round-robin`, got \"x\"");
  // The edges are fine.
  CHECK(applied(json::parse(R"({"node_cache": {"bytes": 0}})")).node_cache.bytes == 0);
  CHECK(applied(json::parse(R"({"leader": {"capacity_per_leaf": 0}})")).leader.capacity_per_leaf == 0);
  CHECK(applied(json::parse(R"({"tree": {"top_height": 0}})")).tree.top_height == 0);
  CHECK(applied(json::parse(R"({"tree": {"top_height": 30}})")).tree.top_height == 30);
}

TEST_CASE("config: tree.top_height takes full in files and --set", "[config]") {
  CHECK(applied(json::parse(R"({"tree": {"top_height": "full"}})")).tree.top_height == -1);
  CHECK(applied(json::parse(R"({"tree": {"top_height": -1}})")).tree.top_height == -1);
  AcceleratorConfig cfg;
  tigris::apply_setting(cfg, "tree.top_height=full");
  CHECK(cfg.tree.top_height == -1);
  CHECK(tigris::config_to_json(cfg)["tree"]["top_height"] == -1);
  tigris::apply_setting(cfg, "tree.top_height=14");
  CHECK(cfg.tree.top_height == 14);
  CHECK(error_of([&] { applied(json::parse(R"({"tree": {"top_height": "Full"}})")); }) ==
        "test.json: 'tree.top_height' must be an integer or \"full\", got \"Full\"");
  CHECK(error_of([&] { tigris::apply_setting(cfg, "tree.top_height=1.5"); }) ==
        "--set 'tree.top_height=1.5': 'tree.top_height' must be an integer or 'full', got '1.5'");
}

TEST_CASE("config: file errors name the file and syntax errors give the line", "[config]") {
  AcceleratorConfig cfg;
  const TempFile bad("syntax.json", "{\n  \"fe\": {\n    \"recursion_units\": 32,\n  }\n}\n");
  const std::string syntax = error_of([&] { tigris::apply_config_file(cfg, bad.path.string()); });
  CHECK(syntax.rfind(bad.path.string() + ": JSON parse error at line 4", 0) == 0);

  const TempFile empty("empty.json", "");
  CHECK(error_of([&] {
          tigris::apply_config_file(cfg, empty.path.string());
        }).rfind(empty.path.string() + ": JSON parse error", 0) == 0);

  const std::string missing = (fs::temp_directory_path() / "tigris_no_such_config.json").string();
  CHECK(error_of([&] { tigris::apply_config_file(cfg, missing); }) ==
        missing + ": cannot read configuration file: no such file");
  const std::string dir = fs::temp_directory_path().string();
  CHECK(error_of([&] { tigris::apply_config_file(cfg, dir); }) ==
        dir + ": cannot read configuration file: is a folder, not a regular file");

  const TempFile typo("typo.json", R"({"be": {"search_unit": 16}})");
  CHECK(error_of([&] { tigris::apply_config_file(cfg, typo.path.string()); }) ==
        typo.path.string() + ": unknown key 'be.search_unit' (did you mean 'be.search_units'?)");
  CHECK(same(cfg, AcceleratorConfig{}));
}

TEST_CASE("config: --set parses the value per the key's type", "[config]") {
  AcceleratorConfig cfg;
  tigris::apply_setting(cfg, "fe.recursion_units=16");
  tigris::apply_setting(cfg, "clock_mhz=1000");
  tigris::apply_setting(cfg, "dram.bytes_per_cycle=51.2");
  tigris::apply_setting(cfg, "energy.distance_pj=2.5e-1");
  tigris::apply_setting(cfg, "node_cache.bytes=0");
  tigris::apply_setting(cfg, "sram.points.bytes=4194304");
  tigris::apply_setting(cfg, "sram.query_stack.banks=4");
  tigris::apply_setting(cfg, "be.issue_policy=mqmn");
  tigris::apply_setting(cfg, "tree.split_axis=round-robin");
  tigris::apply_setting(cfg, "cost.ru_pi_rs_stall=5");
  CHECK(cfg.fe.recursion_units == 16);
  CHECK(cfg.clock_mhz == 1000.0);
  CHECK(cfg.dram.bytes_per_cycle == 51.2);
  CHECK(cfg.energy.distance_pj == 0.25);
  CHECK(cfg.node_cache.bytes == 0);
  CHECK(cfg.sram.points.bytes == 4194304u);
  CHECK(cfg.sram.query_stack.banks == 4);
  CHECK(cfg.be.issue_policy == std::string("mqmn"));
  CHECK(cfg.tree.split_axis == tigris::SplitRule::RoundRobin);
  CHECK(cfg.cost.ru_pi_rs_stall == 5);

  for (const auto& [text, value] : std::vector<std::pair<std::string, bool>>{
           {"true", true}, {"false", false}, {"1", true}, {"0", false}, {"on", true}, {"off", false}}) {
    tigris::apply_setting(cfg, "fe.bypassing=" + text);
    CHECK(cfg.fe.bypassing == value);
    tigris::apply_setting(cfg, "fe.forwarding=" + text);
    CHECK(cfg.fe.forwarding == value);
  }
}

TEST_CASE("config: bad --set forms are errors naming the --set text", "[config]") {
  AcceleratorConfig cfg;
  const auto err = [&](const std::string& text) { return error_of([&] { tigris::apply_setting(cfg, text); }); };
  CHECK(err("fe.recursion_units") == "--set 'fe.recursion_units': expected key=value, e.g. fe.recursion_units=32");
  CHECK(err("=3") == "--set '=3': missing key before '='");
  CHECK(err("fe.recursion_units=") == "--set 'fe.recursion_units=': missing value for 'fe.recursion_units'");
  CHECK(err("fe.recursion_units=abc") ==
        "--set 'fe.recursion_units=abc': 'fe.recursion_units' must be an integer, got 'abc'");
  CHECK(err("fe.recursion_units=3x") ==
        "--set 'fe.recursion_units=3x': 'fe.recursion_units' must be an integer, got '3x'");
  CHECK(err("fe.recursion_units=1.5") ==
        "--set 'fe.recursion_units=1.5': 'fe.recursion_units' must be an integer, got '1.5'");
  CHECK(err("fe.recursion_units=0") ==
        "--set 'fe.recursion_units=0': 'fe.recursion_units' = 0 is out of range (1..4096)");
  CHECK(err("fe=3") == "--set 'fe=3': 'fe' is a block, not a key; set its keys, e.g. 'fe.recursion_units'");
  CHECK(err("sram.points=3") ==
        "--set 'sram.points=3': 'sram.points' is a block, not a key; set its keys, e.g. "
        "'sram.points.bytes'");
  CHECK(err("fe.recursion_unit=3") ==
        "--set 'fe.recursion_unit=3': unknown key 'fe.recursion_unit' (did you mean "
        "'fe.recursion_units'?)");
  CHECK(err("fe.forwarding=yes") ==
        "--set 'fe.forwarding=yes': 'fe.forwarding' must be true/false/1/0/on/off, got 'yes'");
  CHECK(err("clock_mhz=fast") == "--set 'clock_mhz=fast': 'clock_mhz' must be a decimal number, got 'fast'");
  CHECK(err("clock_mhz= 5") == "--set 'clock_mhz= 5': 'clock_mhz' must be a decimal number, got ' 5'");
  CHECK(err("clock_mhz=nan") == "--set 'clock_mhz=nan': 'clock_mhz' must be a decimal number, got 'nan'");
  // A named value by its name only (issue 54: -1 was taken as auto, -0 as off).
  CHECK_THAT(err("sim.sampling=-1"), Catch::Contains("write 'auto' for auto"));
  CHECK_THAT(err("sim.sampling=-0"), Catch::Contains("no negative value"));
  CHECK(err("node_cache.bytes=-1") ==
        "--set 'node_cache.bytes=-1': 'node_cache.bytes' must be a whole number of bytes, got '-1'");
  CHECK(err("be.pes_per_su=99999999999999999999") ==
        "--set 'be.pes_per_su=99999999999999999999': 'be.pes_per_su' = 99999999999999999999 is out "
        "of range (1..4096)");
  CHECK(err("be.pes_per_su=9999999999") ==
        "--set 'be.pes_per_su=9999999999': 'be.pes_per_su' = 9999999999 is out of range (1..4096)");
  CHECK(err("be.issue_policy=MQMN") == "--set 'be.issue_policy=MQMN': 'be.issue_policy' must be one of " +
                                           issue_names() +
                                           ", got "
                                           "\"MQMN\"");
  CHECK(err("node_cache.policy=MQMN") == "--set 'node_cache.policy=MQMN': 'node_cache.policy' must be one of " +
                                             replacement_names() +
                                             ", got "
                                             "\"MQMN\"");
  CHECK(same(cfg, AcceleratorConfig{}));  // a failed --set changes nothing
}

TEST_CASE("config: node_cache.policy is lru by default, takes fifo, rejects anything else", "[config]") {
  AcceleratorConfig cfg;
  CHECK(cfg.node_cache.policy == std::string("lru"));
  CHECK(tigris::config_to_json(cfg)["node_cache"]["policy"] == "lru");
  tigris::apply_setting(cfg, "node_cache.policy=fifo");
  CHECK(cfg.node_cache.policy == std::string("fifo"));
  CHECK(tigris::config_to_json(cfg)["node_cache"]["policy"] == "fifo");
  tigris::apply_setting(cfg, "node_cache.policy=lru");
  CHECK(same(cfg, AcceleratorConfig{}));

  CHECK(error_of([&] { tigris::apply_setting(cfg, "node_cache.policy=foo"); }) ==
        "--set 'node_cache.policy=foo': 'node_cache.policy' must be one of " + replacement_names() +
            ", got "
            "\"foo\"");
  CHECK(error_of([&] {
          tigris::apply_config_json(cfg, json::parse(R"({"node_cache": {"policy": "random"}})"), "c.json");
        }) == "c.json: 'node_cache.policy' must be one of " + replacement_names() + ", got \"random\"");
  CHECK(error_of([&] { tigris::apply_config_json(cfg, json::parse(R"({"node_cache": {"policy": 0}})"), "c.json"); }) ==
        "c.json: 'node_cache.policy' must be one of " + replacement_names() + ", got 0");
  CHECK(same(cfg, AcceleratorConfig{}));  // rejected values change nothing
  CHECK(tigris::config_reference().find("| `node_cache.policy` | lru | - | " + replacement_names() + " |") !=
        std::string::npos);
}

TEST_CASE("config: validate_config checks ranges and cross-field rules, naming the key", "[config]") {
  const auto err = [](const std::function<void(AcceleratorConfig&)>& change) {
    AcceleratorConfig cfg;
    change(cfg);
    return error_of([&] { tigris::validate_config(cfg); });
  };
  CHECK(err([](auto& c) { c.clock_mhz = 0; }) ==
        "invalid configuration: 'clock_mhz' = 0.0 is out of range (1..100000)");
  CHECK(err([](auto& c) { c.clock_mhz = std::nan(""); }).find("'clock_mhz' must be a finite number") !=
        std::string::npos);
  CHECK(err([](auto& c) { c.be.search_units = 0; }).find("'be.search_units' = 0 is out of range") != std::string::npos);
  CHECK(err([](auto& c) { c.sram.results.ports = 0; }).find("'sram.results.ports' = 0 is out of range") !=
        std::string::npos);
  CHECK(err([](auto& c) { c.sram.queries.bytes = 0; }).find("'sram.queries.bytes' = 0 is out of range") !=
        std::string::npos);
  CHECK(err([](auto& c) { c.tree.top_height = -2; }).find("'tree.top_height' = -2 is out of range") !=
        std::string::npos);
  CHECK(err([](auto& c) { c.energy.sram_ref_pj_per_byte = -1; }).find("'energy.sram_ref_pj_per_byte'") !=
        std::string::npos);
  CHECK(err([](auto& c) {
          c.energy.sram_size_exponent = -0.5;
        }).find("'energy.sram_size_exponent' = -0.5 is out of range") != std::string::npos);
  CHECK(err([](auto& c) { c.area.pe_mm2 = -0.1; }).find("'area.pe_mm2' = -0.1 is out of range") != std::string::npos);
  CHECK(err([](auto& c) {
          c.area.sram_mm2_per_mib = std::nan("");
        }).find("'area.sram_mm2_per_mib' must be a finite number") != std::string::npos);
  CHECK(err([](auto& c) { c.be.bqb_entry_bytes = 0; }).find("'be.bqb_entry_bytes' = 0 is out of range") !=
        std::string::npos);
  CHECK(err([](auto& c) { c.cost.ru_node = 0; }).find("'cost.ru_node' = 0 is out of range") != std::string::npos);
  CHECK(err([](auto& c) { c.cost.issue_cycle = -1; }).find("'cost.issue_cycle' = -1 is out of range") !=
        std::string::npos);
  // Cross-field rules.
  CHECK(err([](auto& c) { c.sram.points.bytes = 8; }) ==
        "invalid configuration: 'sram.points.bytes' holds no word of sram.points.word_bytes");
  // Whether a job fits is hw::job_fit_error's question (the tree decides the stack height).
  AcceleratorConfig small_fqq, small_stack;
  small_fqq.fe.fqq_bytes = 4;
  small_stack.sram.query_stack.bytes = 100;
  CHECK_NOTHROW(tigris::validate_config(small_fqq));
  CHECK(tigris::hw::job_fit_error(small_fqq, 1024, 10, 10, tigris::tlm_if::SearchMode::NN, 1) ==
        "the FE Query Queue cannot hold one query: fe.fqq_bytes = 4 holds no entry of "
        "fe.fqq_entry_bytes = 8");
  CHECK(tigris::hw::job_fit_error(small_stack, 1024, 10, 30, tigris::tlm_if::SearchMode::NN, 1) ==
        "the Query Stack Buffer cannot hold one query's stack of top height 30 (240 bytes, "
        "sram.query_stack.bytes)");
  CHECK(tigris::hw::job_fit_error(small_stack, 1024, 10, 12, tigris::tlm_if::SearchMode::NN, 1).empty());
  CHECK(tigris::hw::job_fit_error(small_stack, 1024, 0, 30, tigris::tlm_if::SearchMode::NN, 1).empty());
  // first_leaf kNN slots carry the results' coordinates too: k = 100,000 fits the default slot
  // area (1.5 MB) as 8 + 8k bytes but not as 8 + 20k.
  CHECK(tigris::hw::job_fit_error(AcceleratorConfig{}, 1024, 10, 10, tigris::tlm_if::SearchMode::KNN, 100000).empty());
  CHECK_THAT(
      tigris::hw::job_fit_error(AcceleratorConfig{}, 1024, 10, 10, tigris::tlm_if::SearchMode::KNN, 100000, true),
      Catch::Contains("100000 results with their coordinates (approximate, leader.scope first_leaf)"));
  // Edges that are fine: cache off, no leaders, full height with a small stack (the tree decides).
  AcceleratorConfig ok;
  ok.node_cache.bytes = 0;
  ok.leader.capacity_per_leaf = 0;
  ok.tree.top_height = -1;
  ok.sram.query_stack.bytes = 8;
  CHECK_NOTHROW(tigris::validate_config(ok));
}

TEST_CASE("config: the reference table lists every key of config_to_json", "[config]") {
  const std::string ref = tigris::config_reference();
  CHECK(ref.rfind("| key | default | unit | allowed | meaning |\n|---|---|---|---|---|\n", 0) == 0);
  std::size_t rows = 0;
  for (const auto& [key, value] : flat(tigris::config_to_json(AcceleratorConfig{}))) {
    INFO(key);
    CHECK(ref.find("\n| `" + key + "` | ") != std::string::npos);
    ++rows;
  }
  CHECK(static_cast<std::size_t>(std::count(ref.begin(), ref.end(), '\n')) == rows + 2);
  CHECK(ref.find("| `fe.recursion_units` | 64 | units | 1..4096 |") != std::string::npos);
  CHECK(ref.find("| `sram.points.bytes` | 2097152 (2 MiB) | bytes | 1..268435456 |") != std::string::npos);
}

TEST_CASE("config: every key has a unit and a doc, and the reference lists every key", "[config]") {
  AcceleratorConfig cfg;
  std::vector<std::string> visited;
  cfg.visit([&](const std::string& name, auto&, const tigris::hw::Spec& spec) {
    INFO(name);
    CHECK_FALSE(spec.unit.empty());
    CHECK_FALSE(spec.doc.empty());
    visited.push_back(name);
  });
  CHECK(visited == tigris::config_keys());
  const std::string ref = tigris::config_reference();
  for (const auto& key : tigris::config_keys()) {
    INFO(key);
    CHECK(ref.find("\n| `" + key + "` | ") != std::string::npos);
  }
}
