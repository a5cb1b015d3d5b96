// `tigris presets`: the shipped accelerator configurations (testbench/presets.hpp), what each
// changes against the built-in defaults and why, for people (a table) and tools (--json).
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>

#include "command.hpp"
#include "testbench/presets.hpp"

namespace tigris {
namespace {

struct PresetsOptions {
  bool json = false;
  std::string show;
};

std::string shown(const nlohmann::json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); }

// Why the presets folder lists nothing: missing, a broken link, not a folder, unreadable.
std::string folder_problem(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status link = fs::symlink_status(dir, ec), target = fs::status(dir, ec);
  if (fs::is_symlink(link) && !fs::exists(target))
    return dir + " is a link to " + fs::read_symlink(dir, ec).string() + ", which does not exist";
  if (!fs::exists(target)) return dir + " does not exist (an install puts the presets in PREFIX/share/tigris/presets)";
  if (!fs::is_directory(target)) return dir + " is not a folder";
  fs::directory_iterator it(dir, ec);
  if (ec) return dir + " cannot be read: " + ec.message();
  return "";
}

int run_presets(const PresetsOptions& o) {
  nlohmann::json all = nlohmann::json::array();
  int broken = 0;  // one bad file is named, and the others are still listed
  const auto add = [&](const std::string& name) {
    try {
      all.push_back(describe_preset(name));
    } catch (const std::exception& e) {
      if (!o.show.empty()) throw;
      ++broken;
      std::fprintf(stderr, "tigris presets: the preset %s is left out: %s\n", name.c_str(), e.what());
      all.push_back({{"name", name}, {"error", e.what()}});
    }
  };
  if (!o.show.empty())
    add(o.show);
  else
    for (const std::string& name : preset_names()) add(name);
  if (o.json) {
    std::cout << nlohmann::json{{"dir", presets_dir()}, {"presets", all}}.dump(2) << '\n';
    return broken ? 1 : 0;
  }
  if (all.empty()) {
    const std::string problem = folder_problem(presets_dir());
    std::fprintf(stderr, "tigris presets: %s\n",
                 problem.empty() ? ("none installed in " + presets_dir()).c_str() : problem.c_str());
    return 1;
  }
  std::printf("Presets in %s (tigris run --config NAME; tigris presets --show NAME for one):\n\n",
              presets_dir().c_str());
  for (const nlohmann::json& p : all) {
    if (p.contains("error")) continue;  // said above
    std::string changes;
    for (auto it = p["changes"].begin(); it != p["changes"].end(); ++it)
      changes += (changes.empty() ? "" : ", ") + it.key() + " " + shown(it.value()[0]) + " -> " + shown(it.value()[1]);
    std::printf("%-14s %s\n", p["name"].get<std::string>().c_str(),
                changes.empty() ? "the built-in defaults" : changes.c_str());
    std::printf("%-14s %s\n", "", p["why"].get<std::string>().c_str());
    if (p.contains("cites") && p["cites"].is_object())
      for (auto it = p["cites"].begin(); it != p["cites"].end(); ++it)
        std::printf("%-14s   %s %s\n", "", it.key().c_str(),
                    it.value().is_string() ? it.value().get<std::string>().c_str() : "");
    if (p.contains("variant"))
      std::printf("%-14s a design variant of tigris reproduce --variants%s\n", "",
                  p["variant"].empty() ? "" : (": " + p["variant"].dump()).c_str());
  }
  return broken ? 1 : 0;
}

const CommandRegistration kRegistration{options_command<PresetsOptions>(
    "presets", "List the shipped accelerator configurations (tigris run --config NAME): what each changes and why", 45,
    [](CLI::App& app, PresetsOptions& o) {
      app.add_flag("--json", o.json, "Print them as JSON (name, file, why, every key each sets, the changes)");
      app.add_option("--show", o.show, "Only this preset");
    },
    [](const CLI::App&, PresetsOptions& o, const CommandLine&) { return run_presets(o); })};

}  // namespace
}  // namespace tigris
