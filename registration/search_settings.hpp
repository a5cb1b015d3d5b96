// What a plug-in tree is asked to do (search_plugin.hpp): the back-end, the golden tree's top
// height, the approximate search's settings, error injection and the hooks a registration
// shares between its trees. Apart from the plug-in so the pipeline can pass a stage's settings
// around, and the plug-in's helpers read them, without the PCL template.
#pragma once

#include <memory>

#include "accelerator_port.hpp"
#include "pipeline_config.hpp"  // Backend
#include "search_counters.hpp"  // WorkBudget
#include "sw_ref/leader_policy.hpp"
#include "sw_ref/search.hpp"
#include "trace_recorder.hpp"

namespace tigris::registration {

struct SearchSettings {
  Backend backend = Backend::Exact;
  int top_height = 10;      // clamped to each cloud's full height
  int leaf_size = 0;        // > 0: the top height whose leaf sets hold at most this many points
  float nn_thd = 1.2f;      // approximate NN/kNN: follow a leader this close (metres)
  float radius_thd = 0.4f;  // approximate radius: threshold as a fraction of r
  int leader_capacity = 16;
  int leader_width = 0;  // R for NN/kNN (0: k)
  LeaderScope leader_scope = LeaderScope::FirstLeaf;
  LeaderInFlight leader_in_flight = LeaderInFlight::Wait;
  // Error injection (injection.hpp has the exact semantics); the defaults inject nothing.
  int inject_kth = 1;                       // k-nearest searches return ranks K .. K+k-1 (>= 1)
  float shell_inner = 0.0f;                 // radius searches return R1 <= d <= R2 (metres, >= 0, < outer)
  float shell_outer = 0.0f;                 // 0: no shell
  std::shared_ptr<WorkBudget> budget;       // shared by every tree of a registration; null: none
  std::shared_ptr<TraceRecorder> recorder;  // records every tree and search; null: none
  // In the loop (announced_jobs.hpp): golden back-ends only; null: none.
  std::shared_ptr<AcceleratorPort> accelerator;

  // The top height of a tree on `points` points: top_height, or the lowest height whose leaf
  // sets hold at most leaf_size points (a top node keeps its median: the larger half is n / 2).
  int height_for(std::size_t points) const;
  bool injects_kth() const { return inject_kth > 1; }
  bool injects_shell() const { return shell_outer > 0.0f; }
  // Throws std::invalid_argument naming the field: inject_kth < 1, a shell with inner < 0,
  // inner >= outer or a non-finite bound.
  void validate_injection() const;
};

// `p` as the golden model searches it on these settings' back-end: on approx, approximate
// with the settings' threshold (nn_thd, or radius_thd of the radius) and leader settings;
// otherwise unchanged.
SearchParams golden_params(SearchParams p, const SearchSettings& s);

}  // namespace tigris::registration
