// SHA-256 digests (the digest `sha256sum` prints): every input a command reads is recorded by
// it, and checked again before the results are written (out_folder.hpp).
#pragma once

#include <string>

namespace tigris {

// Hex SHA-256 of a file's bytes; std::invalid_argument naming the file when it cannot be read.
std::string sha256_of_file(const std::string& path);

// Hex SHA-256 of a text (a configuration's JSON: its digest).
std::string sha256_of_text(const std::string& text);

}  // namespace tigris
