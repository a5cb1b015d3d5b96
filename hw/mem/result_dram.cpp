#include "result_dram.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace tigris::hw {

ResultDram::ResultDram(sc_core::sc_module_name name, const AcceleratorConfig& config)
    : sc_module(name), socket("socket"), config_(config.dram),
      host_bytes_per_cycle_(config.cost.host_link_bytes_per_cycle), period_(config.period()) {
  socket.register_b_transport(this, &ResultDram::b_transport);
}

void ResultDram::reset(std::uint64_t stream_buffer_bytes) {
  region_.clear();
  drain_free_ = 0.0;
  buffer_bytes_ = std::max<std::uint64_t>(stream_buffer_bytes, sizeof(tlm_if::ResultRecord));
  stall_cycles_ = 0;
}

std::uint64_t ResultDram::write(std::uint64_t now, const tlm_if::ResultRecord* records, std::size_t n) {
  const double bytes = static_cast<double>(n * sizeof(tlm_if::ResultRecord));
  const double bw = config_.bytes_per_cycle;
  // Backlog still in the stream buffer at `accept`: (drain_free_ - accept) * bw bytes.
  double accept = static_cast<double>(now);
  const double room_needed = bytes - static_cast<double>(buffer_bytes_);
  if (drain_free_ > accept && (drain_free_ - accept) * bw > -room_needed)
    accept = std::max(accept, drain_free_ + room_needed / bw);
  const auto accept_cycle = static_cast<std::uint64_t>(std::ceil(accept));
  stall_cycles_ += accept_cycle - now;
  drain_free_ = std::max(drain_free_, static_cast<double>(accept_cycle)) + bytes / bw;
  const std::size_t old = region_.size();
  region_.resize(old + n * sizeof(tlm_if::ResultRecord));
  std::memcpy(region_.data() + old, records, n * sizeof(tlm_if::ResultRecord));
  return accept_cycle;
}

std::uint64_t ResultDram::drained_cycle() const {
  const auto latency = region_.empty() ? 0 : static_cast<std::uint64_t>(config_.latency_cycles);
  return static_cast<std::uint64_t>(std::ceil(drain_free_)) + latency;
}

void ResultDram::b_transport(tlm::tlm_generic_payload& trans, sc_core::sc_time& delay) {
  const std::uint64_t addr = trans.get_address(), len = trans.get_data_length();
  if (trans.get_command() != tlm::TLM_READ_COMMAND) {
    trans.set_response_status(tlm::TLM_COMMAND_ERROR_RESPONSE);
    return;
  }
  if (addr > region_.size() || len > region_.size() - addr) {
    trans.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
    return;
  }
  std::memcpy(trans.get_data_ptr(), region_.data() + addr, len);
  delay += std::ceil(static_cast<double>(len) / host_bytes_per_cycle_) * period_;
  trans.set_response_status(tlm::TLM_OK_RESPONSE);
}

}  // namespace tigris::hw
