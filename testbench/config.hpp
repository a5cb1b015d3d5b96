// Configuration as data (docs/cli.md): JSON files nested by block and `--set a.b=v`
// onto hw::AcceleratorConfig. Each key (field, unit, allowed values, doc) is declared once, at
// its field in hw/config.hpp; config_keys.cpp builds the key table from it, config_json.cpp
// applies and dumps JSON (a --set becomes a one-key file), config_reference.cpp renders the
// table. Every error is a std::invalid_argument whose message names its source (the file path
// or the --set text) and the dotted key.
//
// File format: a JSON object nested by block, e.g.
//   {"fe": {"recursion_units": 32}, "sram": {"points": {"bytes": 2097152}}}
// Keys left out keep their current value; unknown keys are an error. Integer keys take JSON
// integers only (1.5 is an error), number keys take any number, bytes keys take whole numbers
// >= 0, `tree.top_height` also takes "full" (stored as -1), `sim.sampling` "off" and "auto". A member whose name starts
// with "//" is a comment and is ignored. presets/paper.json writes out every hardware key (the paper's configuration,
// equal to the defaults); `config_reference()` lists them with units and meaning.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hw/config.hpp"

namespace tigris {

// Applies a JSON object nested by block onto cfg, checking each key's type and range (not the
// cross-field rules: call validate_config once everything is applied). `source` names the input
// in error messages, e.g. "my.json: unknown key 'fe.recursion_unit' (did you mean
// 'fe.recursion_units'?)".
void apply_config_json(hw::AcceleratorConfig& cfg, const nlohmann::json& j, const std::string& source);

// Reads and applies a configuration file; a missing file or a JSON syntax error (with its line
// and column) is a std::invalid_argument naming the file.
void apply_config_file(hw::AcceleratorConfig& cfg, const std::string& path);

// The same for the file's text; `source` names it in messages (the fuzz target uses it).
void apply_config_text(hw::AcceleratorConfig& cfg, const std::string& text, const std::string& source);

// Applies one `--set key=value`; the value is parsed per the key's type (bools: true/false/1/0/
// on/off; tree.top_height: a number or "full"). Errors name the --set text.
void apply_setting(hw::AcceleratorConfig& cfg, const std::string& assignment, const std::string& source = "");

// The full effective configuration, nested by block, every key (tree.top_height as an integer,
// -1 for full height). apply_config_json of it onto any config gives back cfg.
nlohmann::json config_to_json(const hw::AcceleratorConfig& cfg);

// Markdown table of every key: key, default, unit, allowed values, meaning (for
// `tigris run --list-config`).
std::string config_reference();

// The same as JSON for tools: {"keys": [{key, type (integer, bytes, number, bool, enum), unit,
// default, doc, and min / above (exclusive) / max, named values, or an enum's values}]}.
nlohmann::json config_reference_json();

// Every dotted key, in declaration order (hw::AcceleratorConfig::visit).
std::vector<std::string> config_keys();

// Per-key ranges plus cross-field rules (FQQ and SRAMs hold at least one entry, the Query Stack
// holds at least one query's stack, ...); std::invalid_argument naming the key.
void validate_config(const hw::AcceleratorConfig& cfg);

}  // namespace tigris
