#include "latency.hpp"

#include "sw_ref/stats.hpp"

namespace tigris {

void LatencyRecorder::job_started(std::uint32_t num_queries) {
  admitted_.assign(num_queries, 0);
  latency_.clear();
  latency_.reserve(num_queries);
  bqb_waits_.clear();
  bqb_waits_.reserve(std::size_t{8} * num_queries);  // one per leaf visit: a few per query (untouched pages are free)
}

nlohmann::json LatencyRecorder::json() const {
  const auto one = [](const std::vector<std::uint64_t>& v) {
    const Distribution d = distribution(v);
    return nlohmann::json{{"count", v.size()}, {"mean", d.mean}, {"p50", d.p50}, {"p99", d.p99}, {"max", d.max}};
  };
  return {{"query", one(latency_)}, {"bqb_wait", one(bqb_waits_)}};
}

}  // namespace tigris
