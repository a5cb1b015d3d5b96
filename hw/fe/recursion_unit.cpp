#include "recursion_unit.hpp"

#include <algorithm>

#include "front_end.hpp"
#include "hw/mem/result_buffer.hpp"
#include "hw/qdn/distribution_network.hpp"

namespace tigris::hw {

RecursionUnit::RecursionUnit(sc_core::sc_module_name name, int id, const AcceleratorConfig& config,
                             const JobDescriptor& job, Links links)
    : sc_module(name), Scheduler::Client(Scheduler::kRecursionUnit, static_cast<std::uint32_t>(id)), points("points"),
      queries("queries"), stacks("stacks"), results("results"), id_(id), config_(config), cost_(config.cost), job_(job),
      links_(links), clock_{config.period()}, stats_(basename(), "recursion_unit"),
      node_energy_(links.meter.line("ru.node", EnergyMeter::Component::Ru, links.meter.table().ru_node_pj)),
      replica_bytes_(links.meter.line("ru.top_level_replica_bytes", EnergyMeter::Component::Ru,
                                      links.meter.table().register_pj_per_byte)),
      stall_(config.stall, "ru" + std::to_string(id), stats_) {
  links.scheduler.add(*this);
}

void RecursionUnit::start_job() {
  state_ = State::Idle;
  const int levels = std::min(config_.fe.top_levels_replicated, job_.top_height);
  replicated_nodes_ = (std::uint32_t{1} << levels) - 1;
  stall_.start();
  tree_ = TreeView(points.data(), job_);
  slots_ = ResultSlots(results.data(), job_.k);
  query_records_ = reinterpret_cast<const tlm_if::QueryRecord*>(queries.data());
  stacks_ = reinterpret_cast<StackEntry*>(stacks.data());
  points_sram_ = dynamic_cast<BankedSram*>(points.timing_target());
  queries_sram_ = dynamic_cast<BankedSram*>(queries.timing_target());
  stacks_sram_ = dynamic_cast<BankedSram*>(stacks.timing_target());
}

void RecursionUnit::start(const QueryToken& token) {
  token_ = token;
  state_ = State::Walking;
  busy_wave_.set(1);
  query_wave_.set(token.query);
  ++activations_;
  const std::uint64_t now = clock_.now();
  links_.scans.ready(token.slot);  // the deferred-result contract (hw/host/scan_service.hpp)
  const auto [pipeline_with_stalls, walk_done, grant_stalls] = walk(now);
  std::uint64_t pipeline = pipeline_with_stalls, done = walk_done;
  if (!job_.radius()) {  // the result slot, read and written back
    tlm_if::AccessProfile a;
    a.first_byte = job_.result_slot_address(token_.slot);
    a.bytes = job_.result_slot_bytes;
    done = std::max(done, results.charge(now, a, clock_.period));
    a.write = true;  // PI's last insert writes the slot back at the end of the walk (posted)
    results.charge(now + pipeline, a, clock_.period);
  }
  // A walk's grant stalls are SRAM stalls, shown after its busy cycles (the cost table's).
  pipeline -= grant_stalls;
  busy_cycles_ += pipeline;
  sram_stall_ += done - (now + pipeline);
  busy_wave_.set_at(clock_, now + pipeline, 0);
  const auto ru = static_cast<std::uint32_t>(id_);
  links_.observer.activity(JobObserver::Activity::RuBusy, 1, now, now + pipeline);
  links_.observer.activity(JobObserver::Activity::RuSramStall, 1, now + pipeline, done);
  if (done > now + pipeline) {
    sram_wave_.set_at(clock_, now + pipeline, 1);
    sram_wave_.set_at(clock_, done, 0);
  }
  links_.observer.ru_walk(ru, token_.query, now, done);

  // A finished NN/kNN query's list leaves for DRAM with the radius hits (in on_done).
  if (!job_.radius() && finished_) {
    slots_.finish(token_.slot);
    const Neighbor* e = slots_.entries(token_.slot);
    for (std::uint32_t i = 0, n = slots_.count(token_.slot); i < n; ++i)
      hits_.push_back({token_.query, e[i].index, e[i].dist2});
  }
  if (finished_ && token_.first_leaf != kNoLeaf && (!job_.wait_for_leaders || token_.leader_entry != kNoLeaf))
    take_leader_record();
  links_.scheduler.at(*this, done);
}

void RecursionUnit::take_leader_record() {
  // A first_leaf leader has finished: its final results that are Node Set entries, closest
  // first (NN/kNN, from its slot) or as its scans found them (radius, staged), go to its
  // first leaf's Leader Buffer. One that found none there has nothing for followers.
  LeaderStaging& staging = links_.result_buffer.leader_staging();
  LeaderRecord r{token_.query, token_.first_leaf, token_.leader_entry, token_.point, {}, 0};
  if (job_.radius()) {
    r.list.swap(staging.staged(token_.slot));
  } else {
    const Neighbor* e = slots_.entries(token_.slot);
    for (std::uint32_t i = 0, n = slots_.count(token_.slot); i < n; ++i)
      if (const tlm_if::PointEntry* p = staging.leaf_entry(e[i].index)) r.list.push_back(*p);
  }
  // wait: every leader's record goes (its followers may be parked for it); finished_only: a
  // list without entries has nothing for followers.
  if (job_.wait_for_leaders ? token_.leader_entry != kNoLeaf : !r.list.empty()) record_ = std::move(r);
}

void RecursionUnit::clear_results() {
  if (!job_.radius()) slots_.clear(token_.slot);
  if (job_.first_leaf && job_.radius()) links_.result_buffer.leader_staging().staged(token_.slot).clear();
}

std::tuple<std::uint64_t, std::uint64_t, std::uint64_t> RecursionUnit::walk(std::uint64_t now) {
  hits_.clear();
  if (!token_.started) clear_results();  // a new query's slot is the RU's, not the engine's
  const WalkEngine::Ports ports{points,         queries,       stacks,      job_,  tree_,
                                query_records_, stacks_,       slots_,      hits_, replicated_nodes_,
                                points_sram_,   queries_sram_, stacks_sram_};
  const WalkEngine::Outcome o = links_.engine.walk(token_, now, ports);
  finished_ = o.finished;
  const auto prune = static_cast<std::uint64_t>(config_.fe.bypassing ? cost_.ru_prune_at_rn : cost_.ru_prune_no_bypass);
  prune_cycles_ += o.pruned * prune;
  if (!config_.fe.forwarding) pi_rs_stall_ += std::uint64_t{o.nodes} * static_cast<std::uint64_t>(cost_.ru_pi_rs_stall);
  replica_bytes_ += std::uint64_t{o.replica_reads} * sizeof(tlm_if::PointEntry);
  node_energy_ += o.nodes;
  links_.observer.walked(token_.query, o.nodes, o.pruned);
  return {o.end - now, o.done, o.grant_stalls};
}

void RecursionUnit::walk_soon(const QueryToken& token) const {
  ScanService& s = links_.scans;
  s.read_soon(query_records_ + token.query, sizeof(tlm_if::QueryRecord));
  if (token.started)
    s.write_soon(stacks_ + std::uint64_t{token.slot} * job_.stack_entries, job_.stack_entries * sizeof(StackEntry));
  if (!job_.radius()) s.write_soon(slots_.address(token.slot), slots_.bytes());
  s.walk_soon(token);
}

void RecursionUnit::on_done() {
  const std::uint64_t now = clock_.now();
  if (const std::uint64_t d = stall_.draw()) {  // the hand-off is held back (stall injection)
    links_.scheduler.at(*this, now + d);
    return;
  }
  if (state_ == State::Blocked) {
    bqb_full_stall_ += now - blocked_since_;
    links_.observer.ru_blocked(static_cast<std::uint32_t>(id_), token_.query, blocked_since_, now);
    links_.observer.activity(JobObserver::Activity::RuBqbFull, 1, blocked_since_, now);
  }
  stalled_wave_.set(0);
  writeback_wave_.set(0);
  if (!hits_.empty()) {  // results leave through the write-back stream, which may push back
    const std::uint64_t accepted = links_.result_buffer.stream(now, hits_.data(), hits_.size());
    hits_.clear();
    if (accepted > now) {
      writeback_stall_ += accepted - now;
      writeback_wave_.set(1);
      links_.observer.activity(JobObserver::Activity::RuWritebackStall, 1, now, accepted);
      links_.scheduler.at(*this, accepted);
      return;
    }
  }
  if (finished_) {
    state_ = State::Idle;
    if (record_) {  // before the query counts as finished: the job waits for the record
      links_.fe.leader_record_sent();
      links_.qdn.send_leader(std::move(*record_), now);
      record_.reset();
    }
    links_.fe.query_finished(token_, now);
    links_.fe.ru_idle(*this);
    return;
  }
  if (!links_.qdn.route(token_, now, *this)) {
    blocked_since_ = now;
    state_ = State::Blocked;
    stalled_wave_.set(1);
    return;  // the QDN calls retry_dispatch() when the BE Query Buffer has room
  }
  state_ = State::Idle;
  links_.fe.ru_idle(*this);
}

void RecursionUnit::retry_dispatch() { links_.scheduler.now(*this); }

}  // namespace tigris::hw
