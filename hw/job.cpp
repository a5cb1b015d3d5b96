#include "job.hpp"

#include <algorithm>

#include "hw/mem/result_buffer.hpp"
#include "hw/mem/result_slots.hpp"

namespace tigris::hw {

std::uint64_t result_slot_bytes(std::uint32_t k, bool first_leaf) {
  return ResultSlots::slot_bytes(k) + (first_leaf ? 12 * std::uint64_t{k} : 0);
}

std::uint64_t queries_in_flight(const AcceleratorConfig& config, int top_height, tlm_if::SearchMode mode,
                                std::uint32_t k, bool approximate, bool first_leaf, std::uint64_t num_queries) {
  const bool radius = mode == tlm_if::SearchMode::Radius;
  const std::uint64_t slot_bytes = radius        ? 0
                                   : approximate ? result_slot_bytes(k, first_leaf)
                                                 : ResultSlots::slot_bytes(k);
  const std::uint64_t stack_slots =
      config.sram.query_stack.bytes / (std::uint64_t(std::max(top_height, 1)) * sizeof(StackEntry));
  const std::uint64_t fqq_entries = config.fe.fqq_bytes / static_cast<std::uint64_t>(config.fe.fqq_entry_bytes);
  return std::min({stack_slots, fqq_entries, ResultBuffer::slot_capacity(config, slot_bytes), num_queries});
}

std::string job_fit_error(const AcceleratorConfig& config, std::uint64_t image_bytes, std::uint64_t num_queries,
                          int top_height, tlm_if::SearchMode mode, std::uint32_t k, bool first_leaf) {
  const auto n = [](std::uint64_t x) { return std::to_string(x); };
  if (image_bytes > config.sram.points.bytes)
    return "the tree image needs " + n(image_bytes) + " bytes, the Point Buffer holds " + n(config.sram.points.bytes) +
           " (sram.points.bytes)";
  const std::uint64_t query_bytes = num_queries * sizeof(tlm_if::QueryRecord);
  if (query_bytes > config.sram.queries.bytes)
    return n(num_queries) + " queries need " + n(query_bytes) + " bytes, the Query Buffer holds " +
           n(config.sram.queries.bytes) + " (sram.queries.bytes)";
  if (num_queries == 0) return {};
  const std::uint64_t stack_bytes = std::uint64_t(std::max(top_height, 1)) * sizeof(StackEntry);
  if (stack_bytes > config.sram.query_stack.bytes)
    return "the Query Stack Buffer cannot hold one query's stack of top height " + std::to_string(top_height) + " (" +
           n(stack_bytes) + " bytes, sram.query_stack.bytes)";
  if (config.fe.fqq_bytes < static_cast<std::uint64_t>(config.fe.fqq_entry_bytes))
    return "the FE Query Queue cannot hold one query: fe.fqq_bytes = " + n(config.fe.fqq_bytes) +
           " holds no entry of fe.fqq_entry_bytes = " + std::to_string(config.fe.fqq_entry_bytes);
  if (mode != tlm_if::SearchMode::Radius && ResultBuffer::slot_capacity(config, result_slot_bytes(k, first_leaf)) == 0)
    return "the Result Buffer cannot hold one query's " + n(k) + " results" +
           (first_leaf ? " with their coordinates (approximate, leader.scope first_leaf)" : "") +
           " (sram.results.bytes x result_buffer.slot_fraction)";
  return {};
}

}  // namespace tigris::hw
