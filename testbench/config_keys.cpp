#include "config_keys.hpp"

#include "config.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <type_traits>

#include "sw_ref/edit_distance.hpp"

namespace tigris::config_table {
namespace {

using hw::AcceleratorConfig;
using nlohmann::json;

template <class T>
constexpr Type type_of() {
  if constexpr (std::is_same_v<T, bool>) return Type::Bool;
  else if constexpr (std::is_enum_v<T> || std::is_same_v<T, std::string>) return Type::Enum;
  else if constexpr (std::is_same_v<T, double>) return Type::Number;
  else if constexpr (std::is_same_v<T, std::uint64_t>) return Type::Bytes;
  else {
    static_assert(std::is_same_v<T, int>, "a configuration field is int, bool, double, "
                                          "std::uint64_t, an enum or a registered name (std::string)");
    return Type::Integer;
  }
}

// Calls f(field) on cfg's field of key k, found by visiting cfg.
template <class F>
void with_field(AcceleratorConfig& cfg, const Key& k, F&& f) {
  cfg.visit([&](const std::string& name, auto& field, const hw::Spec&) {
    if (name == k.name) f(field);
  });
}

}  // namespace

const std::vector<Key>& keys() {
  static const std::vector<Key> table = [] {
    std::vector<Key> t;
    AcceleratorConfig cfg;
    cfg.visit([&](const std::string& name, auto& field, const hw::Spec& spec) {
      t.push_back({name, type_of<std::remove_reference_t<decltype(field)>>(), spec});
    });
    return t;
  }();
  return table;
}

const Key* find_key(const std::string& name) {
  for (const Key& k : keys())
    if (k.name == name) return &k;
  return nullptr;
}

const Key* first_in_block(const std::string& block) {
  for (const Key& k : keys())
    if (k.name.size() > block.size() && k.name.compare(0, block.size(), block) == 0 &&
        k.name[block.size()] == '.')
      return &k;
  return nullptr;
}

std::string nearest_name(const std::string& name) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, name.size() / 3) + 1;
  const auto consider = [&](const std::string& candidate) {
    const std::size_t d = edit_distance(name, candidate);
    if (d < best_d) best_d = d, best = candidate;
  };
  for (const Key& k : keys()) {
    consider(k.name);
    for (std::size_t dot = k.name.find('.'); dot != std::string::npos;
         dot = k.name.find('.', dot + 1))
      consider(k.name.substr(0, dot));
  }
  return best;
}

json get(const AcceleratorConfig& cfg, const Key& k) {
  AcceleratorConfig copy = cfg;  // visit() hands out mutable fields; only read here
  json v;
  with_field(copy, k, [&](auto& field) {
    if constexpr (std::is_enum_v<std::remove_reference_t<decltype(field)>>) {
      v = "?";
      for (const auto& n : k.spec.allowed.names)
        if (n.value == static_cast<int>(field)) v = n.name;
    } else {
      v = field;
    }
  });
  return v;
}

void set(AcceleratorConfig& cfg, const Key& k, const json& v) {
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

json::json_pointer pointer(const std::string& name) {
  std::string p = "/" + name;
  std::replace(p.begin(), p.end(), '.', '/');
  return json::json_pointer(p);
}

std::string number_text(double x) {
  if (std::isfinite(x) && x == std::floor(x) && std::fabs(x) < 1e15)
    return std::to_string(static_cast<long long>(x));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

std::string describe(const Key& k) {
  const hw::Allowed& a = k.spec.allowed;
  if (k.type == Type::Bool) return "true, false";
  std::string s;
  if (k.type == Type::Enum) {
    for (const auto& n : a.names) s += (s.empty() ? "`" : ", `") + n.name + "`";
    return s;
  }
  for (const auto& n : a.names) s += "`" + n.name + "` (" + std::to_string(n.value) + "), ";
  if (a.lo_open)
    s += "> " + number_text(a.lo) + (std::isinf(a.hi) ? "" : ", <= " + number_text(a.hi));
  else if (std::isinf(a.hi))
    s += ">= " + number_text(a.lo);
  else
    s += number_text(a.lo) + ".." + number_text(a.hi);
  return s;
}

}  // namespace tigris::config_table

namespace tigris {

std::vector<std::string> config_keys() {
  std::vector<std::string> names;
  for (const config_table::Key& k : config_table::keys()) names.push_back(k.name);
  return names;
}

}  // namespace tigris
