#include "tlm_walk.hpp"

#include <algorithm>

#include "hw/config.hpp"
#include "hw/job.hpp"
#include "hw/mem/banked_sram.hpp"
#include "hw/mem/buffer_port.hpp"
#include "hw/mem/result_slots.hpp"
#include "hw/tree_view.hpp"
#include "sw_ref/arith.hpp"

namespace tigris::hw {
namespace {

// The walk's buffer accesses, each requested when its step issues and held until granted;
// `done` is when the last of them ends.
struct WalkAccess {
  const WalkEngine::Ports& p;
  const AcceleratorConfig::Sram& sram;
  sc_core::sc_time period;
  std::uint64_t stack_base;
  std::uint64_t done;

  std::uint64_t pop_read(std::uint64_t cycle, std::uint32_t at) {
    return p.stacks.request(p.stacks_sram, cycle, stack_base + at * sizeof(StackEntry), sizeof(StackEntry), false,
                            sram.query_stack.latency_cycles, period, done);
  }
  std::uint64_t push_write(std::uint64_t cycle, std::uint32_t at) {
    return p.stacks.request(p.stacks_sram, cycle, stack_base + at * sizeof(StackEntry), sizeof(StackEntry), true,
                            sram.query_stack.latency_cycles, period, done);
  }
  std::uint64_t point_read(std::uint64_t cycle, std::uint64_t byte, std::uint32_t bytes) {
    return p.points.request(p.points_sram, cycle, byte, bytes, false, sram.points.latency_cycles, period, done);
  }
  std::uint64_t query_read(std::uint64_t cycle, std::uint32_t query) {
    return p.queries.request(p.queries_sram, cycle, std::uint64_t{query} * sizeof(tlm_if::QueryRecord),
                             sizeof(tlm_if::QueryRecord), false, sram.queries.latency_cycles, period, done);
  }
};

class TlmWalk final : public WalkEngine {
 public:
  explicit TlmWalk(const AcceleratorConfig& config) : config_(config), cost_(config.cost), period_(config.period()) {}
  Outcome walk(QueryToken& token, std::uint64_t now, const Ports& p) override;

 private:
  std::uint64_t fetch_query(QueryToken& token, std::uint64_t now, const Ports& p, WalkAccess& access,
                            StackEntry* stack) const;

