// Sampled simulation of a job (docs/sampling.md; after SMARTS, Wunderlich et al., ISCA 2003):
// the accelerator runs one stream made of the job's first queries (the fill: every query slot
// taken, then warming), `windows` stretches of consecutive queries spread evenly over the job,
// each but the first after queries of detailed warming, and its last queries (the drain). With
// every slot taken a query is admitted when one finishes, so the cycles between two admissions
// are the machine's throughput on the queries it holds. The job's cycles are the fill and the
// drain as simulated plus its queries between them at the stream's cycles per query there, seams
// included (a ratio estimate over the segments from one window to the next, with a 95% interval
// from their spread). Every simulated query is checked against the golden model; the others
// take its results.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hw/config.hpp"
#include "hw/observer.hpp"
#include "hw/stats.hpp"

namespace tigris::hw {
class TigrisAccelerator;
}

namespace tigris {

struct SamplingPlan {
  double requested = 0.0;  // sim.sampling (0 off, -1 auto, else a share)
  bool sampled = false;
  std::string why;  // why the job is simulated in full, when it is
  std::uint32_t queries = 0, in_flight = 0;
  std::uint32_t fill = 0, warm = 0, measured = 0, drain = 0;  // queries: head, per window, tail
  std::vector<std::uint32_t> stream;                          // the simulated queries' ids, in job order
  struct Window {
    std::uint32_t from = 0, to = 0;  // stream positions whose admissions bound the window
  };
  std::vector<Window> windows;
};

// The plan for a job of `queries` queries that holds `in_flight` at most (hw::queries_in_flight).
// Approximate search is simulated in full: its leaders depend on every query before.
SamplingPlan plan_sampling(const hw::AcceleratorConfig::Sim& sim, std::uint32_t queries, std::uint32_t in_flight,
                           bool approximate);

// What the golden model counted per query of the job: the auxiliary variables of the estimate
// and the result records that warm the write-back.
struct QueryWork {
  std::vector<std::uint32_t> records, leaf_points, top_nodes;
};

// A ratio estimator (Cochran, Sampling Techniques, 6.3): sum y / sum x over the segments, and
// the 95% half width of that ratio from the successive differences of their residuals
// (Student's t, n - 1 degrees of freedom).
struct RatioEstimate {
  double ratio = 0, half = 0;
};
RatioEstimate ratio_estimate(const std::vector<double>& y, const std::vector<double>& x);

// The sampled run's controller, an observer of admissions: snapshots of the statistics at the
// admissions that bound the windows, and functional warming at each seam of the stream: the
// result write-back's backlog is set to what the skipped queries would have left in the stream
// buffer (their result records, from the golden model, arriving at the fastest window's pace and
// draining at the DRAM bandwidth), since a window's results alone fill little of that buffer.
class SampleController final : public hw::JobObserver {
 public:
  SampleController(const SamplingPlan& plan, hw::TigrisAccelerator& accel, QueryWork work);
  void query_admitted(std::uint32_t query, std::uint64_t cycle) override;
  struct Snapshot {
    std::uint64_t cycle = 0;
    std::vector<std::uint64_t> values;
  };
  // Two per window, in stream order: at its first query's admission and at the next stretch's.
  const std::vector<Snapshot>& snapshots() const { return snaps_; }
  const QueryWork& work() const { return work_; }

 private:
  void warm_writeback(std::size_t window, std::uint64_t cycle);
  const SamplingPlan& plan_;
  hw::TigrisAccelerator& accel_;
  QueryWork work_;
  std::vector<std::uint32_t> marks_;  // stream positions, ascending
  std::vector<Snapshot> snaps_;
  double fastest_ = 0;  // the fewest cycles per query of a window so far
};

// After the stream's run of `stream_cycles`: writes the job's estimate over the accelerator's
// statistics (sums scaled, maxima as simulated) and returns the estimated cycles; `report`
// gets the sampling JSON (plan, windows, cycles_ci95, energy_pj_ci95). Throws
// std::logic_error when the meter missed a window (the stream ended early).
std::uint64_t apply_estimate(const SamplingPlan& plan, const SampleController& control, hw::TigrisAccelerator& accel,
                             std::uint64_t stream_cycles, nlohmann::json& report);

// The sampling JSON of a job simulated in full: what was asked and why it was not sampled.
nlohmann::json full_simulation_json(const SamplingPlan& plan, std::uint64_t cycles);

// The run summary's line on sampling ("" when sim.sampling is off): what was simulated and the
// cycles' interval, or why the job was simulated in full.
std::string sampling_summary(const nlohmann::json& sampling);

// sim.sampling as a file writes it: "off", "auto" or the share.
nlohmann::json sampling_setting(double sampling);

// The two-sided 95% quantile of Student's t with `dof` degrees of freedom.
double student_t95(std::size_t dof);

}  // namespace tigris
