#include "top.hpp"

#include <algorithm>
#include <cstring>
#include <sstream>

#include "hw/mem/result_slots.hpp"

namespace tigris::hw {

using namespace tlm_if;

TigrisAccelerator::TigrisAccelerator(sc_core::sc_module_name name, const AcceleratorConfig& config,
                                     const HostOptions& host_options)
    : sc_module(name), config_(config), meter_(config_.energy), scans_(make_scan_service(host_options.scan_thread)),
      host("host"), irq("irq"), clock_{config_.period()}, scheduler_("scheduler", clock_),
      points_("points", config_.sram.points, clock_, meter_, config_.stall),
      queries_("queries", config_.sram.queries, clock_, meter_, config_.stall),
      query_stack_("query_stack", config_.sram.query_stack, clock_, meter_, config_.stall),
      result_buffer_("result_buffer", config_, meter_, observers_), node_cache_("node_cache", config_, meter_),
      qdn_("qdn", config_, observers_), fe_("fe", config_, job_, qdn_, result_buffer_, meter_, observers_, scheduler_,
                                            *scans_, host_options.reverse_construction),
      to_points_("to_points"), to_queries_("to_queries"), to_dram_("to_dram") {
  const SearchUnit::Links links{fe_, qdn_, node_cache_, result_buffer_, meter_, observers_, scheduler_, *scans_};
  const int n = config_.be.search_units;
  sus_.resize(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const int i = host_options.reverse_construction ? n - 1 - k : k;
    sus_[static_cast<std::size_t>(i)] = std::make_unique<SearchUnit>(
        ("su" + std::to_string(i)).c_str(), static_cast<std::uint32_t>(i), config_, job_, links);
  }
  std::vector<SearchUnit*> units;
  for (auto& su_ptr : sus_) {
    SearchUnit& su = *su_ptr;
    su.points.socket.bind(points_.socket);
    su.results.socket.bind(result_buffer_.socket());
    be_stats_.add(su.stats());
    units.push_back(&su);
  }
  qdn_.connect(units);
  for (auto& ru : fe_.rus) {
    ru->points.socket.bind(points_.socket);
    ru->queries.socket.bind(queries_.socket);
    ru->stacks.socket.bind(query_stack_.socket);
    ru->results.socket.bind(result_buffer_.socket());
  }
  for (StatGroup* g :
       {&fe_.stats(), &qdn_.stats(), &be_stats_, &points_.stats(), &queries_.stats(), &query_stack_.stats(),
        &result_buffer_.sram_stats(), &node_cache_.stats(), &result_buffer_.dram_stats(), &meter_.stats()})
    stats_.add(*g);
  to_points_.socket.bind(points_.socket);
  to_queries_.socket.bind(queries_.socket);
  to_dram_.bind(result_buffer_.dram_socket());
  host.register_b_transport(this, &TigrisAccelerator::host_b_transport);
  host.register_transport_dbg(this, &TigrisAccelerator::host_transport_dbg);
  SC_METHOD(do_start);
  sensitive << start_;
  dont_initialize();
  SC_METHOD(do_finish);
  sensitive << finish_;
  dont_initialize();
  SC_METHOD(drive_irq);
  sensitive << irq_changed_;
  dont_initialize();
}

void TigrisAccelerator::drive_irq() { irq.write((csr_[kStatus / 4] & (kDone | kError)) != 0); }

void TigrisAccelerator::host_b_transport(tlm::tlm_generic_payload& trans, sc_core::sc_time& delay) {
  const std::uint64_t addr = trans.get_address();
  const std::uint64_t window = addr >= kResultDramBase ? kResultDramBase : addr & ~(kWindowSize - 1);
  trans.set_address(addr - window);
  if (window == kCsrBase) {
    csr_access(trans);
    delay += config_.cost.host_csr_access * clock_.period;
  } else if (window == kPointBufferBase) {
    to_points_.socket->b_transport(trans, delay);
  } else if (window == kQueryBufferBase) {
    to_queries_.socket->b_transport(trans, delay);
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
  if (window == kPointBufferBase) n = to_points_.socket->transport_dbg(trans);
  if (window == kQueryBufferBase) n = to_queries_.socket->transport_dbg(trans);
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
      irq_changed_.notify(sc_core::SC_ZERO_TIME);
    } else {
      reg = value;
    }
  }
  trans.set_response_status(tlm::TLM_OK_RESPONSE);
}

