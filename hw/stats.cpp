#include "stats.hpp"

#include <algorithm>
#include <stdexcept>

namespace tigris::hw {

namespace {

nlohmann::json::json_pointer pointer(const std::string& dotted) {
  std::string p = "/" + dotted;
  std::replace(p.begin(), p.end(), '.', '/');
  return nlohmann::json::json_pointer(p);
}

}  // namespace

StatGroup::StatGroup(std::string name, std::string kind, std::string description)
    : name_(std::move(name)), kind_(std::move(kind)), description_(std::move(description)) {}

void StatGroup::reset() {
  for (Counter* c : counters_) c->reset();
  for (CounterArray* a : arrays_) a->reset();
  for (StatGroup* g : children_) g->reset();
}

template <class F>
void StatGroup::walk_values(F&& f) const {
  const auto kind = [](const std::string& unit) { return unit == "cycles" ? ValueKind::Cycles : ValueKind::Sum; };
  for (Counter* c : counters_) f(c->value_, c->merge() == Counter::Merge::Max ? ValueKind::Maximum : kind(c->unit()));
  for (CounterArray* a : arrays_)
    for (std::uint64_t& x : a->values_) f(x, kind(a->unit()));
  for (const StatGroup* g : children_) g->walk_values(f);
}

std::vector<std::uint64_t> StatGroup::values() const {
  std::vector<std::uint64_t> out;
  walk_values([&](std::uint64_t x, ValueKind) { out.push_back(x); });
  return out;
}

void StatGroup::set_values(const std::vector<std::uint64_t>& values) {
  std::size_t i = 0;
  walk_values([&](std::uint64_t& x, ValueKind) { x = values.at(i++); });
  if (i != values.size()) throw std::logic_error("StatGroup::set_values: the snapshot is of another tree");
}

std::vector<StatGroup::ValueKind> StatGroup::value_kinds() const {
  std::vector<ValueKind> out;
  walk_values([&](std::uint64_t, ValueKind k) { out.push_back(k); });
  return out;
}

nlohmann::json StatGroup::counters_json() const {
  nlohmann::json j = nlohmann::json::object();
  for (const Counter* c : counters_) j[pointer(c->name())] = c->value();
  for (const CounterArray* a : arrays_) j[pointer(a->name())] = a->values();
  return j;
}

std::vector<const StatGroup*> StatGroup::find(const std::string& kind) const {
  std::vector<const StatGroup*> out;
  if (kind_ == kind) out.push_back(this);
  for (const StatGroup* g : children_) {
    const auto below = g->find(kind);
    out.insert(out.end(), below.begin(), below.end());
  }
  return out;
}

nlohmann::json StatGroup::sum(const std::vector<const StatGroup*>& groups) {
  nlohmann::json j = nlohmann::json::object();
  for (const StatGroup* g : groups)
    for (const Counter* c : g->counters_) {
      const auto p = pointer(c->name());
      const std::uint64_t old = j.contains(p) ? j[p].get<std::uint64_t>() : 0;
      j[p] = c->merge() == Counter::Merge::Max ? std::max(old, c->value()) : old + c->value();
    }
  for (const StatGroup* g : groups)
    for (const CounterArray* a : g->arrays_) {
      const auto p = pointer(a->name());
      std::vector<std::uint64_t> v =
          j.contains(p) ? j[p].get<std::vector<std::uint64_t>>() : std::vector<std::uint64_t>();
      v.resize(std::max(v.size(), a->values().size()), 0);
      for (std::size_t i = 0; i < a->values().size(); ++i) v[i] += a->values()[i];
      j[p] = v;
    }
  return j;
}

}  // namespace tigris::hw
