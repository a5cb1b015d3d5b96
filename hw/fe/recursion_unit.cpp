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
  const auto [pipeline_with_stalls, walk_done, grant_stalls] = links_.engine ? engine_walk(now) : walk(now);
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

std::tuple<std::uint64_t, std::uint64_t, std::uint64_t> RecursionUnit::engine_walk(std::uint64_t now) {
  hits_.clear();
  if (!token_.started) clear_results();  // the slot is outside the RTL RU
  const WalkEngine::Ports ports{points,         queries, stacks, job_,  tree_,
                                query_records_, stacks_, slots_, hits_, replicated_nodes_};
  const WalkEngine::Outcome o = links_.engine->walk(token_, now, ports);
  finished_ = o.finished;
  const auto prune = static_cast<std::uint64_t>(config_.fe.bypassing ? cost_.ru_prune_at_rn : cost_.ru_prune_no_bypass);
  prune_cycles_ += o.pruned * prune;
  if (!config_.fe.forwarding) pi_rs_stall_ += std::uint64_t{o.nodes} * static_cast<std::uint64_t>(cost_.ru_pi_rs_stall);
  replica_bytes_ += std::uint64_t{o.replica_reads} * sizeof(tlm_if::PointEntry);
  node_energy_ += o.nodes;
  links_.observer.walked(token_.query, o.nodes, o.pruned);
  return {o.end - now, o.done, o.grant_stalls};
}

