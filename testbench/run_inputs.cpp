#include "run_inputs.hpp"

#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <vector>

#include "core/build_info.hpp"
#include "core/input_file.hpp"

namespace tigris {

nlohmann::json provenance_json(const std::string& command_line, const nlohmann::json& inputs,
                               const nlohmann::json& config) {
  return {{"command_line", command_line},
          {"inputs", inputs},
          {"config_sha256", sha256_of_text(config.dump())},
          {"commit", build_commit()}};
}

std::vector<std::string> provenance_lines(const nlohmann::json& p) {
  std::vector<std::string> lines{"command " + p.value("command_line", std::string())};
  for (const auto& in : p.value("inputs", nlohmann::json::array())) {
    const std::string role = in.value("role", std::string("input"));
    if (in.contains("builtin"))
      lines.push_back(role + " " + in["builtin"].get<std::string>() + ", built in");
    else if (in.contains("same_as"))
      lines.push_back(role + " the " + in["same_as"].get<std::string>() + " itself");
    else
      lines.push_back(role + " " + in.value("path", std::string()) + " (sha256 " +
                      in.value("sha256", std::string()).substr(0, 12) + ")");
  }
  lines.push_back("config sha256 " + p.value("config_sha256", std::string()).substr(0, 12) +
                  " (of the configuration stats.json records)");
  lines.push_back("commit " + p.value("commit", std::string()));
  return lines;
}

nlohmann::json search_inputs(const std::string& cloud_path, const std::string& queries_path,
                             const std::string& cloud_name, const std::string& queries_name,
                             const std::string& config_path) {
  nlohmann::json j = nlohmann::json::array();
  j.push_back(cloud_path.empty() ? builtin_input("cloud", cloud_name) : input_file("cloud", cloud_path));
  if (!queries_path.empty())
    j.push_back(input_file("queries", queries_path));
  else if (cloud_path.empty())
    j.push_back(builtin_input("queries", queries_name));
  else
    j.push_back({{"role", "queries"}, {"same_as", "cloud"}});
  if (!config_path.empty()) j.push_back(input_file("config", config_path));
  return j;
}

std::string inputs_summary(const nlohmann::json& inputs) {
  std::string out;
  for (const auto& in : inputs) {
    const std::string role = in.at("role").get<std::string>();
    char line[1024];
    if (in.contains("builtin"))
      std::snprintf(line, sizeof line, "  %-7s %s, built in\n", role.c_str(), in["builtin"].get<std::string>().c_str());
    else if (in.contains("same_as"))
      std::snprintf(line, sizeof line, "  %-7s the %s itself\n", role.c_str(),
                    in["same_as"].get<std::string>().c_str());
    else
      std::snprintf(line, sizeof line, "  %-7s %s (%.4g MB, sha256 %.12s)\n", role.c_str(),
                    in["path"].get<std::string>().c_str(), in["bytes"].get<double>() * 1e-6,
                    in["sha256"].get<std::string>().c_str());
    out += line;
  }
  return out;
}

}  // namespace tigris
