// Configuration as data, one mechanism for every configuration type (config/key_table.hpp): JSON
// files nested by block, `--set a.b=v`, the dump and the reference, all built from the type's
// visit(). Files and --set share one path (a --set becomes a one-key file), so both check each
// value against its key's spec the same way. Every error is a std::invalid_argument whose
// message starts with its source (the file path, or the --set text) and names the dotted key;
// an unknown key gets the nearest valid name as a suggestion.
//
// File format: a JSON object nested by block, e.g. {"fe": {"recursion_units": 32}}; dotted keys
// ({"fe.recursion_units": 32}) are taken at any level too. Keys left out keep their value. Integer
// keys take JSON integers only (1.5 is an error), number keys any finite number, bytes keys whole
// numbers >= 0, enum keys their names; an integer key with named values (tree.top_height's
// "full") takes those names. Members whose name starts with "//", and // or /* */ comments, are
// ignored.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/json_file.hpp"
#include "key_table.hpp"

namespace tigris::config {

// The type-independent core (config/apply.cpp).
using Setter = std::function<void(const Key&, const nlohmann::json&)>;
using Getter = std::function<nlohmann::json(const Key&)>;
void apply_json(const std::vector<Key>& keys, const Setter& set, const nlohmann::json& j, const std::string& source,
                const char* list_command);
void apply_setting(const std::vector<Key>& keys, const Setter& set, const std::string& assignment,
                   const std::string& source, const char* list_command, const char* example);
// Checks a value against its key's type and allowed values; returns it as set() takes it
// ("full" -> -1). Errors start with `source`.
nlohmann::json checked(const Key& k, const nlohmann::json& v, const std::string& source);
std::string reference_markdown(const std::vector<Key>& keys, const Getter& value, const std::string& value_heading);
nlohmann::json reference_json(const std::vector<Key>& keys, const Getter& value);
// A value as an error message shows it (shortened; non-finite numbers and odd bytes readable).
std::string shown(const nlohmann::json& v);

// Applies a JSON object onto cfg, checking each key's type and range (not the rules across
// keys: the configuration type's own validate does that once everything is applied).
template <class C>
void apply_json(C& cfg, const nlohmann::json& j, const std::string& source) {
  apply_json(
      keys<C>(), [&](const Key& k, const nlohmann::json& v) { set(cfg, k, v); }, j, source, C::kListCommand);
}
// The same for a file's text, or a file (missing, unreadable or invalid: an error naming it).
template <class C>
void apply_text(C& cfg, const std::string& text, const std::string& source) {
  apply_json(cfg, parse_json_text(text, source, /*ignore_comments=*/true), source);
}
template <class C>
void apply_file(C& cfg, const std::string& path) {
  apply_json(cfg, read_json_file(path, /*ignore_comments=*/true), path);
}
// One `key=value`, the value parsed per the key's type (bools: true/false/1/0/on/off). Errors
// start with `source`, by default "--set 'key=value'" (a flag that sets a key names itself).
template <class C>
void apply_setting(C& cfg, const std::string& assignment, const std::string& source = "") {
  apply_setting(
      keys<C>(), [&](const Key& k, const nlohmann::json& v) { set(cfg, k, v); }, assignment,
      source.empty() ? "--set '" + assignment + "'" : source, C::kListCommand, C::kSetExample);
}
// Every key, nested by block (enums by name): apply_json of it onto any value gives back cfg.
template <class C>
nlohmann::json to_json(const C& cfg) {
  nlohmann::json j = nlohmann::json::object();
  for (const Key& k : keys<C>()) j[pointer(k.name)] = get(cfg, k);
  return j;
}
// Every key's type and range on a value built in code (not through apply_*).
template <class C>
void check_keys(const C& cfg, const std::string& source) {
  for (const Key& k : keys<C>()) checked(k, get(cfg, k), source);
}
// The reference of every key: a Markdown table (key, `value_heading` = cfg's value, unit, allowed
// values, meaning) for people, and JSON for tools: {"keys": [{key, type (integer, bytes, number,
// bool, enum), unit, default (cfg's value), doc, and min / above (exclusive) / max, named values,
// or an enum's values}]}.
template <class C>
std::string reference_markdown(const C& cfg, const std::string& value_heading = "default") {
  return reference_markdown(
      keys<C>(), [&](const Key& k) { return get(cfg, k); }, value_heading);
}
template <class C>
nlohmann::json reference_json(const C& cfg) {
  return reference_json(keys<C>(), [&](const Key& k) { return get(cfg, k); });
}

}  // namespace tigris::config
