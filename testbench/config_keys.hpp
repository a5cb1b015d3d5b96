// The key table of the configuration (internal to testbench/config_*.cpp): every dotted key of
// hw::AcceleratorConfig with its type and spec, built by visiting a config (hw/config_spec.hpp),
// and get/set of a key's field on any config.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hw/config.hpp"

namespace tigris::config_table {

// A key's JSON type, from its field's C++ type (std::uint64_t fields are byte counts).
enum class Type { Integer, Bytes, Number, Bool, Enum };

struct Key {
  std::string name;  // dotted: block.field or sram.buffer.field
  Type type;
  hw::Spec spec;
};

// Every key, in visit order.
const std::vector<Key>& keys();
const Key* find_key(const std::string& name);
// A block is a proper dotted prefix of some key ("fe", "sram", "sram.points"): its first key,
// or nullptr.
const Key* first_in_block(const std::string& block);
// The key or block nearest to a mistyped name, or "" when none is near.
std::string nearest_name(const std::string& name);

// A key's value as a file writes it (enums by name, tree.top_height as an integer).
nlohmann::json get(const hw::AcceleratorConfig& cfg, const Key& k);
// Sets a key's field from a value already checked against its type and range (enums by name).
void set(hw::AcceleratorConfig& cfg, const Key& k, const nlohmann::json& v);

// The JSON pointer of a dotted key: fe.recursion_units -> /fe/recursion_units.
nlohmann::json::json_pointer pointer(const std::string& name);

// A key's allowed values for messages and the reference: "1..4096", "> 0, <= 1", "`mqsn`,
// `mqmn`", "`full` (-1), -1..30", "true, false".
std::string describe(const Key& k);
// A number as people write it: 4096, 0.5, 1e+06.
std::string number_text(double x);

}  // namespace tigris::config_table
