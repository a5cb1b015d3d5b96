// The transactor between the Verilated RTL Recursion Unit (rtl/tigris_recursion_unit.sv) and
// the model: registers the "rtl" model of fe.recursion_unit_model (hw/fe/walk_engine.hpp).
//
// An activation is clocked cycle by cycle from the cycle it starts. Each request the RU makes
// is booked once, when it appears, in its buffer's bank calendar through the RU's BufferPort
// (the same charge the transaction-level RU makes, one access at a time), and granted in the
// cycle the calendar gives it; read data comes with the grant, from the buffers' DMI views.
// Within a cycle the ports settle in a few evaluations: a pop's data picks the node read in the
// same cycle. The result slot is outside the RU: a candidate the RU offers is inserted after the
// clock edge and the slot's new bound is the RU's input from the next cycle on.
#include <cstring>
#include <memory>
#include <stdexcept>

#include "Vtigris_ru.h"
#include "hw/config.hpp"
#include "hw/fe/walk_engine.hpp"
#include "hw/job.hpp"
#include "hw/mem/buffer_port.hpp"
#include "hw/mem/result_slots.hpp"
#include "hw/tree_view.hpp"
#include "tlm/address_map.hpp"
#include "verilated.h"

namespace tigris::hw {
namespace {

std::uint32_t bits(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  return b;
}
float from_bits(std::uint32_t b) {
  float f;
  std::memcpy(&f, &b, sizeof f);
  return f;
}

class RtlRecursionUnit final : public WalkEngine {
 public:
  explicit RtlRecursionUnit(const AcceleratorConfig& config)
      : config_(config), context_(std::make_unique<VerilatedContext>()),
        ru_(std::make_unique<Vtigris_ru>(context_.get(), "ru")) {
    ru_->rst = 1;
    tick();
    tick();
    ru_->rst = 0;
    ru_->eval();
  }
  ~RtlRecursionUnit() override { ru_->final(); }

  Outcome walk(QueryToken& token, std::uint64_t now, const Ports& p) override {
    Vtigris_ru& ru = *ru_;
    ru.cfg_forwarding = config_.fe.forwarding;
    ru.cfg_bypassing = config_.fe.bypassing;
    ru.cfg_root_nonempty = p.tree.node_nonempty(0);
    ru.cfg_top_nodes = p.tree.num_top_nodes();
    ru.cfg_replicated_nodes = p.replicated_nodes;
    const bool radius = p.job.radius();
    ru.bound = bits(radius ? p.job.r2 : p.slots.bound(token.slot));
    ru.tok_query = token.query;
    ru.tok_stack_base = token.slot * p.job.stack_entries;
    ru.tok_started = token.started;
    ru.tok_sp = token.sp;
    ru.tok_valid = 1;
    tick();  // the RU takes the token: cycle 0 is its FQ
    ru.tok_valid = 0;

    Outcome o;
    Port qb{p.queries, config_.sram.queries.latency_cycles}, pb{p.points, config_.sram.points.latency_cycles},
        qs_rd{p.stacks, config_.sram.query_stack.latency_cycles},
        qs_wr{p.stacks, config_.sram.query_stack.latency_cycles};
    for (std::uint64_t cycle = now;; ++cycle) {
      settle(cycle, p, qb, pb, qs_rd, qs_wr, o);
      if ((ru.qb_req && !ru.qb_gnt) || (ru.pb_req && !ru.pb_gnt) || (ru.qs_rd_req && !ru.qs_rd_gnt) ||
          (ru.qs_wr_req && !ru.qs_wr_gnt))
        ++o.grant_stalls;
      if (ru.qs_wr_gnt) p.stacks_data[ru.qs_wr_index] = StackEntry{ru.qs_wr_node, from_bits(ru.qs_wr_plane2)};
      const bool candidate = ru.cand_valid, advance = ru.advance, done = ru.done_valid;
      const Neighbor n{ru.cand_index, from_bits(ru.cand_dist2)};
      if (done) {
        o.finished = ru.done_finished;
        token.leaf = ru.done_leaf;
        token.sp = ru.done_sp;
      }
      tick();
      if (advance) qb.booked = pb.booked = qs_rd.booked = qs_wr.booked = false;
      if (candidate) {
        if (radius) {
          p.hits.push_back({token.query, n.index, n.dist2});
        } else if (p.slots.insert(token.slot, n)) {
          ru.bound = bits(p.slots.bound(token.slot));
        }
      }
      if (done) {
        o.end = cycle + 1;
        break;
      }
      if (cycle - now > kMaxActivationCycles)
        throw std::runtime_error("rtl recursion unit: an activation of query " + std::to_string(token.query) +
                                 " did not end within " + std::to_string(kMaxActivationCycles) + " cycles");
    }
    o.nodes = ru.cnt_nodes;
    o.pruned = ru.cnt_pruned;
    o.done = std::max(o.end, o.done);
    token.started = true;
    token.point = point_;
    return o;
  }