std::string TigrisAccelerator::configure_job() {
  JobDescriptor j;
  const std::uint32_t mode = csr_[kMode / 4];
  if (mode > 2) return "CSR MODE holds " + std::to_string(mode) + ", not a search mode";
  j.mode = static_cast<SearchMode>(mode);
  j.k = j.mode == SearchMode::NN ? 1 : csr_[kK / 4];
  if (j.mode == SearchMode::KNN && j.k == 0) return "k must be >= 1";
  std::memcpy(&j.r2, &csr_[kRadius2Bits / 4], 4);
  j.num_queries = csr_[kNumQueries / 4];
  j.top_height = static_cast<int>(csr_[kTopHeight / 4]);
  j.num_top_nodes = csr_[kNumTopNodes / 4];
  j.num_leaves = csr_[kNumLeaves / 4];
  j.leaf_dir_offset = csr_[kLeafDirOffset / 4];
  if (j.top_height < 0 || j.top_height > 30 || j.num_top_nodes != (1u << j.top_height) - 1)
    return "CSR TOP_HEIGHT and NUM_TOP_NODES disagree";
  if (j.num_leaves != 0 && j.num_leaves != j.num_top_nodes + 1) return "CSR NUM_LEAVES must be 0 or 2^TOP_HEIGHT";
  if (j.num_leaves && j.leaf_dir_offset % sizeof(LeafDirEntry) != 0)
    return "CSR LEAF_DIR_OFFSET is not a multiple of 4";
  const std::uint64_t image_bytes =
      j.num_leaves ? std::uint64_t{j.leaf_dir_offset} + sizeof(LeafDirEntry) * (std::uint64_t{j.num_leaves} + 1)
                   : std::uint64_t{j.num_top_nodes} * sizeof(PointEntry);
  j.result_slot_bytes = j.radius() ? 0 : ResultSlots::slot_bytes(j.k);
  if (csr_[kApprox / 4] > 3) return "CSR APPROX holds " + std::to_string(csr_[kApprox / 4]) + ", not 0 to 3";
  j.approximate = csr_[kApprox / 4] != 0;
  j.first_leaf = csr_[kApprox / 4] >= 2;
  j.wait_for_leaders = csr_[kApprox / 4] == 2;
  if (j.approximate) {
    std::memcpy(&j.thd2, &csr_[kApproxThd2Bits / 4], 4);
    if (!(j.thd2 >= 0.0f)) return "CSR APPROX_THD2 is not a number >= 0";
    j.leader_width = j.radius() || j.first_leaf ? 0 : csr_[kLeaderWidth / 4];
    if (!j.radius() && !j.first_leaf && j.leader_width == 0) return "CSR LEADER_WIDTH must be >= 1 for NN/kNN";
    j.leader_capacity = static_cast<std::uint32_t>(config_.leader.capacity_per_leaf);
    if (!j.radius()) j.result_slot_bytes = result_slot_bytes(j.k, j.first_leaf);
  }
  const std::string fit =
      job_fit_error(config_, image_bytes, j.num_queries, j.top_height, j.mode, j.k, j.approximate && j.first_leaf);
  if (!fit.empty()) return fit;
  if (j.num_leaves) {
    const auto* dir = reinterpret_cast<const LeafDirEntry*>(to_points_.data() + j.leaf_dir_offset);
    for (std::uint32_t l = 0; l < j.num_leaves; ++l)
      if (dir[l] > dir[l + 1]) return "the leaf directory is not ascending at leaf " + std::to_string(l);
    if (dir[0] != 0 || (std::uint64_t{j.num_top_nodes} + dir[j.num_leaves]) * sizeof(PointEntry) > j.leaf_dir_offset)
      return "the leaf directory points outside the leaf sets";
  }
  j.stack_entries = static_cast<std::uint32_t>(std::max(j.top_height, 1));
  j.slots = static_cast<std::uint32_t>(
      queries_in_flight(config_, j.top_height, j.mode, j.k, j.approximate, j.first_leaf, j.num_queries));
  if (j.approximate) {
    j.leader_area_base = j.slots * j.result_slot_bytes;
    j.leader_area_bytes = ResultBuffer::leader_area_bytes(config_);
  }
  job_ = j;
  return {};
}

void TigrisAccelerator::fail(std::uint32_t code) {
  csr_[kErrorCode / 4] = code;
  csr_[kStatus / 4] = kDone | kError;
  irq_changed_.notify(sc_core::SC_ZERO_TIME);
}

void TigrisAccelerator::do_start() {
  done_ = false;
  stats_.reset();  // a new job counts from zero; the host's loads are not its traffic
  error_ = configure_job();
  if (!error_.empty()) {
    fail(1);
    return;
  }
  start_cycle_ = clock_.now();
  scheduler_.reset();
  for (BankedSram* b : {&points_, &queries_, &query_stack_}) b->start();
  result_buffer_.start(start_cycle_, job_.slots, job_.result_slot_bytes, job_.leader_area_bytes);
  qdn_.start();
  scans_->start(job_, TreeView(to_points_.data(), job_));
  result_buffer_.leader_staging().start(job_, TreeView(to_points_.data(), job_));
  for (auto& su : sus_) su->start();
  node_cache_.start();
  observers_.job_started(job_.num_queries);
  fe_.start([this](std::uint64_t cycle) {
    done_cycle_ = std::max(cycle, result_buffer_.drained_cycle());
    finish_.notify(clock_.until(done_cycle_));
  });
  if (progress_) fe_.set_progress(progress_);
}

