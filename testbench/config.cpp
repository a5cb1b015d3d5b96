#include "config.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <variant>

namespace tigris {
namespace {

using hw::AcceleratorConfig;
using hw::SramConfig;
using nlohmann::json;

// A key's field; its type is the key's type (std::uint64_t fields are byte counts).
using Ref = std::variant<int*, bool*, double*, std::uint64_t*, hw::IssuePolicyKind*, SplitRule*>;

// Enumerated keys: every value with its name.
template <class E>
const std::vector<std::pair<std::string, E>>& enum_names();
template <>
const std::vector<std::pair<std::string, hw::IssuePolicyKind>>& enum_names() {
  static const std::vector<std::pair<std::string, hw::IssuePolicyKind>> v = {
      {"mqsn", hw::IssuePolicyKind::Mqsn}, {"mqmn", hw::IssuePolicyKind::Mqmn}};
  return v;
}
template <>
const std::vector<std::pair<std::string, SplitRule>>& enum_names() {
  static const std::vector<std::pair<std::string, SplitRule>> v = {
      {"widest", SplitRule::WidestExtent}, {"round-robin", SplitRule::RoundRobin}};
  return v;
}
template <class E>
std::string enum_name(E e) {
  for (const auto& [name, value] : enum_names<E>())
    if (value == e) return name;
  return "?";
}

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Allowed {
  double lo = -kInf, hi = kInf;                    // numbers: inclusive range
  bool lo_open = false;                            // numbers: lo itself excluded (> lo)
  std::vector<std::string> choices;                // strings: the values allowed
  std::vector<std::pair<std::string, int>> names;  // integers: names for values ("full" = -1)
};

Allowed in(double lo, double hi) { return Allowed{lo, hi, false, {}, {}}; }
Allowed at_least(double lo) { return in(lo, kInf); }
Allowed above(double lo, double hi = kInf) { return Allowed{lo, hi, true, {}, {}}; }
Allowed one_of(std::vector<std::string> v) { return Allowed{-kInf, kInf, false, std::move(v), {}}; }
Allowed any() { return Allowed{}; }
Allowed named(Allowed a, std::string name, int value) {
  a.names.emplace_back(std::move(name), value);
  return a;
}

struct Key {
  std::string name;  // dotted: block.field or sram.buffer.field
  std::function<Ref(AcceleratorConfig&)> field;
  std::string unit;
  Allowed allowed;
  std::string doc;
};

#define AT(member) [](AcceleratorConfig& c) -> Ref { return &c.member; }

constexpr double kMaxUnits = 4096, kMaxEntries = 1 << 20, kMaxCycles = 1e6;

// THE registry: every configuration key, in the order the reference lists them.
const std::vector<Key>& registry() {
  static const std::vector<Key> keys = [] {
    std::vector<Key> k = {
        {"clock_mhz", AT(clock_mhz), "MHz", above(0, 1e5), "accelerator clock"},
        {"tree.top_height", AT(tree.top_height), "levels", named(in(-1, 30), "full", -1),
         "height of the top tree the RUs walk; below it lie the leaf sets the SUs scan (-1 or "
         "\"full\": the canonical tree, Acc-KD)"},
        {"tree.split_axis", AT(tree.split_axis), "-", one_of({"widest", "round-robin"}),
         "axis a node splits: widest extent, or x, y, z in turn"},
        {"fe.recursion_units", AT(fe.recursion_units), "units", in(1, kMaxUnits),
         "Recursion Units (RUs) in the front end"},
        {"fe.forwarding", AT(fe.forwarding), "-", any(),
         "PI->RS forwarding: removes the PI->RS stall (cost.ru_pi_rs_stall) per visited node"},
        {"fe.bypassing", AT(fe.bypassing), "-", any(),
         "a pruned node leaves the RU pipeline at RN instead of going down to PI"},
        {"fe.fqq_bytes", AT(fe.fqq_bytes), "bytes", at_least(1),
         "FE Query Queue: new queries and queries re-inserted by the BE; backpressure when full"},
        {"fe.fqq_entry_bytes", AT(fe.fqq_entry_bytes), "bytes", in(1, 4096),
         "one FQQ entry (query id + flags)"},
        {"be.search_units", AT(be.search_units), "units", in(1, kMaxUnits),
         "Search Units (SUs) in the back end"},
        {"be.pes_per_su", AT(be.pes_per_su), "PEs", in(1, kMaxUnits),
         "PEs per SU: a 1-D query-stationary systolic array"},
        {"be.bqb_entries", AT(be.bqb_entries), "entries", in(1, kMaxEntries),
         "BE Query Buffer entries per SU"},
        {"be.issue_policy", AT(be.issue_policy), "-", one_of({"mqsn", "mqmn"}),
         "issue logic: mqsn (the head's leaf only, associative search) or mqmn (any query to any "
         "PE)"},
        {"be.issue_search_width", AT(be.issue_search_width), "entries", in(1, kMaxEntries),
         "BQB entries the MQSN associative search checks per cycle"},
        {"leader.capacity_per_leaf", AT(leader.capacity_per_leaf), "leaders", in(0, kMaxUnits),
         "leaders the Leader Buffer keeps per leaf (approximate search)"},
        {"node_cache.bytes", AT(node_cache.bytes), "bytes", at_least(0),
         "Node Cache: whole Node Sets, read as FIFOs; 0 turns it off"},
    };
    const struct {
      const char* name;
      SramConfig AcceleratorConfig::Sram::*member;
      const char* doc;
    } buffers[] = {
        {"points", &AcceleratorConfig::Sram::points,
         "Point Buffer: the tree's points, 16-byte entries (x, y, z, index)"},
        {"queries", &AcceleratorConfig::Sram::queries, "Query Buffer: the queries"},
        {"query_stack", &AcceleratorConfig::Sram::query_stack,
         "Query Stack Buffer: top-height entries per query in flight"},
        {"results", &AcceleratorConfig::Sram::results, "Result Buffer, double-buffered to DRAM"},
    };
    for (const auto& b : buffers) {
      const std::string p = std::string("sram.") + b.name;
      const auto m = b.member;
      // A buffer is one 256 MiB window of the host address map (tlm/address_map.hpp).
      k.push_back({p + ".bytes", [m](AcceleratorConfig& c) -> Ref { return &(c.sram.*m).bytes; },
                   "bytes", in(1, 268435456), b.doc});
      k.push_back({p + ".banks", [m](AcceleratorConfig& c) -> Ref { return &(c.sram.*m).banks; },
                   "banks", in(1, kMaxUnits),
                   "word-interleaved banks, one access per bank per cycle"});
      k.push_back({p + ".ports", [m](AcceleratorConfig& c) -> Ref { return &(c.sram.*m).ports; },
                   "accesses/cycle", in(1, kMaxUnits),
                   "accesses accepted per cycle, all banks together"});
      k.push_back({p + ".latency_cycles",
                   [m](AcceleratorConfig& c) -> Ref { return &(c.sram.*m).latency_cycles; },
                   "cycles", in(0, kMaxCycles), "read latency of one access"});
      k.push_back({p + ".word_bytes",
                   [m](AcceleratorConfig& c) -> Ref { return &(c.sram.*m).word_bytes; }, "bytes",
                   in(1, 4096), "bank interleaving granule (one entry)"});
    }
    const std::vector<Key> rest = {
        {"result_buffer.slot_fraction", AT(result_buffer.slot_fraction), "-", above(0, 1),
         "share of the Result Buffer (sram.results.bytes) holding NN/kNN query slots; the rest "
         "double-buffers the result stream to DRAM"},
        {"dram.bytes_per_cycle", AT(dram.bytes_per_cycle), "bytes/cycle", above(0, 1e6),
         "DRAM bandwidth for the result write-back"},
        {"dram.latency_cycles", AT(dram.latency_cycles), "cycles", in(0, kMaxCycles),
         "DRAM access latency"},
        {"cost.ru_fetch_query", AT(cost.ru_fetch_query), "cycles", in(0, kMaxCycles),
         "RU stage FQ: once per activation (a query taken from the FQQ)"},
        {"cost.ru_node", AT(cost.ru_node), "cycles", in(1, kMaxCycles),
         "RU: one node through RS..PI when nothing stalls"},
        {"cost.ru_pi_rs_stall", AT(cost.ru_pi_rs_stall), "cycles", in(0, kMaxCycles),
         "RU: PI->RS dependency stall per visited node without forwarding"},
        {"cost.ru_prune_at_rn", AT(cost.ru_prune_at_rn), "cycles", in(0, kMaxCycles),
         "RU: a pruned node with bypassing (leaves at RN)"},
        {"cost.ru_prune_no_bypass", AT(cost.ru_prune_no_bypass), "cycles", in(0, kMaxCycles),
         "RU: a pruned node without bypassing (RS..PI)"},
        {"cost.ru_drain", AT(cost.ru_drain), "cycles", in(0, kMaxCycles),
         "RU: CD..CL behind the last node before the query is sent on"},
        {"cost.qdn_latency", AT(cost.qdn_latency), "cycles", in(0, kMaxCycles),
         "QDN: FE -> BQB wire and arbitration"},
        {"cost.qdn_port_interval", AT(cost.qdn_port_interval), "cycles", in(0, kMaxCycles),
         "QDN: interval between two queries on one SU port"},
        {"cost.pe_pipeline_depth", AT(cost.pe_pipeline_depth), "cycles", in(0, kMaxCycles),
         "PE pipeline: read, distance, insert"},
        {"cost.node_cache_hit", AT(cost.node_cache_hit), "cycles", in(0, kMaxCycles),
         "SU: a Node Set streamed from the Node Cache, cycles before its first word"},
        {"cost.issue_cycle", AT(cost.issue_cycle), "cycles", in(0, kMaxCycles),
         "SU issue logic per batch beyond the associative search"},
        {"cost.result_writeback", AT(cost.result_writeback), "cycles", in(0, kMaxCycles),
         "a finished query's results leave the RU (after its last walk)"},
        {"cost.be_to_fe", AT(cost.be_to_fe), "cycles", in(0, kMaxCycles),
         "a scanned query re-enters the FQQ"},
        {"cost.host_csr_access", AT(cost.host_csr_access), "cycles", in(0, kMaxCycles),
         "host: one CSR read or write"},
        {"cost.host_link_bytes_per_cycle", AT(cost.host_link_bytes_per_cycle), "bytes/cycle",
         in(1, kMaxCycles), "host: reading the result region from DRAM"},
        {"energy.distance_pj", AT(energy.distance_pj), "pJ", at_least(0),
         "PE: one float32 squared distance (3 sub, 3 mul, 2 add)"},
        {"energy.ru_node_pj", AT(energy.ru_node_pj), "pJ", at_least(0),
         "RU: one top-tree node through CD (its squared distance) and PI"},
        {"energy.sram_read_pj_per_byte", AT(energy.sram_read_pj_per_byte), "pJ/byte", at_least(0),
         "global buffer SRAM read"},
        {"energy.sram_write_pj_per_byte", AT(energy.sram_write_pj_per_byte), "pJ/byte", at_least(0),
         "global buffer SRAM write"},
        {"energy.node_cache_pj_per_byte", AT(energy.node_cache_pj_per_byte), "pJ/byte", at_least(0),
         "Node Cache access"},
        {"energy.dram_pj_per_byte", AT(energy.dram_pj_per_byte), "pJ/byte", at_least(0),
         "DRAM access"},
    };
    k.insert(k.end(), rest.begin(), rest.end());
    return k;
  }();
  return keys;
}

#undef AT

const Key* find_key(const std::string& name) {
  for (const Key& k : registry())
    if (k.name == name) return &k;
  return nullptr;
}

// A block is a proper dotted prefix of some key ("fe", "sram", "sram.points"); returns its
// first key, or nullptr.
const Key* first_in_block(const std::string& block) {
  for (const Key& k : registry())
    if (k.name.size() > block.size() && k.name.compare(0, block.size(), block) == 0 &&
        k.name[block.size()] == '.')
      return &k;
  return nullptr;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

[[noreturn]] void unknown_key(const std::string& source, const std::string& name) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, name.size() / 3) + 1;
  auto consider = [&](const std::string& candidate) {
    const std::size_t d = edit_distance(name, candidate);
    if (d < best_d) best_d = d, best = candidate;
  };
  for (const Key& k : registry()) {
    consider(k.name);
    for (std::size_t dot = k.name.find('.'); dot != std::string::npos;
         dot = k.name.find('.', dot + 1))
      consider(k.name.substr(0, dot));
  }
  throw std::invalid_argument(source + ": unknown key '" + name + "'" +
                              (best.empty() ? " (tigris run --list-config lists every key)"
                                            : " (did you mean '" + best + "'?)"));
}

[[noreturn]] void block_not_key(const std::string& source, const std::string& block) {
  throw std::invalid_argument(source + ": '" + block +
                              "' is a block, not a key; set its keys, e.g. '" +
                              first_in_block(block)->name + "'");
}

std::string number_text(double x) {
  if (std::isfinite(x) && x == std::floor(x) && std::fabs(x) < 1e15)
    return std::to_string(static_cast<long long>(x));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

std::string describe(const Allowed& a, bool is_bool) {
  if (is_bool) return "true, false";
  std::string s;
  for (const auto& c : a.choices) s += (s.empty() ? "" : ", ") + ("`" + c + "`");
  if (!a.choices.empty()) return s;
  for (const auto& n : a.names) s += "`" + n.first + "` (" + std::to_string(n.second) + "), ";
  if (a.lo_open)
    s += "> " + number_text(a.lo) + (a.hi < kInf ? ", <= " + number_text(a.hi) : "");
  else if (a.hi == kInf)
    s += ">= " + number_text(a.lo);
  else
    s += number_text(a.lo) + ".." + number_text(a.hi);
  return s;
}

std::string shown(const json& v) {
  if (v.is_object()) return "an object";
  if (v.is_array()) return "an array";
  if (v.is_number_float() && !std::isfinite(v.get<double>())) return number_text(v.get<double>());
  std::string s = v.dump();
  return s.size() > 40 ? s.substr(0, 37) + "..." : s;
}

// Checks a JSON value against a key's type and allowed values and converts it; errors start
// with `source`.
template <class T>
T convert(const Key& k, const json& v, const std::string& source) {
  const auto fail = [&](const std::string& what) {
    throw std::invalid_argument(source + ": '" + k.name + "' " + what);
  };
  const auto check_range = [&](double x) {
    const Allowed& a = k.allowed;
    if (x < a.lo || (a.lo_open && x == a.lo) || x > a.hi)
      fail("= " + shown(v) + " is out of range (" + describe(a, false) + ")");
  };
  if constexpr (std::is_same_v<T, bool>) {
    if (!v.is_boolean()) fail("must be true or false, got " + shown(v));
    return v.get<bool>();
  } else if constexpr (std::is_enum_v<T>) {
    if (v.is_string())
      for (const auto& [name, value] : enum_names<T>())
        if (v.get<std::string>() == name) return value;
    fail("must be one of " + describe(k.allowed, false) + ", got " + shown(v));
    return T{};
  } else if constexpr (std::is_same_v<T, double>) {
    if (!v.is_number()) fail("must be a number, got " + shown(v));
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail("must be a finite number, got " + shown(v));
    check_range(x);
    return x;
  } else {  // int or std::uint64_t
    if (v.is_string())
      for (const auto& [name, value] : k.allowed.names)
        if (v.get<std::string>() == name) return static_cast<T>(value);
    if (!v.is_number_integer()) {
      std::string names;
      for (const auto& n : k.allowed.names) names += " or \"" + n.first + "\"";
      fail("must be an integer" + names + ", got " + shown(v));
    }
    // Out-of-type values (negative bytes, ints beyond INT_MAX) are reported as out of range.
    const double x = v.is_number_unsigned() ? static_cast<double>(v.get<std::uint64_t>())
                                            : static_cast<double>(v.get<std::int64_t>());
    check_range(x);
    if constexpr (std::is_same_v<T, int>) {
      if (x > INT_MAX || x < INT_MIN) fail("= " + shown(v) + " is out of range");
      return static_cast<int>(v.get<std::int64_t>());
    } else {
      if (x < 0) fail("= " + shown(v) + " is out of range (>= 0)");
      return v.get<std::uint64_t>();
    }
  }
}

void assign(const Key& k, AcceleratorConfig& cfg, const json& v, const std::string& source) {
  std::visit([&](auto* p) { *p = convert<std::remove_pointer_t<decltype(p)>>(k, v, source); },
             k.field(cfg));
}

json value_of(const Key& k, const AcceleratorConfig& cfg) {
  AcceleratorConfig copy = cfg;  // field() needs a mutable config; only reads here
  return std::visit(
      [](auto* p) -> json {
        if constexpr (std::is_enum_v<std::remove_pointer_t<decltype(p)>>)
          return enum_name(*p);
        else
          return *p;
      },
      k.field(copy));
}

// A --set value as the JSON value a file would hold, per the key's type.
json parse_text(const Key& k, const std::string& text, const std::string& source) {
  const auto fail = [&](const std::string& expected) -> json {
    throw std::invalid_argument(source + ": '" + k.name + "' must be " + expected + ", got '" +
                                text + "'");
  };
  const char* first = text.data();
  const char* last = first + text.size();
  AcceleratorConfig scratch;  // only to learn the key's type
  return std::visit(
      [&](auto* p) -> json {
        using T = std::remove_pointer_t<decltype(p)>;
        if constexpr (std::is_same_v<T, bool>) {
          for (const char* t : {"true", "1", "on"})
            if (text == t) return true;
          for (const char* f : {"false", "0", "off"})
            if (text == f) return false;
          return fail("true/false/1/0/on/off");
        } else if constexpr (std::is_enum_v<T>) {
          return text;
        } else if constexpr (std::is_same_v<T, double>) {
          char* end = nullptr;
          errno = 0;
          const double x = text.empty() || std::isspace(static_cast<unsigned char>(text[0]))
                               ? 0.0
                               : std::strtod(first, &end);
          if (end != last || errno == ERANGE) return fail("a number");
          return x;
        } else {
          for (const auto& n : k.allowed.names)
            if (text == n.first) return text;
          std::conditional_t<std::is_same_v<T, int>, std::int64_t, std::uint64_t> x{};
          const auto r = std::from_chars(first, last, x);
          if (r.ec == std::errc::result_out_of_range && r.ptr == last)
            throw std::invalid_argument(source + ": '" + k.name + "' = " + text +
                                        " is out of range (" + describe(k.allowed, false) + ")");
          if (r.ec != std::errc() || r.ptr != last || text.empty())
            return fail(std::is_same_v<T, int>
                            ? (k.allowed.names.empty()
                                   ? std::string("an integer")
                                   : "an integer or '" + k.allowed.names[0].first + "'")
                            : std::string("a whole number of bytes"));
          return x;
        }
      },
      k.field(scratch));
}

void apply_object(AcceleratorConfig& cfg, const json& obj, const std::string& prefix,
                  const std::string& source) {
  for (const auto& [name, v] : obj.items()) {
    if (name.rfind("//", 0) == 0) continue;  // a comment
    const std::string path = prefix.empty() ? name : prefix + "." + name;
    if (const Key* k = find_key(path)) {
      assign(*k, cfg, v, source);
    } else if (first_in_block(path)) {
      if (!v.is_object())
        throw std::invalid_argument(source + ": '" + path +
                                    "' is a block and must be a JSON object of its keys (e.g. '" +
                                    first_in_block(path)->name + "'), got " + shown(v));
      apply_object(cfg, v, path, source);
    } else {
      unknown_key(source, path);
    }
  }
}

std::string default_text(const Key& k) {
  const json v = value_of(k, AcceleratorConfig{});
  std::string s = v.is_string() ? v.get<std::string>() : v.dump();
  if (v.is_number_unsigned() && v.get<std::uint64_t>() >= 1024) {
    const double b = static_cast<double>(v.get<std::uint64_t>());
    const int e = b >= 1048576.0 ? 2 : 1;
    char buf[32];
    std::snprintf(buf, sizeof buf, " (%.3g %s)", b / std::pow(1024.0, e), e == 2 ? "MiB" : "KiB");
    s += buf;
  }
  return s;
}

std::string cell(std::string s) {
  for (std::size_t i = s.find('|'); i != std::string::npos; i = s.find('|', i + 2))
    s.insert(i, "\\");
  return s;
}

}  // namespace

void apply_config_json(AcceleratorConfig& cfg, const json& j, const std::string& source) {
  if (!j.is_object())
    throw std::invalid_argument(
        source + ": a configuration must be a JSON object nested by block, got " + shown(j));
  apply_object(cfg, j, "", source);
}

void apply_config_file(AcceleratorConfig& cfg, const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw std::invalid_argument(path + ": cannot read configuration file: is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw std::invalid_argument(path + ": cannot open configuration file: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  json j;
  try {
    j = json::parse(text.str());
  } catch (const json::parse_error& e) {
    std::string what = e.what();  // "[json.exception.parse_error.101] parse error at line 3, ..."
    const auto bracket = what.find("] ");
    if (bracket != std::string::npos) what.erase(0, bracket + 2);
    throw std::invalid_argument(path + ": JSON " + what);
  }
  apply_config_json(cfg, j, path);
}

void apply_setting(AcceleratorConfig& cfg, const std::string& assignment) {
  const std::string source = "--set '" + assignment + "'";
  const auto eq = assignment.find('=');
  if (eq == std::string::npos)
    throw std::invalid_argument(source + ": expected key=value, e.g. fe.recursion_units=32");
  const std::string name = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  if (name.empty()) throw std::invalid_argument(source + ": missing key before '='");
  const Key* k = find_key(name);
  if (!k) {
    if (first_in_block(name)) block_not_key(source, name);
    unknown_key(source, name);
  }
  if (text.empty()) throw std::invalid_argument(source + ": missing value for '" + name + "'");
  assign(*k, cfg, parse_text(*k, text, source), source);
}

json config_to_json(const AcceleratorConfig& cfg) {
  json j = json::object();
  for (const Key& k : registry()) {
    std::string pointer = "/" + k.name;
    std::replace(pointer.begin(), pointer.end(), '.', '/');
    j[json::json_pointer(pointer)] = value_of(k, cfg);
  }
  return j;
}

std::string config_reference() {
  std::string s = "| key | default | unit | allowed | meaning |\n|---|---|---|---|---|\n";
  for (const Key& k : registry()) {
    const bool is_bool = value_of(k, AcceleratorConfig{}).is_boolean();
    s += "| `" + k.name + "` | " + cell(default_text(k)) + " | " + cell(k.unit) + " | " +
         cell(describe(k.allowed, is_bool)) + " | " + cell(k.doc) + " |\n";
  }
  return s;
}

std::vector<std::string> config_keys() {
  std::vector<std::string> names;
  for (const Key& k : registry()) names.push_back(k.name);
  return names;
}

void validate_config(const AcceleratorConfig& cfg) {
  const std::string source = "invalid configuration";
  for (const Key& k : registry()) {
    AcceleratorConfig copy = cfg;
    assign(k, copy, value_of(k, cfg), source);  // per-key type and range
  }
  // Cross-field rules: {key to blame, holds, explanation}.
  const auto n = [](auto x) { return std::to_string(x); };
  const auto holds_one = [&](const SramConfig& b) {
    return b.bytes >= static_cast<std::uint64_t>(b.word_bytes);
  };
  const std::uint64_t stack_bytes = static_cast<std::uint64_t>(std::max(cfg.tree.top_height, 0)) *
                                    static_cast<std::uint64_t>(cfg.sram.query_stack.word_bytes);
  const struct {
    const char* key;
    bool ok;
    std::string why;
  } rules[] = {
      {"fe.fqq_bytes", cfg.fe.fqq_bytes >= static_cast<std::uint64_t>(cfg.fe.fqq_entry_bytes),
       "= " + n(cfg.fe.fqq_bytes) +
           " holds no entry of fe.fqq_entry_bytes = " + n(cfg.fe.fqq_entry_bytes)},
      {"sram.points.bytes", holds_one(cfg.sram.points), "holds no word of sram.points.word_bytes"},
      {"sram.queries.bytes", holds_one(cfg.sram.queries),
       "holds no word of sram.queries.word_bytes"},
      {"sram.query_stack.bytes",
       holds_one(cfg.sram.query_stack) && cfg.sram.query_stack.bytes >= stack_bytes,
       "= " + n(cfg.sram.query_stack.bytes) + " holds no query's stack: tree.top_height (" +
           n(cfg.tree.top_height) + ") x sram.query_stack.word_bytes (" +
           n(cfg.sram.query_stack.word_bytes) + ") bytes, at least one word"},
      {"sram.results.bytes", holds_one(cfg.sram.results),
       "holds no word of sram.results.word_bytes"},
  };
  for (const auto& r : rules)
    if (!r.ok) throw std::invalid_argument(source + ": '" + r.key + "' " + r.why);
}

}  // namespace tigris
