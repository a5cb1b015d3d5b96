// Per-query latency (admission to the last results entering the write-back stream) and BE
// Query Buffer waits, recorded from the accelerator's observer reports (docs/stats.md, latency).
#pragma once

#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "hw/observer.hpp"

namespace tigris {

class LatencyRecorder final : public hw::JobObserver {
 public:
  void job_started(std::uint32_t num_queries) override;
  void query_admitted(std::uint32_t query, std::uint64_t cycle) override { admitted_.at(query) = cycle; }
  void query_finished(std::uint32_t query, std::uint64_t cycle) override {
    latency_.push_back(cycle - admitted_.at(query));
  }
  void bqb_waited(std::uint32_t /*query*/, std::uint64_t cycles) override { bqb_waits_.push_back(cycles); }
  // {"query": {mean, p50, p99, max}, "bqb_wait": {...}} in cycles.
  nlohmann::json json() const;

 private:
  std::vector<std::uint64_t> admitted_, latency_, bqb_waits_;
};

}  // namespace tigris
