// JSON apply and dump of the configuration: files and --set share one apply path
// (apply_config_json), which checks each value against its key's spec.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "config.hpp"
#include "config_keys.hpp"
#include "sw_ref/json_file.hpp"
#include "sw_ref/visible_text.hpp"

namespace tigris {
namespace {

using config_table::describe;
using config_table::Key;
using config_table::Type;
using hw::AcceleratorConfig;
using nlohmann::json;

[[noreturn]] void unknown_key(const std::string& source, const std::string& name) {
  const std::string best = config_table::nearest_name(name);
  throw std::invalid_argument(source + ": unknown key '" + visible_text(name) + "'" +
                              (best.empty() ? " (tigris run --list-config lists every key)"
                                            : " (did you mean '" + best + "'?)"));
}

[[noreturn]] void key_error(const std::string& source, const Key& k, const std::string& what) {
  throw std::invalid_argument(source + ": '" + k.name + "' " + what);
}

std::string shown(const json& v) {
  if (v.is_object()) return "an object";
  if (v.is_array()) return "an array";
  if (v.is_number_float() && !std::isfinite(v.get<double>()))
    return config_table::number_text(v.get<double>());
  // A --set value may hold any bytes: invalid UTF-8 is shown replaced, never thrown over.
  std::string s = v.dump(-1, ' ', false, json::error_handler_t::replace);
  return s.size() > 40 ? s.substr(0, 37) + "..." : s;
}

// Checks a value against its key's type and allowed values; returns it as config_table::set
// takes it ("full" -> -1). Errors start with `source`.
json checked(const Key& k, const json& v, const std::string& source) {
  const hw::Allowed& a = k.spec.allowed;
  const auto check_range = [&](double x) {
    if (x < a.lo || (a.lo_open && x == a.lo) || x > a.hi)
      key_error(source, k, "= " + shown(v) + " is out of range (" + describe(k) + ")");
  };
  switch (k.type) {
    case Type::Bool:
      if (!v.is_boolean()) key_error(source, k, "must be true or false, got " + shown(v));
      return v;
    case Type::Enum:
      if (v.is_string())
        for (const auto& n : a.names)
          if (v.get<std::string>() == n.name) return v;
      key_error(source, k, "must be one of " + describe(k) + ", got " + shown(v));
    case Type::Number: {
      if (!v.is_number()) key_error(source, k, "must be a number, got " + shown(v));
      const double x = v.get<double>();
      if (!std::isfinite(x)) key_error(source, k, "must be a finite number, got " + shown(v));
      check_range(x);
      return x;
    }
    case Type::Integer:
    case Type::Bytes: {
      if (v.is_string())
        for (const auto& n : a.names)
          if (v.get<std::string>() == n.name) return n.value;
      if (!v.is_number_integer()) {
        std::string names;
        for (const auto& n : a.names) names += " or \"" + n.name + "\"";
        key_error(source, k, "must be an integer" + names + ", got " + shown(v));
      }
      // Out-of-type values (negative bytes, ints beyond INT_MAX) are reported as out of range.
      const double x = v.is_number_unsigned() ? static_cast<double>(v.get<std::uint64_t>())
                                              : static_cast<double>(v.get<std::int64_t>());
      check_range(x);
      if (k.type == Type::Integer) {
        if (x > INT_MAX || x < INT_MIN) key_error(source, k, "= " + shown(v) + " is out of range");
        return v.get<std::int64_t>();
      }
      if (x < 0) key_error(source, k, "= " + shown(v) + " is out of range (>= 0)");
      return v.get<std::uint64_t>();
    }
  }
  throw std::logic_error("unhandled configuration key type");
}

// A --set value as the JSON value a file would hold, per the key's type; the value's range is
// then checked on the file's path.
json parse_text(const Key& k, const std::string& text, const std::string& source) {
  const auto fail = [&](const std::string& expected) -> json {
    key_error(source, k, "must be " + expected + ", got '" + text + "'");
  };
  const char* first = text.data();
  const char* last = first + text.size();
  const auto& names = k.spec.allowed.names;
  switch (k.type) {
    case Type::Bool:
      for (const char* t : {"true", "1", "on"})
        if (text == t) return true;
      for (const char* f : {"false", "0", "off"})
        if (text == f) return false;
      return fail("true/false/1/0/on/off");
    case Type::Enum:
      return text;
    case Type::Number: {
      // Decimal numbers only: strtod would also take hex ("0x10"), "inf" and "nan".
      if (text.find_first_not_of("0123456789.eE+-") != std::string::npos) return fail("a decimal number");
      char* end = nullptr;
      errno = 0;
      const double x = text.empty() || std::isspace(static_cast<unsigned char>(text[0]))
                           ? 0.0
                           : std::strtod(first, &end);
      // ERANGE on underflow still gives the nearest number (a denormal, or 0): the range decides.
      if (end != last || (errno == ERANGE && std::abs(x) == HUGE_VAL)) return fail("a number");
      return x;
    }
    case Type::Integer:
    case Type::Bytes: {
      for (const auto& n : names)
        if (text == n.name) return text;
      const bool is_int = k.type == Type::Integer;
      std::int64_t i = 0;
      std::uint64_t u = 0;
      const auto r = is_int ? std::from_chars(first, last, i) : std::from_chars(first, last, u);
      if (r.ec == std::errc::result_out_of_range && r.ptr == last)
        key_error(source, k, "= " + text + " is out of range (" + describe(k) + ")");
      if (r.ec != std::errc() || r.ptr != last || text.empty())
        return fail(!is_int          ? std::string("a whole number of bytes")
                    : names.empty() ? std::string("an integer")
                                    : "an integer or '" + names[0].name + "'");
      return is_int ? json(i) : json(u);
    }
  }
  throw std::logic_error("unhandled configuration key type");
}

void apply_object(AcceleratorConfig& cfg, const json& obj, const std::string& prefix,
                  const std::string& source) {
  for (const auto& [name, v] : obj.items()) {
    if (name.rfind("//", 0) == 0) continue;  // a comment
    const std::string path = prefix.empty() ? name : prefix + "." + name;
    if (const Key* k = config_table::find_key(path)) {
      config_table::set(cfg, *k, checked(*k, v, source));
    } else if (const Key* first = config_table::first_in_block(path)) {
      if (!v.is_object())
        throw std::invalid_argument(source + ": '" + path +
                                    "' is a block and must be a JSON object of its keys (e.g. '" +
                                    first->name + "'), got " + shown(v));
      apply_object(cfg, v, path, source);
    } else {
      unknown_key(source, path);
    }
  }
}

}  // namespace

void apply_config_json(AcceleratorConfig& cfg, const json& j, const std::string& source) {
  if (!j.is_object())
    throw std::invalid_argument(
        source + ": a configuration must be a JSON object nested by block, got " + shown(j));
  apply_object(cfg, j, "", source);
}

void apply_config_file(AcceleratorConfig& cfg, const std::string& path) {
  apply_config_json(cfg, read_json_file(path), path);
}

void apply_config_text(AcceleratorConfig& cfg, const std::string& text, const std::string& source) {
  apply_config_json(cfg, parse_json_text(text, source), source);
}

void apply_setting(AcceleratorConfig& cfg, const std::string& assignment) {
  const std::string source = "--set '" + assignment + "'";
  const auto eq = assignment.find('=');
  if (eq == std::string::npos)
    throw std::invalid_argument(source + ": expected key=value, e.g. fe.recursion_units=32");
  const std::string name = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  if (name.empty()) throw std::invalid_argument(source + ": missing key before '='");
  const Key* k = config_table::find_key(name);
  if (!k) {
    if (const Key* first = config_table::first_in_block(name))
      throw std::invalid_argument(source + ": '" + name +
                                  "' is a block, not a key; set its keys, e.g. '" + first->name +
                                  "'");
    unknown_key(source, name);
  }
  if (text.empty()) throw std::invalid_argument(source + ": missing value for '" + name + "'");
  json nested = json::object();  // {"fe": {"recursion_units": 32}}, as a file would hold it
  nested[config_table::pointer(name)] = parse_text(*k, text, source);
  apply_config_json(cfg, nested, source);
}

json config_to_json(const AcceleratorConfig& cfg) {
  json j = json::object();
  for (const Key& k : config_table::keys())
    j[config_table::pointer(k.name)] = config_table::get(cfg, k);
  return j;
}

void validate_config(const AcceleratorConfig& cfg) {
  const std::string source = "invalid configuration";
  for (const Key& k : config_table::keys())
    checked(k, config_table::get(cfg, k), source);  // per-key type and range
  // Cross-field rules: {key to blame, holds, explanation}. Whether a job fits the buffers (its
  // tree image, queries, stack and results) is hw::job_fit_error's to say, once.
  const auto holds_one = [&](const hw::SramConfig& b) {
    return b.bytes >= static_cast<std::uint64_t>(b.word_bytes);
  };
  const struct {
    const char* key;
    bool ok;
    std::string why;
  } rules[] = {
      {"sram.points.bytes", holds_one(cfg.sram.points), "holds no word of sram.points.word_bytes"},
      {"sram.queries.bytes", holds_one(cfg.sram.queries),
       "holds no word of sram.queries.word_bytes"},
      {"sram.query_stack.bytes", holds_one(cfg.sram.query_stack),
       "holds no word of sram.query_stack.word_bytes"},
      {"sram.results.bytes", holds_one(cfg.sram.results),
       "holds no word of sram.results.word_bytes"},
      {"result_buffer.leader_fraction",
       cfg.result_buffer.slot_fraction + cfg.result_buffer.leader_fraction < 1.0,
       "plus result_buffer.slot_fraction must stay below 1: the result stream needs the rest"},
  };
  for (const auto& r : rules)
    if (!r.ok) throw std::invalid_argument(source + ": '" + r.key + "' " + r.why);
}

}  // namespace tigris
