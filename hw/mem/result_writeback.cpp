#include "result_writeback.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace tigris::hw {

ResultWriteback::ResultWriteback(sc_core::sc_module_name name, const AcceleratorConfig& config, EnergyMeter& meter,
                                 JobObserver& observer)
    : sc_module(name), socket("socket"), config_(config.dram),
      host_bytes_per_cycle_(config.cost.host_link_bytes_per_cycle), clock_{config.period()},
      dram_energy_(meter.line("dram.write_bytes", EnergyMeter::Component::Dram, dram_price(meter.table()))),
      dram_read_energy_(meter.line("dram.read_bytes", EnergyMeter::Component::Dram, dram_price(meter.table()))),
      observer_(observer), stall_(config.stall, "writeback", stats_) {
  socket.register_b_transport(this, &ResultWriteback::b_transport);
}

double ResultWriteback::dram_price(const EnergyTable& table) {
  return table.charge_result_dram ? table.dram_pj_per_byte : 0.0;
}

void ResultWriteback::start(std::uint64_t cycle, std::uint64_t stream_buffer_bytes) {
  region_.clear();
  stall_.start();
  origin_ = cycle;
  drain_free_ = 0.0;
  last_accept_ = 0;
  buffer_bytes_ = std::max<std::uint64_t>(stream_buffer_bytes, sizeof(tlm_if::ResultRecord));
}

std::uint64_t ResultWriteback::write(std::uint64_t now, const tlm_if::ResultRecord* records, std::size_t n) {
  const std::uint64_t bytes_n = n * sizeof(tlm_if::ResultRecord);
  const double bytes = static_cast<double>(bytes_n);
  const double bw = config_.bytes_per_cycle;
  double accept = static_cast<double>(now - origin_ + stall_.draw());
  std::uint64_t accept_cycle = static_cast<std::uint64_t>(std::ceil(accept));
  std::uint64_t in_dram = accept_cycle;  // off the critical path: in DRAM as far as the job knows
  if (config_.writeback == Writeback::Channel) {
    // Backlog still in the stream buffer at `accept`: (drain_free_ - accept) * bw bytes.
    const double room_needed = bytes - static_cast<double>(buffer_bytes_);
    if (drain_free_ > accept && (drain_free_ - accept) * bw > -room_needed)
      accept = std::max(accept, drain_free_ + room_needed / bw);
    accept_cycle = static_cast<std::uint64_t>(std::ceil(accept));
    drain_free_ = std::max(drain_free_, static_cast<double>(accept_cycle)) + bytes / bw;
    if (backlog_wave_)
      backlog_wave_->set(static_cast<std::uint64_t>((drain_free_ - static_cast<double>(accept_cycle)) * bw));
    in_dram = static_cast<std::uint64_t>(std::ceil(drain_free_)) + static_cast<std::uint64_t>(config_.latency_cycles);
  }
  last_accept_ = std::max(last_accept_, accept_cycle);
  region_.append(records, bytes_n);
  writes_ += n;
  write_bytes_ += bytes_n;
  dram_energy_ += bytes_n;
  if (n > 0) observer_.writeback(records[0].query, n, origin_ + accept_cycle, origin_ + in_dram);
  return origin_ + accept_cycle;
}

std::uint64_t ResultWriteback::transfer(std::uint64_t now, std::uint64_t bytes, bool write) {
  const double begin = std::max(static_cast<double>(now - origin_), drain_free_);
  drain_free_ = begin + static_cast<double>(bytes) / config_.bytes_per_cycle;
  (write ? list_writes_ : list_reads_) += bytes;
  (write ? dram_energy_ : dram_read_energy_) += bytes;
  return origin_ + static_cast<std::uint64_t>(std::ceil(drain_free_)) +
         static_cast<std::uint64_t>(config_.latency_cycles);
}

std::uint64_t ResultWriteback::drained_cycle() const {
  // Off the critical path the job ends with its last record (and any leader-list transfer).
  const bool waits = config_.writeback == Writeback::Channel ? !region_.empty() : drain_free_ > 0.0;
  const auto latency = waits ? static_cast<std::uint64_t>(config_.latency_cycles) : 0;
  return origin_ + std::max(last_accept_, static_cast<std::uint64_t>(std::ceil(drain_free_)) + latency);
}

double ResultWriteback::backlog_bytes(std::uint64_t now) const {
  return std::max(0.0, drain_free_ - static_cast<double>(now - origin_)) * config_.bytes_per_cycle;
}

void ResultWriteback::set_backlog(std::uint64_t now, double bytes) {
  const double b = std::clamp(bytes, 0.0, static_cast<double>(buffer_bytes_));
  drain_free_ = static_cast<double>(now - origin_) + b / config_.bytes_per_cycle;
}

void ResultWriteback::b_transport(tlm::tlm_generic_payload& trans, sc_core::sc_time& delay) {
  const std::uint64_t addr = trans.get_address(), len = trans.get_data_length();
  if (trans.get_command() != tlm::TLM_READ_COMMAND) {
    trans.set_response_status(tlm::TLM_COMMAND_ERROR_RESPONSE);
    return;
  }
  if (addr > region_.size() || len > region_.size() - addr) {
    trans.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
    return;
  }
  region_.read(addr, trans.get_data_ptr(), len);
  ++reads_;
  read_bytes_ += len;
  delay += std::ceil(static_cast<double>(len) / host_bytes_per_cycle_) * clock_.period;
  trans.set_response_status(tlm::TLM_OK_RESPONSE);
}

}  // namespace tigris::hw
