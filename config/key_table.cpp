#include "key_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/edit_distance.hpp"

namespace tigris::config {

const Key* find_key(const std::vector<Key>& keys, const std::string& name) {
  for (const Key& k : keys)
    if (k.name == name) return &k;
  return nullptr;
}

const Key* first_in_block(const std::vector<Key>& keys, const std::string& block) {
  for (const Key& k : keys)
    if (k.name.size() > block.size() && k.name.compare(0, block.size(), block) == 0 && k.name[block.size()] == '.')
      return &k;
  return nullptr;
}

std::string nearest_name(const std::vector<Key>& keys, const std::string& name) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, name.size() / 3) + 1;
  const auto consider = [&](const std::string& candidate) {
    const std::size_t d = edit_distance(name, candidate);
    if (d < best_d) best_d = d, best = candidate;
  };
  for (const Key& k : keys) {
    consider(k.name);
    for (std::size_t dot = k.name.find('.'); dot != std::string::npos; dot = k.name.find('.', dot + 1))
      consider(k.name.substr(0, dot));
  }
  return best;
}

nlohmann::json::json_pointer pointer(const std::string& name) {
  std::string p = "/" + name;
  std::replace(p.begin(), p.end(), '.', '/');
  return nlohmann::json::json_pointer(p);
}

std::string number_text(double x) {
  if (std::isfinite(x) && x == std::floor(x) && std::fabs(x) < 1e15) return std::to_string(static_cast<long long>(x));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

std::string describe(const Key& k) {
  const Allowed& a = k.spec.allowed;
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

}  // namespace tigris::config
