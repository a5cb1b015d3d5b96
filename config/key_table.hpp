// The key table of a configuration type: every dotted key with its type and spec, built by
// visiting a default value (config/spec.hpp), and get/set of a key's field on any value of the
// type. A configuration type `C` offers:
//   template <class V> void visit(V&& v);    // v(dotted name, field, Spec) per key
//   static constexpr const char* kListCommand;  // the command that lists its keys
//   static constexpr const char* kSetExample;   // a --set example, "fe.recursion_units=32"
// Fields are int, bool, double, std::uint64_t (byte counts), an enum (named by one_of) or a
// std::string with named values (a registered policy).
#pragma once

#include <string>
#include <type_traits>
#include <vector>

#include <nlohmann/json.hpp>

#include "spec.hpp"

namespace tigris::config {

// A key's JSON type, from its field's C++ type (std::uint64_t fields are byte counts).
enum class Type { Integer, Bytes, Number, Bool, Enum };

struct Key {
  std::string name;  // dotted: block.field or sram.buffer.field
  Type type;
  Spec spec;
};

template <class T>
constexpr Type type_of() {
  if constexpr (std::is_same_v<T, bool>)
    return Type::Bool;
  else if constexpr (std::is_enum_v<T> || std::is_same_v<T, std::string>)
    return Type::Enum;
  else if constexpr (std::is_same_v<T, double>)
    return Type::Number;
  else if constexpr (std::is_same_v<T, std::uint64_t>)
    return Type::Bytes;
  else {
    static_assert(std::is_same_v<T, int>,
                  "a configuration field is int, bool, double, "
                  "std::uint64_t, an enum or a registered name (std::string)");
    return Type::Integer;
  }
}

// Every key of C, in visit order.
template <class C>
const std::vector<Key>& keys() {
  static const std::vector<Key> table = [] {
    std::vector<Key> t;
    C cfg;
    cfg.visit([&](const std::string& name, auto& field, const Spec& spec) {
      t.push_back({name, type_of<std::remove_reference_t<decltype(field)>>(), spec});
    });
    return t;
  }();
  return table;
}

const Key* find_key(const std::vector<Key>& keys, const std::string& name);
// A block is a proper dotted prefix of some key ("fe", "sram", "sram.points"): its first key,
// or nullptr.
const Key* first_in_block(const std::vector<Key>& keys, const std::string& block);
// The key or block nearest to a mistyped name, or "" when none is near.
std::string nearest_name(const std::vector<Key>& keys, const std::string& name);

// Calls f(field) on cfg's field of key k.
template <class C, class F>
void with_field(C& cfg, const Key& k, F&& f) {
  cfg.visit([&](const std::string& name, auto& field, const Spec&) {
    if (name == k.name) f(field);
  });
}

// A key's value as a file writes it (enums and a number key's named values by name,
// tree.top_height as an integer).
template <class C>
nlohmann::json get(const C& cfg, const Key& k) {
  C copy = cfg;  // visit() hands out mutable fields; only read here
  nlohmann::json v;
  with_field(copy, k, [&](auto& field) {
    if constexpr (std::is_enum_v<std::remove_reference_t<decltype(field)>>) {
      v = "?";
      for (const auto& n : k.spec.allowed.names)
        if (n.value == static_cast<int>(field)) v = n.name;
    } else if constexpr (std::is_same_v<std::remove_reference_t<decltype(field)>, double>) {
      v = field;  // a number key's named values ("off", "auto") are written by name
      for (const auto& n : k.spec.allowed.names)
        if (field == n.value) v = n.name;
    } else {
      v = field;
    }
  });
  return v;
}

// Sets a key's field from a value already checked against its type and range (enums by name).
template <class C>
void set(C& cfg, const Key& k, const nlohmann::json& v) {
  with_field(cfg, k, [&](auto& field) {
    using T = std::remove_reference_t<decltype(field)>;
    if constexpr (std::is_enum_v<T>) {
      for (const auto& n : k.spec.allowed.names)
        if (n.name == v.get<std::string>()) field = static_cast<T>(n.value);
    } else if constexpr (std::is_same_v<T, std::string>) {
      field = v.get<std::string>();
    } else {
      field = v.get<T>();
    }
  });
}

// The JSON pointer of a dotted key: fe.recursion_units -> /fe/recursion_units.
nlohmann::json::json_pointer pointer(const std::string& name);

// A key's allowed values for messages and the reference: "1..4096", "> 0, <= 1", "`mqsn`,
// `mqmn`", "`full` (-1), -1..30", "true, false".
std::string describe(const Key& k);
// A number as people write it: 4096, 0.5, 1e+06.
std::string number_text(double x);

}  // namespace tigris::config
