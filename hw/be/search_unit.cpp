#include "search_unit.hpp"

#include <algorithm>
#include <limits>

#include "hw/fe/front_end.hpp"
#include "hw/mem/result_buffer.hpp"
#include "hw/qdn/distribution_network.hpp"

namespace tigris::hw {

SearchUnit::SearchUnit(sc_core::sc_module_name name, std::uint32_t id,
                       const AcceleratorConfig& config, const JobDescriptor& job, Links links)
    : sc_module(name), points("points"), results("results"), id_(id), config_(config), job_(job),
      links_(links), clock_{config.period()},
      capacity_(static_cast<std::size_t>(config.be.bqb_entries)),
      pes_(static_cast<std::uint32_t>(config.be.pes_per_su)), free_pes_(pes_),
      stats_(basename(), "search_unit"),
      distance_energy_(links.meter.line("pe.distance", EnergyMeter::Component::Pe, links.meter.table().distance_pj)) {
  SC_METHOD(step);
  sensitive << wake_;
  dont_initialize();
}

void SearchUnit::start() {
  bqb_.clear();
  running_.clear();
  free_pes_ = pes_;
  busy_until_ = 0;
  tree_ = TreeView(points.data(), job_);
  pe_array_.start(job_, tree_, ResultSlots(results.data(), job_.k));
}

void SearchUnit::accept(const QueryToken& token) {
  bqb_.push_back(token);
  bqb_wave_.set(bqb_.size());
  bqb_max_.max(bqb_.size());
  const std::uint64_t now = clock_.now();
  wake_.notify(clock_.until(std::max(token.ready, now)));
}

void SearchUnit::step() {
  const std::uint64_t now = clock_.now();
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
    for (const QueryToken& t : running_[i].tokens) links_.fe.reinsert(t, back);
    free_pes_ += static_cast<std::uint32_t>(running_[i].tokens.size());
    running_[i] = std::move(running_.back());
    running_.pop_back();
  }
  // Issue while the policy finds batches for the free PEs.
  bool issued = false;
  for (;;) {
    const IssueDecision d = links_.policy.pick(bqb_, free_pes_, pes_, now);
    if (d.batches.empty()) break;
    std::vector<std::vector<QueryToken>> batches;
    std::vector<std::size_t> taken;
    for (const auto& positions : d.batches) {
      batches.emplace_back();
      for (std::size_t i : positions) batches.back().push_back(bqb_[i]), taken.push_back(i);
    }
    std::sort(taken.begin(), taken.end());
    for (auto it = taken.rbegin(); it != taken.rend(); ++it) bqb_.erase(bqb_.begin() + static_cast<std::ptrdiff_t>(*it));
    const std::uint64_t setup = d.search_cycles + static_cast<std::uint64_t>(config_.cost.issue_cycle);
    issue_stall_ += setup;
    for (auto& b : batches) issue(std::move(b), now, setup);
    issued = true;
  }
  if (issued) links_.qdn.space_freed(id_);
  bqb_wave_.set(bqb_.size());
  pes_wave_.set(pes_ - free_pes_);
  // Sleep until a batch drains or a queued query arrives.
  std::uint64_t next = std::numeric_limits<std::uint64_t>::max();
  for (const Batch& b : running_) next = std::min(next, b.end);
  for (const QueryToken& t : bqb_)
    if (t.ready > now) next = std::min(next, t.ready);
  if (next != std::numeric_limits<std::uint64_t>::max()) wake_.notify(clock_.until(next));
}

void SearchUnit::issue(std::vector<QueryToken> tokens, std::uint64_t now, std::uint64_t setup) {
  const std::uint64_t start = now + setup;  // buffers are read during the issue search
  const std::uint32_t leaf = tokens.front().leaf;
  const std::uint64_t n = tree_.leaf_size(leaf);
  const std::uint64_t b = tokens.size();
  const std::uint64_t set_bytes = n * sizeof(tlm_if::PointEntry);
  free_pes_ -= static_cast<std::uint32_t>(b);
  leaf_wave_.set(leaf);
  ++batches_;
  queries_ += b;

  // Node Set: from the Node Cache on a hit, else one burst from the Point Buffer.
  std::uint64_t data_ready = start + static_cast<std::uint64_t>(config_.cost.node_cache_hit);
  if (!links_.cache.lookup(leaf, set_bytes)) {
    tlm_if::AccessProfile a;
    a.first_byte = tree_.leaf_address(leaf);
    a.bytes = set_bytes;
    data_ready = points.charge(now, a, clock_.period);
  }
  // Result Buffer: each query's NN/kNN slot is read into its PE (written back at retire).
  if (!job_.radius()) data_ready = std::max(data_ready, results.charge(now, slot_access(tokens, false), clock_.period));
  const int depth = config_.cost.pe_pipeline_depth;
  const std::uint64_t compute_end = start + PeArray::stream_cycles(n, b, depth);
  const std::uint64_t end = PeArray::stream_end(start, data_ready, n, b, depth);
  // Function: every PE scans the Node Set for its query; the decisions are reported in order.
  std::vector<tlm_if::ResultRecord> hits;
  for (const QueryToken& t : tokens) {
    const std::uint32_t scanned = pe_array_.scan(t, hits);
    distance_energy_ += scanned;
    links_.observer.leaf_scanned(t.query, t.leaf, scanned);
  }
  // Busy: streaming as the formula says (cycles with a PE busy, batches of MQMN overlap);
  // stall: the stream waiting for its data beyond that.
  busy_cycles_ += compute_end - std::max(start, std::min(compute_end, busy_until_));
  busy_until_ = std::max(busy_until_, compute_end);
  sram_stall_ += end - compute_end;
  pe_busy_cycles_ += b * (compute_end - start);
  running_.push_back({std::move(tokens), std::move(hits), end, false});
}

tlm_if::AccessProfile SearchUnit::slot_access(const std::vector<QueryToken>& tokens, bool write) {
  slot_addrs_.clear();
  for (const QueryToken& t : tokens) slot_addrs_.push_back(job_.result_slot_address(t.slot));
  tlm_if::AccessProfile a;
  a.write = write;
  a.scatter = slot_addrs_.data();
  a.scatter_size = static_cast<std::uint32_t>(job_.result_slot_bytes);
  a.scatter_count = static_cast<std::uint32_t>(slot_addrs_.size());
  a.bytes = tokens.size() * job_.result_slot_bytes;
  return a;
}

std::uint64_t SearchUnit::retire(Batch& batch) {
  // The PEs' insert stage writes NN/kNN slots back (posted) or streams the radius hits out.
  const std::uint64_t now = clock_.now();
  if (batch.written) return now;
  batch.written = true;
  if (!job_.radius()) {
    results.charge(now, slot_access(batch.tokens, true), clock_.period);  // posted
    return now;
  }
  if (batch.hits.empty()) return now;
  const std::uint64_t accepted = links_.result_buffer.stream(now, batch.hits.data(), batch.hits.size());
  writeback_stall_ += accepted - now;
  return accepted;
}

}  // namespace tigris::hw
