#include "recursion_unit.hpp"

#include <algorithm>

#include "hw/fe/front_end.hpp"
#include "hw/mem/result_dram.hpp"
#include "hw/mem/result_slots.hpp"
#include "hw/qdn/distribution_network.hpp"

namespace tigris::hw {

RecursionUnit::RecursionUnit(sc_core::sc_module_name name, int id, const AcceleratorConfig& config,
                             FrontEnd& fe, DistributionNetwork& qdn, ResultDram& dram, Job& job)
    : sc_module(name), points("points"), queries("queries"), stacks("stacks"),
      results("results"), id_(id), config_(config), cost_(config.cost), fe_(fe), qdn_(qdn),
      dram_(dram), job_(job) {
  SC_METHOD(on_done);
  sensitive << done_;
  dont_initialize();
}

void RecursionUnit::start(const QueryToken& token) {
  token_ = token;
  state_ = State::Walking;
  busy_wave_.set(1);
  query_wave_.set(token.query);
  ++stats_.activations;
  const std::uint64_t now = job_.cycle();
  const std::uint64_t pipeline = walk();
  stats_.busy_cycles += pipeline;

  // One transaction per buffer for the whole activation.
  tlm_if::AccessProfile a;
  std::uint64_t done = now + pipeline;
  a.first_byte = std::uint64_t{token_.query} * 12, a.words = 1, a.bytes = 12;
  done = std::max(done, queries.charge(now, a, job_.period));
  a = {};
  tlm_if::AccessProfile reads = node_reads_.profile(sizeof(tlm_if::PointEntry));
  if (!finished_) reads.bytes -= sizeof(tlm_if::PointEntry) - 4;  // the last read: a 4-byte directory entry
  done = std::max(done, points.charge(now, reads, job_.period));
  // Query Stack Buffer: the pops as one read, the pushes as one write, in pipeline order.
  done = std::max(done, stacks.charge(now, stack_pops_.profile(sizeof(StackSlotEntry)), job_.period));
  tlm_if::AccessProfile pushes = stack_pushes_.profile(sizeof(StackSlotEntry));
  pushes.write = true;
  done = std::max(done, stacks.charge(now, pushes, job_.period));
  if (job_.mode != tlm_if::SearchMode::Radius) {  // the result slot, read and written back
    a = {};
    a.first_byte = token_.slot * job_.result_slot_bytes;
    a.words = static_cast<std::uint32_t>((job_.result_slot_bytes + 7) / 8);
    a.bytes = job_.result_slot_bytes;
    done = std::max(done, results.charge(now, a, job_.period));
    a.write = true;  // PI's last insert writes the slot back at the end of the walk (posted)
    results.charge(now + pipeline, a, job_.period);
  }
  stats_.sram_stall_cycles += done - (now + pipeline);

  // A finished NN/kNN query's list leaves for DRAM with the radius hits (in on_done).
  if (job_.mode != tlm_if::SearchMode::Radius && finished_) {
    const ResultSlots slots(job_.result_slots, job_.k);
    const std::uint32_t n = slots.count(token_.slot);
    for (std::uint32_t i = 0; i < n; ++i)
      hits_.push_back({token_.query, slots.entries(token_.slot)[i].index, slots.entries(token_.slot)[i].dist2});
  }
  done_.notify((done - now) * job_.period);
}

std::uint64_t RecursionUnit::walk() {
  node_reads_.clear();
  stack_pops_.clear();
  stack_pushes_.clear();
  hits_.clear();
  finished_ = false;
  QueryCounters& count = job_.counters[token_.query];
  ResultSlots slots(job_.result_slots, job_.k);
  StackSlotEntry* stack = job_.stacks + std::uint64_t{token_.slot} * job_.stack_entries;
  const std::uint64_t stack_base = std::uint64_t{token_.slot} * job_.stack_entries * sizeof(StackSlotEntry);
  const bool radius = job_.mode == tlm_if::SearchMode::Radius;
  const bool forwarding = config_.fe.forwarding, bypassing = config_.fe.bypassing;

  // FQ: fetch the query point and its stack address.
  std::uint64_t cycles = static_cast<std::uint64_t>(cost_.ru_fetch_query);
  const Point3 q = job_.query(token_.query);
  if (!token_.started) {
    token_.started = true;
    token_.sp = 0;
    if (!radius) slots.clear(token_.slot);
    if (job_.node_nonempty(0)) stack[token_.sp++] = {0, 0.0f};
  }
  while (token_.sp > 0) {
    // RS: pop the top of stack. RN: its distance information says whether it can be pruned.
    const StackSlotEntry tos = stack[--token_.sp];
    stack_pops_.add(stack_base + token_.sp * sizeof(StackSlotEntry), cycles);
    const float bound = radius ? job_.r2 : slots.bound(token_.slot);
    if (tos.plane2 > bound) {
      ++count.pruned;
      ++stats_.pruned;
      const int c = bypassing ? cost_.ru_prune_at_rn : cost_.ru_prune_no_bypass;
      cycles += static_cast<std::uint64_t>(c);
      stats_.prune_cycles += static_cast<std::uint64_t>(c);
      continue;
    }
    std::uint32_t node = tos.node;
    while (node < job_.num_top_nodes) {
      // RN: read the node; CD: its distance to the query; PI: insert into the result, push
      // the far child with its plane distance, go on with the near child.
      const tlm_if::PointEntry& e = job_.entries[node];
      node_reads_.add(std::uint64_t{node} * sizeof(tlm_if::PointEntry), cycles);
      ++count.top;
      ++stats_.nodes;
      cycles += static_cast<std::uint64_t>(cost_.ru_node);
      if (!forwarding) {
        cycles += static_cast<std::uint64_t>(cost_.ru_pi_rs_stall);
        stats_.pi_rs_stall_cycles += static_cast<std::uint64_t>(cost_.ru_pi_rs_stall);
      }
      const Point3 p{e.x, e.y, e.z};
      const std::uint32_t index = e.tag & tlm_if::kIndexMask;
      const float d = dist2(q, p);
      if (radius) {
        if (d <= job_.r2) hits_.push_back({token_.query, index, d});
      } else {
        slots.insert(token_.slot, index, d);
      }
      const int axis = static_cast<int>(e.tag >> tlm_if::kAxisShift);
      const bool left = q[axis] < p[axis];
      const std::uint32_t near_child = 2 * node + (left ? 1 : 2);
      const std::uint32_t far_child = left ? near_child + 1 : near_child - 1;
      if (job_.node_nonempty(far_child)) {
        stack_pushes_.add(stack_base + token_.sp * sizeof(StackSlotEntry), cycles);
        stack[token_.sp++] = {far_child, plane_dist2(q, p, axis)};
      }
      if (!job_.node_nonempty(near_child)) break;
      node = near_child;
    }
    if (node >= job_.num_top_nodes && job_.node_nonempty(node)) {
      // CL: the query leaves for the back-end with the leaf set it must scan.
      token_.leaf = node - job_.num_top_nodes;
      node_reads_.add(job_.leaf_dir_offset + std::uint64_t{token_.leaf} * 4, cycles);  // its size
      return cycles + static_cast<std::uint64_t>(cost_.ru_drain);
    }
  }
  finished_ = true;  // the stack is empty: the query's results leave the RU
  return cycles + static_cast<std::uint64_t>(cost_.ru_drain + cost_.result_writeback);
}

void RecursionUnit::on_done() {
  const std::uint64_t now = job_.cycle();
  if (state_ == State::Blocked) stats_.bqb_full_stall_cycles += now - blocked_since_;
  stalled_wave_.set(0);
  if (!hits_.empty()) {  // results leave through the write-back stream, which may push back
    const std::uint64_t accepted = dram_.write(now, hits_.data(), hits_.size());
    hits_.clear();
    if (accepted > now) {
      stats_.writeback_stall_cycles += accepted - now;
      done_.notify((accepted - now) * job_.period);
      return;
    }
  }
  if (finished_) {
    state_ = State::Idle;
    busy_wave_.set(0);
    fe_.query_finished(token_, now);
    fe_.ru_idle(*this);
    return;
  }
  if (!qdn_.route(token_, now, *this)) {
    blocked_since_ = now;
    state_ = State::Blocked;
    stalled_wave_.set(1);
    return;  // the QDN calls retry_dispatch() when the BE Query Buffer has room
  }
  state_ = State::Idle;
  busy_wave_.set(0);
  fe_.ru_idle(*this);
}

void RecursionUnit::retry_dispatch() { done_.notify(sc_core::SC_ZERO_TIME); }

}  // namespace tigris::hw
