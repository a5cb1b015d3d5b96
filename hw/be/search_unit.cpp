#include "search_unit.hpp"

#include <algorithm>
#include <limits>

#include "hw/be/pe_array.hpp"
#include "hw/fe/front_end.hpp"
#include "hw/mem/result_dram.hpp"
#include "hw/mem/result_slots.hpp"
#include "hw/qdn/distribution_network.hpp"

namespace tigris::hw {

SearchUnit::SearchUnit(sc_core::sc_module_name name, std::uint32_t id,
                       const AcceleratorConfig& config, const IssuePolicy& policy, FrontEnd& fe,
                       DistributionNetwork& qdn, NodeCache& cache, ResultDram& dram, Job& job)
    : sc_module(name), points("points"), results("results"), id_(id), config_(config),
      policy_(policy), fe_(fe), qdn_(qdn), cache_(cache), dram_(dram), job_(job),
      capacity_(static_cast<std::size_t>(config.be.bqb_entries)),
      pes_(static_cast<std::uint32_t>(config.be.pes_per_su)), free_pes_(pes_) {
  SC_METHOD(step);
  sensitive << wake_;
  dont_initialize();
}

void SearchUnit::reset() {
  bqb_.clear();
  running_.clear();
  free_pes_ = pes_;
  busy_until_ = 0;
  stats_ = {};
}

void SearchUnit::accept(const QueryToken& token) {
  bqb_.push_back(token);
  bqb_wave_.set(bqb_.size());
  stats_.bqb_max_occupancy = std::max<std::uint64_t>(stats_.bqb_max_occupancy, bqb_.size());
  const std::uint64_t now = job_.cycle();
  wake_.notify((token.ready > now ? token.ready - now : 0) * job_.period);
}

void SearchUnit::step() {
  const std::uint64_t now = job_.cycle();
  // Retire batches whose stream has drained: their queries go back to the front-end.
  for (std::size_t i = 0; i < running_.size();) {
    if (running_[i].end > now) {
      ++i;
      continue;
    }
    // Results leave first; a full write-back stream holds the batch (and its PEs) back.
    const std::uint64_t accepted = retire(running_[i]);
    if (accepted > now) {
      running_[i].end = accepted;
      ++i;
      continue;
    }
    const std::uint64_t back = now + static_cast<std::uint64_t>(config_.cost.be_to_fe);
    for (const QueryToken& t : running_[i].tokens) fe_.reinsert(t, back);
    free_pes_ += static_cast<std::uint32_t>(running_[i].tokens.size());
    running_[i] = std::move(running_.back());
    running_.pop_back();
  }
  // Issue while the policy finds work for the free PEs.
  bool issued = false;
  while (free_pes_ > 0 && !(policy_.shared_stream() && free_pes_ < pes_)) {
    const IssueDecision d = policy_.pick(bqb_, free_pes_, now);
    if (d.picks.empty()) break;
    std::vector<QueryToken> tokens;
    for (std::size_t i : d.picks) tokens.push_back(bqb_[i]);
    for (auto it = d.picks.rbegin(); it != d.picks.rend(); ++it) bqb_.erase(bqb_.begin() + static_cast<std::ptrdiff_t>(*it));
    const std::uint64_t setup = d.search_cycles + static_cast<std::uint64_t>(config_.cost.issue_cycle);
    stats_.issue_cycles += setup;
    if (policy_.shared_stream()) {
      issue(std::move(tokens), now, setup);
    } else {
      for (QueryToken& t : tokens) issue({t}, now, setup);
    }
    issued = true;
  }
  if (issued) qdn_.space_freed(id_);
  bqb_wave_.set(bqb_.size());
  pes_wave_.set(pes_ - free_pes_);
  // Sleep until a batch drains or a queued query arrives.
  std::uint64_t next = std::numeric_limits<std::uint64_t>::max();
  for (const Batch& b : running_) next = std::min(next, b.end);
  for (const QueryToken& t : bqb_)
    if (t.ready > now) next = std::min(next, t.ready);
  if (next != std::numeric_limits<std::uint64_t>::max()) wake_.notify((next - now) * job_.period);
}

void SearchUnit::issue(std::vector<QueryToken> tokens, std::uint64_t now, std::uint64_t setup) {
  const std::uint64_t start = now + setup;  // buffers are read during the issue search
  const std::uint32_t leaf = tokens.front().leaf;
  const std::uint64_t n = job_.leaf_dir[leaf + 1] - job_.leaf_dir[leaf];
  const std::uint64_t b = tokens.size();
  const std::uint64_t set_bytes = n * sizeof(tlm_if::PointEntry);
  free_pes_ -= static_cast<std::uint32_t>(b);
  leaf_wave_.set(leaf);
  ++stats_.batches;
  stats_.queries += b;

  // Node Set: from the Node Cache on a hit, else one burst from the Point Buffer.
  std::uint64_t data_ready = start;
  if (!cache_.lookup(leaf, set_bytes)) {
    tlm_if::AccessProfile a;
    a.first_byte = (job_.num_top_nodes + job_.leaf_dir[leaf]) * sizeof(tlm_if::PointEntry);
    a.words = static_cast<std::uint32_t>(n);
    a.bytes = set_bytes;
    data_ready = points.charge(now, a, job_.period);
  }
  // Result Buffer: each query's NN/kNN slot is read into its PE (written back at retire).
  if (job_.mode != tlm_if::SearchMode::Radius)
    data_ready = std::max(data_ready, results.charge(now, slot_access(tokens, false), job_.period));
  const int depth = config_.cost.pe_pipeline_depth;
  const std::uint64_t compute_end = start + PeArray::stream_cycles(n, b, depth);
  // The stream cannot run ahead of its data: the last point enters the array once it arrived.
  std::uint64_t end = std::max(compute_end, data_ready + b - 1 + static_cast<std::uint64_t>(depth));
  // Function: every PE scans the Node Set for its query.
  std::vector<tlm_if::ResultRecord> hits;
  for (const QueryToken& t : tokens) {
    job_.schedule.emplace_back(t.query, t.leaf);
    PeArray::scan(job_, t, hits);
  }
  // Busy: streaming as the formula says (cycles with a PE busy, batches of MQMN overlap);
  // stall: the stream waiting for its data beyond that.
  stats_.busy_cycles += compute_end - std::max(start, std::min(compute_end, busy_until_));
  busy_until_ = std::max(busy_until_, compute_end);
  stats_.sram_stall_cycles += end - compute_end;
  stats_.pe_busy_cycles += b * (compute_end - start);
  running_.push_back({std::move(tokens), std::move(hits), end, false});
}

tlm_if::AccessProfile SearchUnit::slot_access(const std::vector<QueryToken>& tokens, bool write) {
  slot_words_.clear();
  const std::uint64_t words = (job_.result_slot_bytes + 7) / 8;
  for (const QueryToken& t : tokens)
    for (std::uint64_t w = 0; w < words; ++w) slot_words_.push_back(t.slot * job_.result_slot_bytes + 8 * w);
  tlm_if::AccessProfile a;
  a.write = write;
  a.scatter = slot_words_.data();
  a.scatter_count = static_cast<std::uint32_t>(slot_words_.size());
  a.bytes = tokens.size() * job_.result_slot_bytes;
  return a;
}

std::uint64_t SearchUnit::retire(Batch& batch) {
  // The PEs' insert stage writes NN/kNN slots back (posted) or streams the radius hits out.
  const std::uint64_t now = job_.cycle();
  if (batch.written) return now;
  batch.written = true;
  if (job_.mode != tlm_if::SearchMode::Radius) {
    results.charge(now, slot_access(batch.tokens, true), job_.period);  // posted
    return now;
  }
  if (batch.hits.empty()) return now;
  const std::uint64_t accepted = dram_.write(now, batch.hits.data(), batch.hits.size());
  stats_.writeback_stall_cycles += accepted - now;
  return accepted;
}

}  // namespace tigris::hw
