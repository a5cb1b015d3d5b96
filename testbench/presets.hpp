// Named accelerator configurations (docs/cli.md, "Presets"): presets/NAME.json in the source,
// PREFIX/share/tigris/presets/ beside the binary. A preset is an ordinary configuration file
// whose "//preset" member (a comment to the configuration reader) says why it exists and, when
// it is one of `tigris reproduce --variants`' design variants ("variant"), which experiments it
// can change and the leader width of its approximate runs (tigris/reports/variants.py reads the same files). So
// `--config paper` and `--config presets/paper.json` run the same machine.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tigris {

// PREFIX/share/tigris/presets for this binary.
std::string presets_dir();
// The presets' names in `dir` (default: presets_dir()), sorted.
std::vector<std::string> preset_names(const std::string& dir = presets_dir());

// A --config value: a name without '/' that does not end in ".json" is a preset and becomes its
// file's path; anything else is a file path and stays as given. An unknown name is a
// std::invalid_argument listing the presets (with the nearest one).
std::string config_path(const std::string& value);
// The same with the presets in `dir` (a program outside PREFIX/bin: find_package(TigrisTLM)
// gives TigrisTLM_PRESETS_DIR).
std::string config_path(const std::string& value, const std::string& dir);

// One preset for `tigris presets` and the Python tools: name, file, why, "sets" (every dotted key
// the file gives), "changes" (those differing from the built-in defaults: {key: [default, value]})
// and "variant" (experiments, leader_width) when the preset is one of reproduce's design variants. Errors name the
// file.
nlohmann::json describe_preset(const std::string& name);

}  // namespace tigris