 private:
  static constexpr std::uint64_t kMaxActivationCycles = std::uint64_t{1} << 32;
  // A port's request being served: booked when it appeared, granted from `grant` on.
  struct Port {
    BufferPort& port;
    int latency;
    bool booked = false;
    std::uint64_t grant = 0;
    // Books one access from `cycle`; raises `complete` to the cycle its data is complete.
    void book(std::uint64_t cycle, std::uint64_t byte, std::uint32_t bytes, bool write, const sc_core::sc_time& period,
              std::uint64_t& complete) {
      grant = port.request(cycle, byte, bytes, write, latency, period, complete);
      booked = true;
    }
  };

  void tick() {
    ru_->clk = 1;
    ru_->eval();
    ru_->clk = 0;
    ru_->eval();
  }

  // Evaluates the RU until its requests and grants stop changing in this cycle.
  void settle(std::uint64_t cycle, const Ports& p, Port& qb, Port& pb, Port& qs_rd, Port& qs_wr, Outcome& o) {
    Vtigris_ru& ru = *ru_;
    const sc_core::sc_time period = config_.period();
    ru.qb_gnt = ru.pb_gnt = ru.qs_rd_gnt = ru.qs_wr_gnt = 0;
    for (int pass = 0; pass < 8; ++pass) {
      ru.eval();
      bool changed = false;
      const auto serve = [&](Port& port, bool req, unsigned char& gnt, auto book) {
        if (req && !port.booked) book(), changed = true;
        const unsigned char g = req && port.booked && cycle >= port.grant;
        if (g != gnt) gnt = g, changed = true;
      };
      serve(qb, ru.qb_req, ru.qb_gnt, [&] {
        qb.book(cycle, std::uint64_t{ru.qb_index} * sizeof(tlm_if::QueryRecord), sizeof(tlm_if::QueryRecord), false,
                period, o.done);
      });
      if (ru.pb_req && ru.pb_replica) {  // the RU's own copy: no bank
        if (!pb.booked) pb.booked = true, pb.grant = cycle, ++o.replica_reads, changed = true;
      }
      serve(pb, ru.pb_req, ru.pb_gnt, [&] {
        if (ru.pb_dir)
          pb.book(cycle, p.tree.dir_address(ru.pb_index), sizeof(tlm_if::LeafDirEntry), false, period, o.done);
        else
          pb.book(cycle, p.tree.node_address(ru.pb_index), sizeof(tlm_if::PointEntry), false, period, o.done);
      });
      serve(qs_rd, ru.qs_rd_req, ru.qs_rd_gnt, [&] {
        qs_rd.book(cycle, std::uint64_t{ru.qs_rd_index} * sizeof(StackEntry), sizeof(StackEntry), false, period,
                   o.done);
      });
      serve(qs_wr, ru.qs_wr_req, ru.qs_wr_gnt, [&] {
        qs_wr.book(cycle, std::uint64_t{ru.qs_wr_index} * sizeof(StackEntry), sizeof(StackEntry), true, period, o.done);
      });
      // Read data with the grants.
      if (ru.qb_gnt) {
        const tlm_if::QueryRecord& r = p.query_records[ru.qb_index];
        ru.qb_x = bits(r.x), ru.qb_y = bits(r.y), ru.qb_z = bits(r.z);
        point_ = Point3{r.x, r.y, r.z};
      }
      if (ru.pb_gnt && !ru.pb_dir) {
        const tlm_if::PointEntry& e = p.tree.node(ru.pb_index);
        ru.pb_x = bits(e.x), ru.pb_y = bits(e.y), ru.pb_z = bits(e.z), ru.pb_tag = e.tag;
        const std::uint32_t left = 2 * ru.pb_index + 1;
        ru.pb_child_nonempty =
            static_cast<unsigned char>((p.tree.node_nonempty(left) ? 1 : 0) | (p.tree.node_nonempty(left + 1) ? 2 : 0));
      }
      if (ru.qs_rd_gnt) {
        const StackEntry& e = p.stacks_data[ru.qs_rd_index];
        ru.qs_rd_node = e.node, ru.qs_rd_plane2 = bits(e.plane2);
      }
      if (!changed) return;
    }
    throw std::logic_error("rtl recursion unit: its ports did not settle within a cycle");
  }

  const AcceleratorConfig& config_;
  std::unique_ptr<VerilatedContext> context_;
  std::unique_ptr<Vtigris_ru> ru_;
  Point3 point_;
};

const bool kRegistered = RecursionUnitModels::add(
    "rtl", "the RTL Recursion Unit (rtl/), Verilated and clocked cycle by cycle; for the cross-check",
    [](const AcceleratorConfig& c) { return std::unique_ptr<WalkEngine>(std::make_unique<RtlRecursionUnit>(c)); });

}  // namespace
}  // namespace tigris::hw
