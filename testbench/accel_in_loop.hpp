// The accelerator model in the registration loop (`tigris register --search accel`):
// the search plug-in hands each announced query set over as one job (registration/
// accelerator_port.hpp); this runs it through the model, checks every query against the
// golden model and sends the results and the modeled cost back. A job searching another tree
// than the job before it pays for the tree image on the host link, as in `tigris run --trace`.
//
// Processes: SystemC elaborates once per process, so every job runs in a process of its own.
// Forking those from the registration would write-protect its (large) memory at every job and
// slow its own CPU work, which is measured; so a small model server is forked once, when this
// object is made (make it before loading clouds), and it forks a process per job. The
// registration talks to it over a socket: the tree's points when the tree changes, the
// queries and parameters of each job; the answers come back the same way.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "accel_job.hpp"
#include "hw/config.hpp"
#include "registration/accelerator_port.hpp"
#include "sw_ref/work_guard.hpp"

namespace tigris {

class ModelInTheLoop : public registration::AcceleratorPort {
 public:
  // Starts the model server (std::runtime_error when it cannot); `side_by_side` 2 starts a
  // second one, for a prefetched job to run beside the job run() runs.
  ModelInTheLoop(hw::AcceleratorConfig config, WorkLimits limits, int sim_threads, int side_by_side = 1);
  ~ModelInTheLoop() override;  // stops the server
  ModelInTheLoop(const ModelInTheLoop&) = delete;
  ModelInTheLoop& operator=(const ModelInTheLoop&) = delete;

  // Throws registration::AcceleratorFailure on a golden mismatch or a deadlock (the message
  // names the first differing queries), std::invalid_argument when the job cannot run (e.g.
  // it does not fit the buffers), std::runtime_error when the model's process failed.
  registration::AccelAnswer run(const registration::AccelJob& job) override;
  // Starts `job` on the second server (side_by_side 2; one at a time). run() takes its answer
  // when it is the next job and follows one on another tree; else it runs the job itself.
  void prefetch(const registration::AccelJob& job) override;

  // Called after each job with its number (from 1) and report (accel_job.hpp).
  std::function<void(std::uint64_t number, const registration::AccelJob& job, const nlohmann::json& report)> on_job;
  std::uint64_t jobs() const { return jobs_; }

 private:
  void stop() noexcept;
  struct Server {
    int socket = -1;
    pid_t pid = -1;
    std::uint64_t tree = 0;  // the tree whose points it holds
  };
  struct Pending {  // the prefetched job (its queries copied: the caller's may change)
    registration::AccelJob job;
    PointCloud queries;
  };
  std::vector<Server> servers_;  // [0] runs jobs in turn; [1] a prefetched one
  std::optional<Pending> pending_;
  std::uint64_t last_tree_ = 0, jobs_ = 0;
};

}  // namespace tigris
