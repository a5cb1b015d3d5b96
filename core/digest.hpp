// SHA-256 digests (the digest `sha256sum` prints): every input a command reads is recorded by
// it, and checked again before the results are written (out_folder.hpp).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace tigris {

// Hex SHA-256 of a file's bytes; std::invalid_argument naming the file when it cannot be read.
std::string sha256_of_file(const std::string& path);

// Hex SHA-256 of a text (a configuration's JSON: its digest).
std::string sha256_of_text(const std::string& text);

// The record of an input (stats.json's "inputs", the output folder's manifest): {"role", "path",
// "bytes", "sha256"} of a file, checked as every input is (input_file.hpp).
nlohmann::json input_file(const std::string& role, const std::string& path);
// {"role", "builtin"}: a workload made by the program (the synthetic frames).
nlohmann::json builtin_input(const std::string& role, const std::string& name);

}  // namespace tigris
