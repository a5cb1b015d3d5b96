// Reading a configuration file as JSON, the same way for the accelerator's and the pipeline's
// configurations: every error names the file (a folder, a missing file, a syntax error with
// line and column, a number beyond double such as 1e400), and a key given twice in one object
// is an error (the JSON library would keep the last one silently).
#pragma once

#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "input_file.hpp"
#include "visible_text.hpp"

namespace tigris {

// Parses `text`; errors are std::invalid_argument starting with `source`. Json:
// nlohmann::ordered_json keeps the file's key order.
template <class Json = nlohmann::json>
Json parse_json_text(const std::string& text, const std::string& source, bool ignore_comments = false) {
  using json = Json;
  std::vector<std::set<std::string>> keys;  // the keys seen in each open object
  const typename json::parser_callback_t check = [&](int depth, typename json::parse_event_t event, json& parsed) {
    if (depth > 512) throw std::invalid_argument(source + ": JSON nested deeper than 512 levels; not a tigris file");
    if (event == json::parse_event_t::object_start) keys.emplace_back();
    if (event == json::parse_event_t::object_end && !keys.empty()) keys.pop_back();
    if (event == json::parse_event_t::key && !keys.empty() &&
        !keys.back().insert(parsed.template get<std::string>()).second)
      throw std::invalid_argument(source + ": key '" + visible_text(parsed.template get<std::string>()) +
                                  "' appears twice in one object; give each key once");
    return true;
  };
  try {
    return json::parse(text, check, true, ignore_comments);
  } catch (const typename json::exception& e) {
    // parse_error (syntax, with line and column), out_of_range (1e400): drop the library's tag.
    std::string what = e.what();
    const auto bracket = what.find("] ");
    if (bracket != std::string::npos) what.erase(0, bracket + 2);
    throw std::invalid_argument(source + ": JSON " + visible_text(what));
  }
}

// Reads and parses a file through the one input opener; errors name it.
inline nlohmann::json read_json_file(const std::string& path, bool ignore_comments = false) {
  std::string text;
  try {
    text = read_input(path, "configuration file", kMaxSettingsBytes);
  } catch (const std::exception& e) {  // a configuration's errors are std::invalid_argument
    throw std::invalid_argument(e.what());
  }
  return parse_json_text(text, path, ignore_comments);
}

}  // namespace tigris
