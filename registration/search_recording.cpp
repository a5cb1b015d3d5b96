#include "search_recording.hpp"

#include <chrono>

namespace tigris::registration {

trace::Job knn_shape(int k, const SearchSettings& s) {
  trace::Job shape;
  shape.mode = k == 1 ? "nn" : "knn";
  shape.k = k;
  shape.inject_kth = s.inject_kth;
  return shape;
}

trace::Job radius_shape(double radius, unsigned int max_nn, bool shell, const SearchSettings& s) {
  trace::Job shape;
  shape.mode = "radius";
  shape.radius = static_cast<float>(radius);
  shape.max_nn = max_nn;
  shape.shell_inner = shell ? s.shell_inner : 0.0f;
  shape.shell_outer = shell ? s.shell_outer : 0.0f;
  return shape;
}

void SearchRecording::tree_built(const SearchSettings& s, const PointCloud& points,
                                 const std::vector<pcl::index_t>& map, std::size_t input_size, double build_seconds,
                                 SteadyClock::time_point t1) {
  // The trace stores the points the golden tree is built on; FLANN's results are mapped into
  // the same numbering.
  if (s.backend == Backend::Flann) {
    local_of_.assign(input_size, -1);
    for (std::size_t i = 0; i < map.size(); ++i) local_of_[static_cast<std::size_t>(map[i])] = static_cast<int>(i);
  }
  serial_ = s.recorder->tree_built(points, to_string(s.backend), s.height_for(points.size()), build_seconds);
  s.recorder->add_overhead(seconds_since(t1));
}

void SearchRecording::searched(const SearchSettings& s, trace::Job shape, const Point3& query,
                               const pcl::Indices& k_indices, int n, SteadyClock::time_point t0) {
  if (s.backend == Backend::Approx) {
    shape.approximate = true;
    shape.approx_thd = shape.mode == "radius" ? s.radius_thd * shape.radius : s.nn_thd;
    shape.leader_capacity = s.leader_capacity;
    shape.leader_width = s.leader_width;
    shape.leader_scope = to_string(s.leader_scope);
    shape.leader_in_flight = to_string(s.leader_in_flight);
  }
  if (s.backend == Backend::Flann) {
    local_.clear();
    for (int i = 0; i < n; ++i) {
      const pcl::index_t input = k_indices[static_cast<std::size_t>(i)];
      local_.push_back(static_cast<std::uint32_t>(local_of_[static_cast<std::size_t>(input)]));
    }
  }
  const std::uint32_t* idx = s.backend == Backend::Flann ? local_.data() : golden_local_.data();
  const auto t1 = SteadyClock::now();
  s.recorder->searched(serial_, shape, query, idx, static_cast<std::size_t>(n > 0 ? n : 0),
                       std::chrono::duration<double>(t1 - t0).count());
  seconds_ = seconds_since(t1);
  s.recorder->add_overhead(seconds_);
}

}  // namespace tigris::registration
