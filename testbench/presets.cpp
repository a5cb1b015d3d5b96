#include "presets.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "config.hpp"
#include "core/edit_distance.hpp"
#include "core/json_file.hpp"
#include "core/share_dir.hpp"

namespace tigris {

namespace fs = std::filesystem;

std::string presets_dir() { return (fs::path(share_dir()) / "presets").string(); }

namespace {

// Names with their numbers in numeric order: top-6 before top-10, nc-32k before nc-512k.
bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) && std::isdigit(static_cast<unsigned char>(b[j]))) {
      std::size_t ei = i, ej = j;
      while (ei < a.size() && std::isdigit(static_cast<unsigned char>(a[ei]))) ++ei;
      while (ej < b.size() && std::isdigit(static_cast<unsigned char>(b[ej]))) ++ej;
      const std::string na = a.substr(i, ei - i), nb = b.substr(j, ej - j);
      if (na.size() != nb.size()) return na.size() < nb.size();  // no leading zeros in names
      if (na != nb) return na < nb;
      i = ei, j = ej;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i, ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

}  // namespace

std::vector<std::string> preset_names(const std::string& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".json") names.push_back(it->path().stem().string());
  std::sort(names.begin(), names.end(), natural_less);
  return names;
}

namespace {

bool is_preset_name(const std::string& v) {
  const bool json_suffix = v.size() >= 5 && v.compare(v.size() - 5, 5, ".json") == 0;
  return !v.empty() && v.find('/') == std::string::npos && !json_suffix;
}

// Flattens {"a": {"b": 1}} to {"a.b": 1}, leaving "//" comments out.
void flatten(const nlohmann::json& j, const std::string& prefix, nlohmann::json& out) {
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (it.key().rfind("//", 0) == 0) continue;
    const std::string key = prefix.empty() ? it.key() : prefix + "." + it.key();
    if (it.value().is_object())
      flatten(it.value(), key, out);
    else
      out[key] = it.value();
  }
}

}  // namespace

std::string config_path(const std::string& value) { return config_path(value, presets_dir()); }

std::string config_path(const std::string& value, const std::string& dir) {
  if (!is_preset_name(value)) {
    // "paper.json" meant as the preset: say so rather than "no such file".
    const fs::path p(value);
    std::error_code ec;
    const std::vector<std::string> names = preset_names(dir);
    if (p.extension() == ".json" && !p.has_parent_path() && !fs::exists(p, ec) &&
        std::find(names.begin(), names.end(), p.stem().string()) != names.end())
      throw std::invalid_argument("no file " + value +
                                  " here; the preset is named without .json: " + p.stem().string());
    return value;
  }
  const std::vector<std::string> names = preset_names(dir);
  if (std::find(names.begin(), names.end(), value) != names.end()) {
    std::error_code ec;
    if (fs::exists(value, ec))
      std::fprintf(stderr,
                   "tigris: note: '%s' is the preset %s; the file %s in this folder is not read (name it ./%s "
                   "for the file)\n",
                   value.c_str(), value.c_str(), value.c_str(), value.c_str());
    return (fs::path(dir) / (value + ".json")).string();
  }
  std::string list, nearest;
  std::size_t best = 3;  // suggest only a near miss
  for (const std::string& n : names) {
    list += (list.empty() ? "" : ", ") + n;
    if (const std::size_t d = edit_distance(value, n); d < best) best = d, nearest = n;
  }
  if (names.empty())
    throw std::invalid_argument("'" + value + "' is no file path and no preset is installed (" + dir +
                                " is empty or missing); a file needs a '/' or a .json name");
  throw std::invalid_argument("no preset named '" + value + "'" +
                              (nearest.empty() ? "" : " (did you mean '" + nearest + "'?)") + "; presets: " + list +
                              " (tigris presets says what each changes); a file needs a '/' or a .json name");
}

nlohmann::json describe_preset(const std::string& name) {
  const std::string file = config_path(name);
  const nlohmann::json j = read_json_file(file, /*ignore_comments=*/true);
  hw::AcceleratorConfig cfg;
  apply_config_json(cfg, j, file);  // a preset must load, or it is no preset
  validate_config(cfg);
  nlohmann::json sets = nlohmann::json::object(), changes = nlohmann::json::object();
  flatten(j, "", sets);
  nlohmann::json defaults = nlohmann::json::object(), loaded = nlohmann::json::object();
  flatten(config_to_json(hw::AcceleratorConfig{}), "", defaults);
  flatten(config_to_json(cfg), "", loaded);
  for (auto it = loaded.begin(); it != loaded.end(); ++it)
    if (defaults.at(it.key()) != it.value()) changes[it.key()] = {defaults.at(it.key()), it.value()};
  nlohmann::json out = {{"name", name}, {"file", file}, {"sets", sets}, {"changes", changes}};
  const nlohmann::json meta = j.contains("//preset") ? j["//preset"] : nlohmann::json::object();
  out["why"] = meta.is_object() && meta.contains("why") ? meta["why"] : nlohmann::json("");
  if (meta.is_object() && meta.contains("variant")) out["variant"] = meta["variant"];
  // The paper's accounting: the sentence each switch follows, by key.
  if (meta.is_object() && meta.contains("accounting")) out["accounting"] = meta["accounting"];
  if (meta.is_object() && meta.contains("cites")) out["cites"] = meta["cites"];
  return out;
}

}  // namespace tigris
