#include "leader_buffer.hpp"

#include <algorithm>
#include <cstring>

namespace tigris::hw {

LeaderBuffer::LeaderBuffer(std::uint32_t su, const AcceleratorConfig& config, EnergyMeter& meter)
    : su_(su), sus_(static_cast<std::uint32_t>(config.be.search_units)),
      capacity_(static_cast<std::uint32_t>(config.leader.capacity_per_leaf)),
      resident_(config.result_buffer.leader_lists == LeaderLists::Resident), stats_("leader_buffer", "leader_buffer"),
      read_energy_(meter.line("leader_buffer.read_bytes", EnergyMeter::Component::LeaderBuffer,
                              meter.table().leader_buffer_pj_per_byte)),
      write_energy_(meter.line("leader_buffer.write_bytes", EnergyMeter::Component::LeaderBuffer,
                               meter.table().leader_buffer_pj_per_byte)) {}

void LeaderBuffer::start(const JobDescriptor& job, std::uint8_t* result_buffer) {
  leaves_.assign(job.approximate ? (job.num_leaves + sus_ - 1) / sus_ : 0, {});
  capacity_ = job.leader_capacity;
  // Equal shares of the area, whole list entries each, so lists never straddle two SUs.
  const std::uint64_t share = job.leader_area_bytes / sus_ / kListEntryBytes * kListEntryBytes;
  area_base_ = job.leader_area_base + su_ * share;
  area_ = result_buffer + area_base_;
  area_bytes_ = share;
  area_used_ = 0;
  overflow_.clear();
}

std::size_t LeaderBuffer::append(std::uint32_t leaf, const Point3& point, const std::vector<tlm_if::PointEntry>& list) {
  const std::size_t i = reserve(leaf, point);
  fill(leaf, i, list);
  return i;
}

std::size_t LeaderBuffer::reserve(std::uint32_t leaf, const Point3& point) {
  std::vector<Leader>& here = leaves_[slot(leaf)];
  Leader l;
  l.point = point;
  l.pending = true;
  here.push_back(std::move(l));
  write_bytes_ += kLeaderBytes;
  write_energy_ += kLeaderBytes;
  max_leaders_.max(here.size());
  return here.size() - 1;
}

void LeaderBuffer::fill(std::uint32_t leaf, std::size_t index, const std::vector<tlm_if::PointEntry>& list) {
  Leader& l = leaves_[slot(leaf)][index];
  l.pending = false;
  store_list(l, list);
}

void LeaderBuffer::store_list(Leader& l, const std::vector<tlm_if::PointEntry>& list) {
  l.list_length = static_cast<std::uint32_t>(list.size());
  const std::uint64_t bytes = list.size() * kListEntryBytes;
  if (area_used_ + bytes <= area_bytes_) {
    l.list_address = area_base_ + area_used_;
    if (bytes) std::memcpy(area_ + area_used_, list.data(), bytes);
    area_used_ += bytes;
  } else {
    // The list's entries go to the overflow store; its bytes cross the channel (spill) or stay
    // in the Result Buffer at a wrapped address (resident).
    l.overflowed = true;
    l.list_address = overflow_.size() * kListEntryBytes;
    overflow_.insert(overflow_.end(), list.begin(), list.end());
    ++(resident_ ? resident_overflow_ : dram_lists_);
  }
  list_bytes_ += bytes;
}

const tlm_if::PointEntry* LeaderBuffer::list(const Leader& l) const {
  if (l.overflowed) return overflow_.data() + l.list_address / kListEntryBytes;
  return reinterpret_cast<const tlm_if::PointEntry*>(area_ + (l.list_address - area_base_));
}

}  // namespace tigris::hw
