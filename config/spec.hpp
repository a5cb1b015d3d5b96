// What a configuration key is, declared once at its field: each configuration block has a
// `template <class V> void visit(V&& v)` calling v(name, field, Spec{unit, allowed, doc}) for
// each field. The accelerator's (hw/config.hpp) and the registration pipeline's
// (registration/pipeline_config.hpp) configurations both do; config/key_table.hpp builds
// their JSON keys, checks, dump and reference from these visits alone.
#pragma once

#include <initializer_list>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace tigris::config {

// A value with a name: "full" = -1 for tree.top_height, "auto" = -1 for sim.sampling, or an enum
// value (by its to_string).
struct Named {
  std::string name;
  int value;
};

// The values a key accepts. Numbers: lo..hi, lo excluded when lo_open; integer and number keys
// also take their named values. Enum keys take their named values only.
struct Allowed {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  std::vector<Named> names;
};

struct Spec {
  std::string unit;  // "-" when the key has none
  Allowed allowed;
  std::string doc;  // the key's meaning: the one place it is documented
};

inline Allowed in(double lo, double hi) { return Allowed{lo, hi, false, {}}; }
inline Allowed at_least(double lo) { return in(lo, std::numeric_limits<double>::infinity()); }
inline Allowed above(double lo, double hi) { return Allowed{lo, hi, true, {}}; }
inline Allowed boolean() { return Allowed{}; }
inline Allowed named(Allowed a, std::string name, int value) {
  a.names.push_back({std::move(name), value});
  return a;
}
// An enum key: every value it takes, named by the enum's to_string (found by ADL).
template <class E>
Allowed one_of(std::initializer_list<E> values) {
  Allowed a;
  for (E e : values) a.names.push_back({to_string(e), static_cast<int>(e)});
  return a;
}

// Visits a nested block's keys under "block." (sram.points.bytes).
template <class V>
struct InBlock {
  V& v;
  std::string prefix;
  template <class T>
  void operator()(const std::string& name, T& field, const Spec& spec) {
    v(prefix + name, field, spec);
  }
};
template <class V>
InBlock<V> in_block(V& v, const std::string& block) {
  return {v, block + "."};
}

}  // namespace tigris::config