void TigrisAccelerator::do_finish() {
  done_ = true;
  for (auto& su : sus_) su->finish();
  const std::uint64_t cycles = job_cycles();
  csr_[kCyclesLo / 4] = static_cast<std::uint32_t>(cycles);
  csr_[kCyclesHi / 4] = static_cast<std::uint32_t>(cycles >> 32);
  const std::uint64_t bytes = result_buffer_.streamed_bytes();
  csr_[kResultBytesLo / 4] = static_cast<std::uint32_t>(bytes);
  csr_[kResultBytesHi / 4] = static_cast<std::uint32_t>(bytes >> 32);
  csr_[kStatus / 4] = kDone;
  irq_changed_.notify(sc_core::SC_ZERO_TIME);
}

void TigrisAccelerator::time_through_transport_for_test() {
  for (auto& ru : fe_.rus)
    for (BufferPort* p : {&ru->points, &ru->queries, &ru->stacks, &ru->results}) p->use_transport_for_timing();
  for (auto& su : sus_)
    for (BufferPort* p : {&su->points, &su->results}) p->use_transport_for_timing();
}

void TigrisAccelerator::attach_waves(VcdWriter& vcd) {
  const std::string scope = name();
  // Declared first, so a viewer lists them first: the whole machine at a glance.
  const std::string all = scope + ".all.";
  waves_.rus_busy.attach(vcd, all + "rus_busy", 16);
  waves_.rus_sram_stall.attach(vcd, all + "rus_sram_stall", 16);
  waves_.rus_bqb_full_stall.attach(vcd, all + "rus_bqb_full_stall", 16);
  waves_.rus_writeback_stall.attach(vcd, all + "rus_writeback_stall", 16);
  waves_.busy_pes.attach(vcd, all + "busy_pes", 32);
  waves_.pes_sram_stall.attach(vcd, all + "pes_sram_stall", 32);
  waves_.pes_writeback_stall.attach(vcd, all + "pes_writeback_stall", 32);
  waves_.bqb_occupancy.attach(vcd, all + "bqb_occupancy", 32);
  waves_.writeback_backlog.attach(vcd, all + "writeback_backlog_bytes", 32);
  waves_.queries_finished.attach(vcd, all + "queries_finished", 32);
  result_buffer_.attach_waves(waves_.writeback_backlog);
  fe_.attach_waves(vcd, scope + ".fe", waves_);
  for (std::size_t i = 0; i < sus_.size(); ++i)
    sus_[i]->attach_waves(vcd, scope + ".be.su" + std::to_string(i), waves_);
}

std::string TigrisAccelerator::describe_state() const {
  std::ostringstream s;
  std::size_t held = fe_.fqq_occupancy();
  s << "queries finished " << fe_.finished() << " of " << job_.num_queries << ", admitted " << fe_.admitted() << " ("
    << fe_.admitted() - fe_.finished() << " in flight); FE Query Queue holds " << fe_.fqq_occupancy() << "\n";
  for (const auto& ru : fe_.rus) {
    if (!ru->busy_flag()) continue;
    ++held;
    s << "  RU " << ru->id() << " holds query " << ru->current_query();
    if (ru->blocked())
      s << ", blocked: waits for room in the BE Query Buffer of SU " << ru->blocked_leaf() % sus_.size() << " (leaf "
        << ru->blocked_leaf() << ")";
    s << "\n";
  }
  for (std::size_t i = 0; i < sus_.size(); ++i) {
    held += sus_[i]->bqb_occupancy() + sus_[i]->busy_pes();
    if (sus_[i]->bqb_occupancy() || sus_[i]->busy_pes())
      s << "  SU " << i << ": BE Query Buffer " << sus_[i]->bqb_occupancy() << " of " << config_.be.bqb_entries
        << ", busy PEs " << sus_[i]->busy_pes() << " of " << config_.be.pes_per_su << "\n";
  }
  const std::size_t in_flight = fe_.admitted() - fe_.finished();
  if (held < in_flight) s << "  " << in_flight - held << " admitted queries are held by no queue or unit (lost)\n";
  if (!error_.empty()) s << "  error: " << error_ << "\n";
  return s.str();
}

}  // namespace tigris::hw
