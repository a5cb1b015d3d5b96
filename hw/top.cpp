#include "top.hpp"

#include <algorithm>
#include <cstring>
#include <sstream>

#include "hw/mem/result_slots.hpp"

namespace tigris::hw {

using namespace tlm_if;

TigrisAccelerator::TigrisAccelerator(sc_core::sc_module_name name, const AcceleratorConfig& config)
    : sc_module(name), config_(config), host("host"), irq("irq"),
      points_sram("points", config.sram.points, config.period()),
      queries_sram("queries", config.sram.queries, config.period()),
      stack_sram("query_stack", config.sram.query_stack, config.period()),
      results_sram("results", config.sram.results, config.period()),
      dram("dram", config_), node_cache(config_.node_cache.bytes), qdn(config_, job_),
      fe("fe", config_, qdn, dram, job_), policy_(make_issue_policy(config_)),
      to_points_("to_points"), to_queries_("to_queries"), to_dram_("to_dram") {
  job_.period = config.period();
  for (int i = 0; i < config.be.search_units; ++i)
    sus.push_back(std::make_unique<SearchUnit>(("su" + std::to_string(i)).c_str(),
                                               static_cast<std::uint32_t>(i), config_, *policy_,
                                               fe, qdn, node_cache, dram, job_));
  std::vector<SearchUnit*> units;
  for (auto& su : sus) {
    su->points.socket.bind(points_sram.socket);
    su->results.socket.bind(results_sram.socket);
    units.push_back(su.get());
  }
  qdn.connect(units);
  for (auto& ru : fe.rus) {
    ru->points.socket.bind(points_sram.socket);
    ru->queries.socket.bind(queries_sram.socket);
    ru->stacks.socket.bind(stack_sram.socket);
    ru->results.socket.bind(results_sram.socket);
  }
  to_points_.bind(points_sram.socket);
  to_queries_.bind(queries_sram.socket);
  to_dram_.bind(dram.socket);
  host.register_b_transport(this, &TigrisAccelerator::host_b_transport);
  host.register_transport_dbg(this, &TigrisAccelerator::host_transport_dbg);
  SC_METHOD(do_start);
  sensitive << start_;
  dont_initialize();
  SC_METHOD(do_finish);
  sensitive << finish_;
  dont_initialize();
}

void TigrisAccelerator::host_b_transport(tlm::tlm_generic_payload& trans, sc_core::sc_time& delay) {
  const std::uint64_t addr = trans.get_address();
  const std::uint64_t window = addr >= kResultDramBase ? kResultDramBase : addr & ~(kWindowSize - 1);
  trans.set_address(addr - window);
  if (window == kCsrBase) {
    csr_access(trans);
    delay += config_.cost.host_csr_access * job_.period;
  } else if (window == kPointBufferBase) {
    to_points_->b_transport(trans, delay);
  } else if (window == kQueryBufferBase) {
    to_queries_->b_transport(trans, delay);
  } else if (window == kResultDramBase) {
    to_dram_->b_transport(trans, delay);
  } else {
    trans.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
  }
  trans.set_address(addr);
}

unsigned int TigrisAccelerator::host_transport_dbg(tlm::tlm_generic_payload& trans) {
  const std::uint64_t addr = trans.get_address();
  const std::uint64_t window = addr & ~(kWindowSize - 1);
  trans.set_address(addr - window);
  unsigned int n = 0;
  if (window == kPointBufferBase) n = to_points_->transport_dbg(trans);
  if (window == kQueryBufferBase) n = to_queries_->transport_dbg(trans);
  trans.set_address(addr);
  return n;
}

void TigrisAccelerator::csr_access(tlm::tlm_generic_payload& trans) {
  const std::uint64_t offset = trans.get_address();
  if (trans.get_data_length() != 4 || offset % 4 != 0 || offset >= sizeof(csr_)) {
    trans.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
    return;
  }
  std::uint32_t& reg = csr_[offset / 4];
  if (trans.get_command() == tlm::TLM_READ_COMMAND) {
    std::memcpy(trans.get_data_ptr(), &reg, 4);
  } else if (trans.get_command() == tlm::TLM_WRITE_COMMAND) {
    std::uint32_t value;
    std::memcpy(&value, trans.get_data_ptr(), 4);
    if (offset == kCtrl) {
      if ((value & 1) && !(csr_[kStatus / 4] & kBusy)) {
        csr_[kStatus / 4] = kBusy;
        start_.notify(sc_core::SC_ZERO_TIME);
      }
    } else if (offset == kStatus) {
      csr_[kStatus / 4] &= value;  // write 0 clears done/error, and the interrupt with it
      if (!(csr_[kStatus / 4] & (kDone | kError))) irq.write(false);
    } else {
      reg = value;
    }
  }
  trans.set_response_status(tlm::TLM_OK_RESPONSE);
}

std::string TigrisAccelerator::configure_job() {
  Job& j = job_;
  const std::uint32_t mode = csr_[kMode / 4];
  if (mode > 2) return "CSR MODE holds " + std::to_string(mode) + ", not a search mode";
  j.mode = static_cast<SearchMode>(mode);
  j.k = j.mode == SearchMode::NN ? 1 : csr_[kK / 4];
  if (j.mode == SearchMode::KNN && j.k == 0) return "k must be >= 1";
  std::memcpy(&j.r2, &csr_[kRadius2Bits / 4], 4);
  j.num_points = csr_[kNumPoints / 4];
  j.num_queries = csr_[kNumQueries / 4];
  j.top_height = static_cast<int>(csr_[kTopHeight / 4]);
  j.num_top_nodes = csr_[kNumTopNodes / 4];
  j.num_leaves = csr_[kNumLeaves / 4];
  j.leaf_dir_offset = csr_[kLeafDirOffset / 4];
  const std::uint64_t image_end = std::uint64_t{j.num_top_nodes} * sizeof(PointEntry);
  if (j.top_height < 0 || j.top_height > 30 || j.num_top_nodes != (1u << j.top_height) - 1)
    return "CSR TOP_HEIGHT and NUM_TOP_NODES disagree";
  if (j.num_leaves != 0 && j.num_leaves != j.num_top_nodes + 1)
    return "CSR NUM_LEAVES must be 0 or 2^TOP_HEIGHT";
  const std::string fit = "the tree image does not fit the Point Buffer (" +
                          std::to_string(points_sram.size()) + " bytes, sram.points.bytes)";
  if (image_end > points_sram.size()) return fit;
  if (j.num_leaves) {
    if (j.leaf_dir_offset % 4 != 0) return "CSR LEAF_DIR_OFFSET is not a multiple of 4";
    if (std::uint64_t{j.leaf_dir_offset} + 4ull * (j.num_leaves + 1) > points_sram.size()) return fit;
    const auto* dir = reinterpret_cast<const std::uint32_t*>(points_sram.data() + j.leaf_dir_offset);
    for (std::uint32_t l = 0; l < j.num_leaves; ++l)
      if (dir[l] > dir[l + 1]) return "the leaf directory is not ascending at leaf " + std::to_string(l);
    if (dir[0] != 0 || (std::uint64_t{j.num_top_nodes} + dir[j.num_leaves]) * sizeof(PointEntry) > j.leaf_dir_offset)
      return "the leaf directory points outside the leaf sets";
  }
  if (std::uint64_t{j.num_queries} * 12 > queries_sram.size())
    return "the queries do not fit the Query Buffer";
  j.entries = reinterpret_cast<const PointEntry*>(points_sram.data());
  j.leaf_dir = reinterpret_cast<const std::uint32_t*>(points_sram.data() + j.leaf_dir_offset);
  j.queries = reinterpret_cast<const float*>(queries_sram.data());
  j.stack_entries = static_cast<std::uint32_t>(std::max(j.top_height, 1));
  const std::uint64_t stack_slots = stack_sram.size() / (j.stack_entries * sizeof(StackSlotEntry));
  const std::uint64_t fqq_entries = config_.fe.fqq_bytes / static_cast<std::uint64_t>(config_.fe.fqq_entry_bytes);
  j.result_slot_bytes = j.mode == SearchMode::Radius ? 0 : ResultSlots::slot_bytes(j.k);
  // At most half the Result Buffer holds query slots; the rest is the write-back stream.
  const std::uint64_t result_slots = j.result_slot_bytes ? results_sram.size() / 2 / j.result_slot_bytes : ~0ull;
  const std::uint64_t slots = std::min({stack_slots, fqq_entries, result_slots, std::uint64_t{j.num_queries}});
  if (slots == 0 && j.num_queries > 0) {
    if (stack_slots == 0) return "the Query Stack Buffer cannot hold one query's stack of top height " + std::to_string(j.top_height);
    if (fqq_entries == 0) return "the FE Query Queue cannot hold one query";
    return "the Result Buffer cannot hold one query's " + std::to_string(j.k) + " results";
  }
  j.slots = static_cast<std::uint32_t>(slots);
  j.stacks = reinterpret_cast<StackSlotEntry*>(stack_sram.data());
  j.result_slots = results_sram.data();
  j.counters.assign(j.num_queries, {});
  j.schedule.clear();
  dram.reset(results_sram.size() - slots * j.result_slot_bytes);
  return {};
}

void TigrisAccelerator::fail(std::uint32_t code) {
  csr_[kErrorCode / 4] = code;
  csr_[kStatus / 4] = kDone | kError;
  irq.write(true);
}

void TigrisAccelerator::do_start() {
  done_ = false;
  error_ = configure_job();
  if (!error_.empty()) {
    fail(1);
    return;
  }
  start_cycle_ = job_.cycle();
  for (BankedSram* b : {&points_sram, &queries_sram, &stack_sram, &results_sram}) b->reset_stats();
  dram.start(start_cycle_);
  qdn.reset();
  for (auto& su : sus) su->reset();
  node_cache.reset();
  fe.start([this](std::uint64_t cycle) {
    done_cycle_ = std::max(cycle, dram.drained_cycle());
    finish_.notify((done_cycle_ - job_.cycle()) * job_.period);
  });
  if (progress_) fe.set_progress(progress_);
}

void TigrisAccelerator::do_finish() {
  done_ = true;
  const std::uint64_t cycles = job_cycles();
  csr_[kCyclesLo / 4] = static_cast<std::uint32_t>(cycles);
  csr_[kCyclesHi / 4] = static_cast<std::uint32_t>(cycles >> 32);
  csr_[kResultBytesLo / 4] = static_cast<std::uint32_t>(dram.bytes());
  csr_[kResultBytesHi / 4] = static_cast<std::uint32_t>(dram.bytes() >> 32);
  csr_[kStatus / 4] = kDone;
  irq.write(true);
}

void TigrisAccelerator::attach_waves(VcdWriter& vcd) {
  const std::string scope = name();
  fe.attach_waves(vcd, scope + ".fe");
  for (std::size_t i = 0; i < sus.size(); ++i) sus[i]->attach_waves(vcd, scope + ".be.su" + std::to_string(i));
}

std::string TigrisAccelerator::describe_state() const {
  std::ostringstream s;
  s << "queries finished " << fe.finished() << " of " << job_.num_queries << ", admitted "
    << fe.admitted() << "; FQQ holds " << fe.fqq_occupancy() << "\n";
  for (const auto& ru : fe.rus)
    if (ru->busy_flag()) s << "  RU " << ru->id() << " holds query " << ru->current_query() << "\n";
  for (std::size_t i = 0; i < sus.size(); ++i)
    if (sus[i]->bqb_occupancy() || sus[i]->busy_pes())
      s << "  SU " << i << ": BE Query Buffer " << sus[i]->bqb_occupancy() << ", busy PEs "
        << sus[i]->busy_pes() << "\n";
  if (!error_.empty()) s << "  error: " << error_ << "\n";
  return s.str();
}

}  // namespace tigris::hw
