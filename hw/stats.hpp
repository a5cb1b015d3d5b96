// Statistics as a tree (after DRAMSys): every unit owns a StatGroup, declares its counters at
// the field with their unit and meaning (`Counter busy{stats, "busy_cycles", "cycles", "..."}`)
// and registers the group with its parent's. The schema of the stats JSON (`tigris run
// --stats-schema`, docs/stats.md) is walked from these declarations.
// The root is walked into JSON; reset() at START clears the whole tree, so a second job on the
// same accelerator starts from zero. Sums over units of one kind are made in one place, sum().
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tigris::hw {

class Counter;
class CounterArray;

class StatGroup {
 public:
  // `kind` names what the group describes ("recursion_unit", "buffer", ...), so sums over
  // every unit of a kind need not know where the units sit in the tree.
  // `description` names the block for the schema when several groups share a kind ("Point
  // Buffer" for the buffer group "points").
  explicit StatGroup(std::string name, std::string kind = {}, std::string description = {});
  StatGroup(const StatGroup&) = delete;
  StatGroup& operator=(const StatGroup&) = delete;

  void add(StatGroup& child) { children_.push_back(&child); }
  const std::string& name() const { return name_; }
  const std::string& kind() const { return kind_; }
  const std::string& description() const { return description_; }
  const std::vector<Counter*>& counters() const { return counters_; }
  const std::vector<CounterArray*>& arrays() const { return arrays_; }
  const std::vector<StatGroup*>& children() const { return children_; }

  void reset();  // this group and every group below it
  // This group's counters and arrays; a dotted name nests ("stall_cycles.sram").
  nlohmann::json counters_json() const;
  // Every group of `kind` at or below this one, in tree order.
  std::vector<const StatGroup*> find(const std::string& kind) const;
  // Every counter and array element at or below this group in walk order (a snapshot; sampled
  // simulation differences two), and the same list written back.
  std::vector<std::uint64_t> values() const;
  void set_values(const std::vector<std::uint64_t>& values);
  // Per entry of values(): a maximum (Counter::Merge::Max, not a sum of work), cycles (busy or
  // stall time), or another sum (events, bytes).
  enum class ValueKind : char { Maximum, Cycles, Sum };
  std::vector<ValueKind> value_kinds() const;
  // The counters of `groups` merged name by name (summed, or the maximum for maxima; arrays
  // summed element by element).
  static nlohmann::json sum(const std::vector<const StatGroup*>& groups);

 private:
  friend class Counter;
  friend class CounterArray;
  // Calls f(value&, kind) on every counter and array element here and below, in walk order.
  template <class F>
  void walk_values(F&& f) const;
  std::string name_, kind_, description_;
  std::vector<Counter*> counters_;
  std::vector<CounterArray*> arrays_;
  std::vector<StatGroup*> children_;
};

class Counter {
 public:
  enum class Merge { Sum, Max };  // how sum() combines the counter across units
  // `unit`: "cycles", "bytes" or "count"; `description`: what one increment means, for the
  // schema and the docs.
  Counter(StatGroup& group, std::string name, std::string unit, std::string description, Merge merge = Merge::Sum)
      : name_(std::move(name)), unit_(std::move(unit)), description_(std::move(description)), merge_(merge) {
    group.counters_.push_back(this);
  }
  Counter(const Counter&) = delete;
  Counter& operator=(const Counter&) = delete;

  Counter& operator+=(std::uint64_t v) {
    value_ += v;
    return *this;
  }
  Counter& operator++() { return *this += 1; }
  void max(std::uint64_t v) { value_ = v > value_ ? v : value_; }
  void set(std::uint64_t v) { value_ = v; }
  std::uint64_t value() const { return value_; }
  operator std::uint64_t() const { return value_; }
  const std::string& name() const { return name_; }
  const std::string& unit() const { return unit_; }
  const std::string& description() const { return description_; }
  Merge merge() const { return merge_; }
  void reset() { value_ = 0; }

 private:
  friend class StatGroup;
  std::string name_, unit_, description_;
  Merge merge_;
  std::uint64_t value_ = 0;
};

// A counter per element of a block (a buffer's banks): one JSON array, reset with the tree.
class CounterArray {
 public:
  CounterArray(StatGroup& group, std::string name, std::string unit, std::string description, std::size_t size)
      : name_(std::move(name)), unit_(std::move(unit)), description_(std::move(description)), values_(size, 0) {
    group.arrays_.push_back(this);
  }
  CounterArray(const CounterArray&) = delete;
  CounterArray& operator=(const CounterArray&) = delete;

  std::uint64_t& operator[](std::size_t i) { return values_[i]; }
  const std::vector<std::uint64_t>& values() const { return values_; }
  const std::string& name() const { return name_; }
  const std::string& unit() const { return unit_; }
  const std::string& description() const { return description_; }
  void reset() { std::fill(values_.begin(), values_.end(), 0); }

 private:
  friend class StatGroup;
  std::string name_, unit_, description_;
  std::vector<std::uint64_t> values_;
};

}  // namespace tigris::hw
