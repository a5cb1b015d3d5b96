// The host side of a run (docs/architecture.md): writes the tree image and the queries through
// the accelerator's TLM-2.0 target socket, programs the CSRs, starts the job, waits for the
// done interrupt and reads the result stream back into canonical per-query results.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>

#include <tlm_utils/simple_initiator_socket.h>
#include <systemc>
#include <tlm>

#include "sw_ref/cloud.hpp"
#include "sw_ref/results.hpp"
#include "tlm/address_map.hpp"
#include "tlm/tree_image.hpp"

namespace tigris {

struct HostJob {
  tlm_if::SearchMode mode = tlm_if::SearchMode::NN;
  std::uint32_t k = 1;
  float radius = 0.0f;
  std::uint32_t max_nn = 0;        // radius: the host keeps the first max_nn of each query's hits
  bool approximate = false;        // leader/follower search (docs/model.md)
  bool first_leaf = true;          // ... with the leader check at a query's first leaf (else every leaf)
  bool wait_for_leaders = true;    // first_leaf: in-flight leaders count, followers wait (else finished only)
  float approx_thd = 0.0f;         // metres
  std::uint32_t leader_width = 1;  // R for NN/kNN
  int runs = 1;                    // the job is loaded and run this many times on one accelerator
};

// The job a golden-model search asks for (the testbench's translation into CSR terms).
struct SearchParams;
HostJob host_job(const SearchParams& params);

class HostDriver : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(HostDriver);
  tlm_utils::simple_initiator_socket<HostDriver> socket;
  sc_core::sc_in<bool> irq;

  HostDriver(sc_core::sc_module_name name, const tlm_if::TreeImage& image, const PointCloud& queries,
             std::uint32_t num_points, const HostJob& job);

  // Called after each run of the job, once its results are read (before the next run starts).
  void on_run_done(std::function<void(int run)> f) { on_run_done_ = std::move(f); }
  bool finished() const { return finished_; }
  const std::string& error() const { return error_; }  // empty when the job completed
  const Results& results() const { return results_; }
  Results take_results() { return std::move(results_); }  // after the run: no copy of a frame's lists
  std::uint64_t cycles() const { return cycles_; }

 private:
  void run();  // SC_THREAD: the job's runs, one after another
  void run_once();
  void write(std::uint64_t addr, const void* data, std::size_t len, const char* what);
  void read(std::uint64_t addr, void* data, std::size_t len);
  // One bus transaction; throws with `what` on an error response.
  void transport(tlm::tlm_command cmd, std::uint64_t addr, unsigned char* data, std::size_t len, const char* what);
  void write_csr(std::uint32_t offset, std::uint32_t value);
  std::uint32_t read_csr(std::uint32_t offset);
  void collect(std::uint64_t bytes);

  const tlm_if::TreeImage& image_;
  const PointCloud& queries_;
  std::uint32_t num_points_;
  HostJob job_;
  bool finished_ = false;
  std::string error_;
  Results results_;
  std::uint64_t cycles_ = 0;
  std::function<void(int)> on_run_done_;
};

}  // namespace tigris