  const AcceleratorConfig& config_;
  const CostTable& cost_;
  sc_core::sc_time period_;
};

// FQ: fetch the query point and its stack address; a new query's root goes into its stack.
// Returns when the fetch (and the push) are granted.
std::uint64_t TlmWalk::fetch_query(QueryToken& token, std::uint64_t now, const Ports& p, WalkAccess& access,
                                   StackEntry* stack) const {
  const tlm_if::QueryRecord& r = p.query_records[token.query];
  std::uint64_t granted = access.query_read(now, token.query);
  token.point = Point3{r.x, r.y, r.z};
  if (!token.started) {
    token.started = true;
    token.sp = 0;
    if (p.tree.node_nonempty(0)) {
      granted = std::max(granted, access.push_write(now, 0));
      stack[token.sp++] = {0, 0.0f};
    }
  }
  return granted;
}

WalkEngine::Outcome TlmWalk::walk(QueryToken& token, std::uint64_t now, const Ports& p) {
  Outcome o;
  std::uint32_t top = 0, pruned = 0;
  const JobDescriptor& job = p.job;
  const TreeView& tree = p.tree;
  StackEntry* stack = p.stacks_data + std::uint64_t{token.slot} * job.stack_entries;
  const bool forwarding = config_.fe.forwarding, bypassing = config_.fe.bypassing;
  // Every access is requested when its step issues and held until granted: a busy bank or
  // port stalls the whole walk there (`stall` so far), as the RTL RU's ports do (rtl/).
  WalkAccess access{p, config_.sram, period_, job.stack_base(token.slot), now};
  std::uint64_t stall = 0;
  const std::uint64_t granted = fetch_query(token, now, p, access, stack);
  const Point3 q = token.point;
  stall += granted - now;
  std::uint64_t cycles = static_cast<std::uint64_t>(cost_.ru_fetch_query);
  // The walk keeps its state in locals (written back on leaving): the pruning bound changes
  // only when an insert took a point.
  const bool radius = job.radius();
  const std::uint32_t slot = token.slot, top_nodes = tree.num_top_nodes();
  const std::uint64_t node_cycles =
      static_cast<std::uint64_t>(cost_.ru_node) + (forwarding ? 0 : static_cast<std::uint64_t>(cost_.ru_pi_rs_stall));
  const auto prune_cycles = static_cast<std::uint64_t>(bypassing ? cost_.ru_prune_at_rn : cost_.ru_prune_no_bypass);
  float bound = radius ? job.r2 : p.slots.bound(slot);
  std::uint32_t sp = token.sp;
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
      o.finished = true;
      cycles += static_cast<std::uint64_t>(cost_.ru_drain + cost_.result_writeback);
      break;
    }
    if (pushed) end = std::max(end, access.push_write(t, sp - 1));
    if (!forwarded) {
      // RS: pop the top of stack. RN: its distance information says whether it can be pruned.
      const StackEntry tos = stack[--sp];
      if (!pushed) end = node_from = std::max(end, access.pop_read(t, sp));
      pushed = false;
      if (tos.plane2 > bound) {
        ++pruned;
        cycles += prune_cycles;
        stall += end - t;
        continue;
      }
      node = tos.node;
    }
    forwarded = pushed = false;
    if (node >= top_nodes) {
      // CL: the query leaves for the back-end with the leaf set it must scan (its size read).
      token.leaf = node - top_nodes;
      end = std::max(end, access.point_read(node_from, tree.dir_address(token.leaf), sizeof(tlm_if::LeafDirEntry)));
      stall += end - t;
      cycles += static_cast<std::uint64_t>(cost_.ru_drain);
      break;
    }
    // RN: read the node; CD: its distance to the query; PI: insert into the result, push the
    // far child with its plane distance, forward the near child.
    const tlm_if::PointEntry& e = tree.node(node);
    if (node < p.replicated_nodes)  // the RU's own copy of the first levels
      ++o.replica_reads;
    else
      end = std::max(end, access.point_read(node_from, tree.node_address(node), sizeof(tlm_if::PointEntry)));
    stall += end - t;
    ++top;
    cycles += node_cycles;
    const Point3 pt{e.x, e.y, e.z};
    const float d = dist2(q, pt);
    // A point beyond the bound cannot enter the list (an equal one still may, by index).
    if (d <= bound) {
      const std::uint32_t index = e.tag & tlm_if::kIndexMask;
      if (radius)
        p.hits.push_back({token.query, index, d});
      else if (p.slots.insert(slot, {index, d}))
        bound = p.slots.bound(slot);
    }
    const int axis = static_cast<int>(e.tag >> tlm_if::kAxisShift);
    const bool left = q[axis] < pt[axis];
    const std::uint32_t near_child = 2 * node + (left ? 1 : 2);
    const std::uint32_t far_child = left ? near_child + 1 : near_child - 1;
    if (tree.node_nonempty(far_child)) {
      stack[sp++] = {far_child, plane_dist2(q, pt, axis)};
      pushed = true;
    }
    forwarded = tree.node_nonempty(near_child);
    next = near_child;
  }
  token.sp = static_cast<std::uint16_t>(sp);
  o.nodes = top;
  o.pruned = pruned;
  o.end = now + cycles + stall;
  o.done = std::max(access.done, o.end);
  o.grant_stalls = stall;
  return o;
}

}  // namespace

std::unique_ptr<WalkEngine> make_tlm_walk(const AcceleratorConfig& config) { return std::make_unique<TlmWalk>(config); }

}  // namespace tigris::hw
