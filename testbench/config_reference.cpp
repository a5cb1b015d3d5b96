// The reference table of every configuration key (`tigris run --list-config`),
// rendered from the key table.
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "config.hpp"
#include "config_keys.hpp"

namespace tigris {
namespace {

using config_table::Key;
using nlohmann::json;

// The default value; byte counts of 1 KiB and more also in KiB or MiB.
std::string default_text(const Key& k) {
  const json v = config_table::get(hw::AcceleratorConfig{}, k);
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

// A Markdown table cell: '|' escaped.
std::string cell(std::string s) {
  for (std::size_t i = s.find('|'); i != std::string::npos; i = s.find('|', i + 2))
    s.insert(i, "\\");
  return s;
}

}  // namespace

std::string config_reference() {
  std::string s = "| key | default | unit | allowed | meaning |\n|---|---|---|---|---|\n";
  for (const Key& k : config_table::keys())
    s += "| `" + k.name + "` | " + cell(default_text(k)) + " | " + cell(k.spec.unit) + " | " +
         cell(config_table::describe(k)) + " | " + cell(k.spec.doc) + " |\n";
  return s;
}

json config_reference_json() {
  static const char* const type_names[] = {"integer", "bytes", "number", "bool", "enum"};
  json keys = json::array();
  for (const Key& k : config_table::keys()) {
    const hw::Allowed& a = k.spec.allowed;
    json j = {{"key", k.name},
              {"type", type_names[static_cast<int>(k.type)]},
              {"unit", k.spec.unit},
              {"default", config_table::get(hw::AcceleratorConfig{}, k)},
              {"doc", k.spec.doc}};
    if (k.type == config_table::Type::Enum) {
      j["values"] = json::array();
      for (const auto& n : a.names) j["values"].push_back(n.name);
    } else if (k.type != config_table::Type::Bool) {
      // JSON has no infinity: an open end is left out.
      if (std::isfinite(a.lo)) j[a.lo_open ? "above" : "min"] = a.lo;
      if (std::isfinite(a.hi)) j["max"] = a.hi;
      for (const auto& n : a.names) j["named"][n.name] = n.value;
    }
    keys.push_back(j);
  }
  return {{"keys", keys}};
}

}  // namespace tigris
