// What a run read, so that a result can be traced to its inputs: stats.json's "inputs", each
// file's role, path, size and SHA-256 (the digest `sha256sum` prints), or the name of a
// built-in workload.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/digest.hpp"  // sha256_of_file, sha256_of_text, input_file, builtin_input

namespace tigris {

// What made an output that is not stats.json (a VCD, a GTKWave save file, a timeline):
// {"command_line", "inputs", "config_sha256" (of config.dump()), "commit"}.
nlohmann::json provenance_json(const std::string& command_line, const nlohmann::json& inputs,
                               const nlohmann::json& config);
// The same as short lines for a text header: "command tigris run ...", "cloud a.bin (sha256
// 0123abcd4567)", "config sha256 ...", "commit ...".
std::vector<std::string> provenance_lines(const nlohmann::json& provenance);

// The inputs of a search run: cloud and queries (files, or the built-in names when the paths
// are empty; queries of a cloud alone are the cloud itself), then the configuration file.
nlohmann::json search_inputs(const std::string& cloud_path, const std::string& queries_path,
                             const std::string& cloud_name, const std::string& queries_name,
                             const std::string& config_path);

// "  inputs  cloud a.bin (1.8 MB, sha256 0123abcd4567), queries ..." lines for the summary.
std::string inputs_summary(const nlohmann::json& inputs);

}  // namespace tigris
