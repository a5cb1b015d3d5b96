// A plug-in tree's side of the workload trace (trace_recorder.hpp): its serial in the trace,
// every search as issued (after error injection widened it) with its results in the trace's
// numbering, the finite points the golden tree is built on, and the time recording takes, kept
// out of the searches' own seconds. Apart from the plug-in because none of it depends on PCL's
// point type, and a registration that records nothing never touches it.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <pcl/types.h>

#include "core/timer.hpp"
#include "search_settings.hpp"
#include "sw_ref/cloud.hpp"
#include "traces/workload_trace.hpp"

namespace tigris::registration {

// The shapes of the searches the plug-in issues (approximate settings are added by searched()).
trace::Job knn_shape(int k, const SearchSettings& s);  // k: as searched, k + K - 1 under inject_kth
trace::Job radius_shape(double radius, unsigned int max_nn, bool shell, const SearchSettings& s);

class SearchRecording {
 public:
  // A tree was built in `build_seconds` on an input of `input_size` points whose finite ones are
  // `points` (`map`: their input indices). Recording began at `t1`, the caller gathering
  // `points` after it.
  void tree_built(const SearchSettings& s, const PointCloud& points, const std::vector<pcl::index_t>& map,
                  std::size_t input_size, double build_seconds, SteadyClock::time_point t1);
  // One search of `query` that began at `t0` and returned `n` neighbours: `k_indices` (input
  // indices) on FLANN, else golden_local() (already in the trace's numbering).
  void searched(const SearchSettings& s, trace::Job shape, const Point3& query, const pcl::Indices& k_indices, int n,
                SteadyClock::time_point t0);

  // The golden back-ends' results for the search being recorded, as indices into the tree's
  // points; the search fills it.
  std::vector<std::uint32_t>& golden_local() { return golden_local_; }
  // The seconds the last search spent being recorded; zero from then on.
  double take_seconds() { return std::exchange(seconds_, 0.0); }

 private:
  int serial_ = -1;
  std::vector<int> local_of_;  // FLANN: input index -> trace index
  std::vector<std::uint32_t> local_, golden_local_;
  double seconds_ = 0.0;
};

}  // namespace tigris::registration
