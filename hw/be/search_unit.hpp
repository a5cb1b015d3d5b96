// Search Unit (paper section 5.3): BE Query Buffer, query issue logic, systolic PE array and
// the Node Set stream from the Point Buffer (or the Node Cache). A batch is one work item: its
// cycles are the stream formula, stretched by the buffers' bank contention.
#pragma once

#include <cstdint>
#include <vector>

#include <systemc>

#include "hw/be/issue_policy.hpp"
#include "hw/be/node_cache.hpp"
#include "hw/config.hpp"
#include "hw/job.hpp"
#include "hw/mem/buffer_port.hpp"
#include "hw/probe.hpp"
#include "hw/stats.hpp"

namespace tigris::hw {

class FrontEnd;
class DistributionNetwork;
class ResultDram;

class SearchUnit : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(SearchUnit);
  BufferPort points, results;

  SearchUnit(sc_core::sc_module_name name, std::uint32_t id, const AcceleratorConfig& config,
             const IssuePolicy& policy, FrontEnd& fe, DistributionNetwork& qdn, NodeCache& cache,
             ResultDram& dram, Job& job);

  bool has_room() const { return bqb_.size() < capacity_; }
  std::size_t room() const { return capacity_ - bqb_.size(); }
  void accept(const QueryToken& token);  // from the QDN; the caller checked has_room()
  void reset();

  std::size_t bqb_occupancy() const { return bqb_.size(); }
  std::uint32_t busy_pes() const { return pes_ - free_pes_; }
  const SearchUnitStats& stats() const { return stats_; }
  void attach_waves(VcdWriter& vcd, const std::string& scope) {
    bqb_wave_.attach(vcd, scope + ".bqb_occupancy", 16);
    pes_wave_.attach(vcd, scope + ".busy_pes", 16);
    leaf_wave_.attach(vcd, scope + ".streaming_leaf", 32);
  }

 private:
  struct Batch {
    std::vector<QueryToken> tokens;
    std::vector<tlm_if::ResultRecord> hits;  // radius hits, streamed out at the end
    std::uint64_t end = 0;
    bool written = false;  // results handed to the Result Buffer / write-back stream
  };
  void step();  // SC_METHOD: retire finished batches, issue new ones
  void issue(std::vector<QueryToken> tokens, std::uint64_t now, std::uint64_t setup);
  std::uint64_t retire(Batch& batch);  // returns the cycle the queries may leave
  // The Result Buffer words of the batch's NN/kNN slots, as one scattered access.
  tlm_if::AccessProfile slot_access(const std::vector<QueryToken>& tokens, bool write);
  std::vector<std::uint64_t> slot_words_;

  std::uint32_t id_;
  const AcceleratorConfig& config_;
  const IssuePolicy& policy_;
  FrontEnd& fe_;
  DistributionNetwork& qdn_;
  NodeCache& cache_;
  ResultDram& dram_;
  Job& job_;
  std::size_t capacity_;
  std::uint32_t pes_, free_pes_;
  std::uint64_t busy_until_ = 0;
  std::vector<QueryToken> bqb_;
  std::vector<Batch> running_;
  sc_core::sc_event wake_;
  SearchUnitStats stats_;
  Probe bqb_wave_, pes_wave_, leaf_wave_;
};

}  // namespace tigris::hw
