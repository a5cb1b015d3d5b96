#include "apply.hpp"

#include <cctype>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "core/visible_text.hpp"

namespace tigris::config {
namespace {

using nlohmann::json;

[[noreturn]] void unknown_key(const std::vector<Key>& keys, const std::string& source, const std::string& name,
                              const char* list_command) {
  const std::string best = nearest_name(keys, name);
  throw std::invalid_argument(
      source + ": unknown key '" + visible_text(name) + "'" +
      (best.empty() ? " (" + std::string(list_command) + " lists every key)" : " (did you mean '" + best + "'?)"));
}

[[noreturn]] void key_error(const std::string& source, const Key& k, const std::string& what) {
  throw std::invalid_argument(source + ": '" + k.name + "' " + what);
}

// A named value is written by its name on the command line: "-1" is not "auto", and "-0" of a
// key that takes no negative number is not "off" either.
void check_sign_and_names(const Key& k, const std::string& text, double x, const std::string& source) {
  const Allowed& a = k.spec.allowed;
  for (const auto& n : a.names)
    if (x == n.value && (x < a.lo || x > a.hi || (a.lo_open && x == a.lo)))
      key_error(source, k,
                "= " + text + " is out of range (" + describe(k) + "); write '" + n.name + "' for " + n.name);
  if (!text.empty() && text[0] == '-' && x == 0 && a.lo >= 0)  // "-0": the range would take it as 0
    key_error(source, k, "= " + text + " is out of range (" + describe(k) + "): no negative value");
}

// A --set value as the JSON value a file would hold, per the key's type; the value's range is
// then checked on the file's path.
json parse_text(const Key& k, const std::string& text, const std::string& source) {
  const auto fail = [&](const std::string& expected) -> json {
    key_error(source, k, "must be " + expected + ", got '" + visible_text(text) + "'");
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
    case Type::Enum: return text;
    case Type::Number: {
      for (const auto& n : names)
        if (text == n.name) return text;
      // Decimal numbers only: strtod would also take hex ("0x10"), "inf" and "nan".
      std::string number = "a decimal number";
      for (const auto& n : names) number += " or '" + n.name + "'";
      if (text.find_first_not_of("0123456789.eE+-") != std::string::npos) return fail(number);
      char* end = nullptr;
      errno = 0;
      const double x =
          text.empty() || std::isspace(static_cast<unsigned char>(text[0])) ? 0.0 : std::strtod(first, &end);
      // ERANGE on underflow still gives the nearest number (a denormal, or 0): the range decides.
      if (end != last || (errno == ERANGE && std::abs(x) == HUGE_VAL)) return fail(number);
      check_sign_and_names(k, text, x, source);
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
        return fail(!is_int         ? std::string("a whole number of bytes")
                    : names.empty() ? std::string("an integer")
                                    : "an integer or '" + names[0].name + "'");
      if (is_int) check_sign_and_names(k, text, static_cast<double>(i), source);
      return is_int ? json(i) : json(u);
    }
  }
  throw std::logic_error("unhandled configuration key type");
}

void apply_object(const std::vector<Key>& keys, const Setter& set, const json& obj, const std::string& prefix,
                  const std::string& source, const char* list_command) {
  for (const auto& [name, v] : obj.items()) {
    if (name.rfind("//", 0) == 0) continue;  // a comment
    const std::string path = prefix.empty() ? name : prefix + "." + name;
    if (const Key* k = find_key(keys, path)) {
      set(*k, checked(*k, v, source));
    } else if (const Key* first = first_in_block(keys, path)) {
      if (!v.is_object())
        throw std::invalid_argument(source + ": '" + path +
                                    "' is a block and must be a JSON object of its keys (e.g. '" + first->name +
                                    "'), got " + shown(v));
      apply_object(keys, set, v, path, source, list_command);
    } else {
      unknown_key(keys, source, path, list_command);
    }
  }
}

// A Markdown table cell: '|' escaped.
std::string cell(std::string s) {
  for (std::size_t i = s.find('|'); i != std::string::npos; i = s.find('|', i + 2)) s.insert(i, "\\");
  return s;
}

// A value in the reference; byte counts of 1 KiB and more also in KiB or MiB.
std::string value_text(const json& v) {
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

}  // namespace

std::string shown(const json& v) {
  if (v.is_object()) return "an object";
  if (v.is_array()) return "an array";
  if (v.is_number_float() && !std::isfinite(v.get<double>())) return number_text(v.get<double>());
  // A --set value may hold any bytes: invalid UTF-8 is shown replaced, never thrown over.
  std::string s = visible_text(v.dump(-1, ' ', false, json::error_handler_t::replace));
  return s.size() > 40 ? s.substr(0, 37) + "..." : s;
}

json checked(const Key& k, const json& v, const std::string& source) {
  const Allowed& a = k.spec.allowed;
  const auto check_range = [&](double x) {
    for (const auto& n : a.names)
      if (x == n.value) return;  // a named value's number ("auto" = -1)
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
      if (v.is_string())
        for (const auto& n : a.names)
          if (v.get<std::string>() == n.name) return static_cast<double>(n.value);
      if (!v.is_number()) {
        std::string names;
        for (const auto& n : a.names) names += " or \"" + n.name + "\"";
        key_error(source, k, "must be a number" + names + ", got " + shown(v));
      }
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

void apply_json(const std::vector<Key>& keys, const Setter& set, const json& j, const std::string& source,
                const char* list_command) {
  if (!j.is_object())
    throw std::invalid_argument(source + ": a configuration must be a JSON object nested by block, got " + shown(j));
  apply_object(keys, set, j, "", source, list_command);
}

void apply_setting(const std::vector<Key>& keys, const Setter& set, const std::string& assignment,
                   const std::string& source, const char* list_command, const char* example) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos) throw std::invalid_argument(source + ": expected key=value, e.g. " + example);
  const std::string name = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  if (name.empty()) throw std::invalid_argument(source + ": missing key before '='");
  const Key* k = find_key(keys, name);
  if (!k) {
    if (const Key* first = first_in_block(keys, name))
      throw std::invalid_argument(source + ": '" + name + "' is a block, not a key; set its keys, e.g. '" +
                                  first->name + "'");
    unknown_key(keys, source, name, list_command);
  }
  if (text.empty()) throw std::invalid_argument(source + ": missing value for '" + name + "'");
  json nested = json::object();  // {"fe": {"recursion_units": 32}}, as a file would hold it
  nested[pointer(name)] = parse_text(*k, text, source);
  apply_json(keys, set, nested, source, list_command);
}

std::string reference_markdown(const std::vector<Key>& keys, const Getter& value, const std::string& value_heading) {
  std::string s = "| key | " + value_heading + " | unit | allowed | meaning |\n|---|---|---|---|---|\n";
  for (const Key& k : keys)
    s += "| `" + k.name + "` | " + cell(value_text(value(k))) + " | " + cell(k.spec.unit) + " | " + cell(describe(k)) +
         " | " + cell(k.spec.doc) + " |\n";
  return s;
}

json reference_json(const std::vector<Key>& keys, const Getter& value) {
  static const char* const type_names[] = {"integer", "bytes", "number", "bool", "enum"};
  json out = json::array();
  for (const Key& k : keys) {
    const Allowed& a = k.spec.allowed;
    json j = {{"key", k.name},
              {"type", type_names[static_cast<int>(k.type)]},
              {"unit", k.spec.unit},
              {"default", value(k)},
              {"doc", k.spec.doc}};
    if (k.type == Type::Enum) {
      j["values"] = json::array();
      for (const auto& n : a.names) j["values"].push_back(n.name);
    } else if (k.type != Type::Bool) {
      // JSON has no infinity: an open end is left out.
      if (std::isfinite(a.lo)) j[a.lo_open ? "above" : "min"] = a.lo;
      if (std::isfinite(a.hi)) j["max"] = a.hi;
      for (const auto& n : a.names) j["named"][n.name] = n.value;
    }
    out.push_back(j);
  }
  return {{"keys", out}};
}

}  // namespace tigris::config