std::tuple<std::uint64_t, std::uint64_t, std::uint64_t> RecursionUnit::walk(std::uint64_t now) {
  hits_.clear();
  finished_ = false;
  std::uint32_t top = 0, pruned = 0;
  StackEntry* stack = stacks_ + std::uint64_t{token_.slot} * job_.stack_entries;
  const std::uint64_t stack_base = job_.stack_base(token_.slot);
  const bool forwarding = config_.fe.forwarding, bypassing = config_.fe.bypassing;
  const auto& sram = config_.sram;
  // Every access is requested when its step issues and held until granted: a busy bank or
  // port stalls the whole walk there (`stall` so far), as the RTL RU's ports do (rtl/).
  std::uint64_t done = now, stall = 0;
  const auto pop_read = [&](std::uint64_t cycle, std::uint32_t at) {
    return stacks.request(stacks_sram_, cycle, stack_base + at * sizeof(StackEntry), sizeof(StackEntry), false,
                          sram.query_stack.latency_cycles, clock_.period, done);
  };
  const auto push_write = [&](std::uint64_t cycle, std::uint32_t at) {
    return stacks.request(stacks_sram_, cycle, stack_base + at * sizeof(StackEntry), sizeof(StackEntry), true,
                          sram.query_stack.latency_cycles, clock_.period, done);
  };
  const auto point_read = [&](std::uint64_t cycle, std::uint64_t byte, std::uint32_t bytes) {
    return points.request(points_sram_, cycle, byte, bytes, false, sram.points.latency_cycles, clock_.period, done);
  };

  // FQ: fetch the query point and its stack address; a new query's root goes into its stack.
  const tlm_if::QueryRecord& r = query_records_[token_.query];
  std::uint64_t granted =
      queries.request(queries_sram_, now, std::uint64_t{token_.query} * sizeof(tlm_if::QueryRecord),
                      sizeof(tlm_if::QueryRecord), false, sram.queries.latency_cycles, clock_.period, done);
  token_.point = Point3{r.x, r.y, r.z};
  const Point3 q = token_.point;
  if (!token_.started) {
    token_.started = true;
    token_.sp = 0;
    clear_results();
    if (tree_.node_nonempty(0)) {
      granted = std::max(granted, push_write(now, 0));
      stack[token_.sp++] = {0, 0.0f};
    }
  }
  stall += granted - now;
  std::uint64_t cycles = static_cast<std::uint64_t>(cost_.ru_fetch_query);
  // The walk keeps its state in locals (written back on leaving): the pruning bound changes
  // only when an insert took a point, and the statistics are added once per activation.
  const bool radius = job_.radius();
  const std::uint32_t slot = token_.slot, top_nodes = tree_.num_top_nodes();
  const std::uint64_t node_cycles =
      static_cast<std::uint64_t>(cost_.ru_node) + (forwarding ? 0 : static_cast<std::uint64_t>(cost_.ru_pi_rs_stall));
  float bound = radius ? job_.r2 : slots_.bound(slot);
  std::uint32_t sp = token_.sp;
  std::uint64_t prune_cycles = 0, replica_reads = 0;
  // The near child a node forwards (its next step), and the far child it pushed: the push is
  // written with the next step, and a pop of that very entry takes the push's data.
  bool forwarded = false, pushed = false;
  std::uint32_t next = 0;
  for (;;) {
    const std::uint64_t t = now + cycles + stall;  // this step issues
    std::uint64_t end = t;                         // ... and is granted everything by
    std::uint64_t node_from = t;                   // its node read waits for a pop's data
    std::uint32_t node = next;
    if (!forwarded && sp == 0) {  // the stack is empty: the query's results leave the RU
      finished_ = true;
      cycles += static_cast<std::uint64_t>(cost_.ru_drain + cost_.result_writeback);
      break;
    }
    if (pushed) end = std::max(end, push_write(t, sp - 1));
    if (!forwarded) {
      // RS: pop the top of stack. RN: its distance information says whether it can be pruned.
      const StackEntry tos = stack[--sp];
      if (!pushed) end = node_from = std::max(end, pop_read(t, sp));
      pushed = false;
      if (tos.plane2 > bound) {
        ++pruned;
        const auto c = static_cast<std::uint64_t>(bypassing ? cost_.ru_prune_at_rn : cost_.ru_prune_no_bypass);
        cycles += c;
        prune_cycles += c;
        stall += end - t;
        continue;
      }
      node = tos.node;
    }
    forwarded = pushed = false;
    if (node >= top_nodes) {
      // CL: the query leaves for the back-end with the leaf set it must scan (its size read).
      token_.leaf = node - top_nodes;
      end = std::max(end, point_read(node_from, tree_.dir_address(token_.leaf), sizeof(tlm_if::LeafDirEntry)));
      stall += end - t;
      cycles += static_cast<std::uint64_t>(cost_.ru_drain);
      break;
    }
    // RN: read the node; CD: its distance to the query; PI: insert into the result, push the
    // far child with its plane distance, forward the near child.
    const tlm_if::PointEntry& e = tree_.node(node);
    if (node < replicated_nodes_)  // the RU's own copy of the first levels
      ++replica_reads;
    else
      end = std::max(end, point_read(node_from, tree_.node_address(node), sizeof(tlm_if::PointEntry)));
    stall += end - t;
    ++top;
    cycles += node_cycles;
    const Point3 p{e.x, e.y, e.z};
    const float d = dist2(q, p);
    // A point beyond the bound cannot enter the list (an equal one still may, by index).
    if (d <= bound) {
      const std::uint32_t index = e.tag & tlm_if::kIndexMask;
      if (radius)
        hits_.push_back({token_.query, index, d});
      else if (slots_.insert(slot, {index, d}))
        bound = slots_.bound(slot);
    }
    const int axis = static_cast<int>(e.tag >> tlm_if::kAxisShift);
    const bool left = q[axis] < p[axis];
    const std::uint32_t near_child = 2 * node + (left ? 1 : 2);
    const std::uint32_t far_child = left ? near_child + 1 : near_child - 1;
    if (tree_.node_nonempty(far_child)) {
      stack[sp++] = {far_child, plane_dist2(q, p, axis)};
      pushed = true;
    }
    forwarded = tree_.node_nonempty(near_child);
    next = near_child;
  }
  token_.sp = static_cast<std::uint16_t>(sp);
  prune_cycles_ += prune_cycles;
  if (!forwarding) pi_rs_stall_ += top * static_cast<std::uint64_t>(cost_.ru_pi_rs_stall);
  replica_bytes_ += replica_reads * sizeof(tlm_if::PointEntry);
  node_energy_ += top;
  links_.observer.walked(token_.query, top, pruned);
  const std::uint64_t pipeline = cycles + stall;
  return {pipeline, std::max(done, now + pipeline), stall};
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
