// Policies that register themselves (Ramulator 2's pattern): a policy's own file adds its name,
// meaning and factory to its kind's registry at start-up, e.g.
//   const bool registered = IssuePolicies::add("mqmn", "any query to any free PE", make);
// and everything else asks the registry: the configuration key's allowed values and meaning
// (hence --list-config, the docs and the sweep tools), and the factory the model calls.
// Files in hw/be/policies/ are found by CMake and linked whole, so nothing else names them.
#pragma once

#include <algorithm>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "config_spec.hpp"

namespace tigris::hw {

struct AcceleratorConfig;
class IssuePolicy;
class ReplacementPolicy;
class WalkEngine;

template <class Base>
class PolicyRegistry {
 public:
  using Factory = std::function<std::unique_ptr<Base>(const AcceleratorConfig&)>;
  struct Entry {
    std::string name, doc;
    Factory make;
  };
  // Registers a policy; returns true, so that a file can hold the result in a constant.
  static bool add(std::string name, std::string doc, Factory make) {
    auto& e = entries_mut();
    if (find(name)) return false;  // the same file linked twice; a name is registered once
    e.push_back({std::move(name), std::move(doc), std::move(make)});
    // By name: the listing does not depend on the order the linker ran the files' start-up.
    std::sort(e.begin(), e.end(), [](const Entry& a, const Entry& b) { return a.name < b.name; });
    return true;
  }
  static const std::vector<Entry>& entries() { return entries_mut(); }
  static const Entry* find(const std::string& name) {
    for (const Entry& e : entries())
      if (e.name == name) return &e;
    return nullptr;
  }
  // The configuration key's allowed values and meaning.
  static Allowed allowed() {
    Allowed a;
    for (std::size_t i = 0; i < entries().size(); ++i) a.names.push_back({entries()[i].name, static_cast<int>(i)});
    return a;
  }
  static std::string doc(const std::string& what) {
    std::string s = what + ": ";
    for (std::size_t i = 0; i < entries().size(); ++i)
      s += (i ? "; " : "") + entries()[i].name + " (" + entries()[i].doc + ")";
    return s;
  }

 private:
  static std::vector<Entry>& entries_mut() {
    static std::vector<Entry> e;
    return e;
  }
};

using IssuePolicies = PolicyRegistry<IssuePolicy>;
using ReplacementPolicies = PolicyRegistry<ReplacementPolicy>;
using RecursionUnitModels = PolicyRegistry<WalkEngine>;  // hw/fe/walk_engine.hpp

}  // namespace tigris::hw
