// The Python module's native part (tigris._tigris): the cloud readers and the golden model on
// NumPy arrays, in process. Everything that simulates goes through the `tigris` binary in a
// child process (python/tigris/__init__.py): SystemC elaborates once per process.
//
// Arrays: clouds are float32 (N, 3), C-contiguous; the results come back as arrays that own the
// golden model's own vectors (no copy).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/input_error.hpp"
#include "sw_ref/kdtree.hpp"
#include "sw_ref/leader_policy.hpp"
#include "sw_ref/search.hpp"
#include "sw_ref/work_guard.hpp"
#include "workloads/io/cloud_io.hpp"
#include "workloads/workload.hpp"

namespace py = pybind11;
using namespace tigris;

namespace {

using FloatArray = py::array_t<float, py::array::c_style>;

// A vector handed to NumPy without a copy: the array's base owns it.
template <class T>
py::array owned(std::vector<T>&& v, std::vector<py::ssize_t> shape) {
  auto* heap = new std::vector<T>(std::move(v));
  py::capsule owner(heap, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, heap->data(), owner);
}

py::array cloud_array(PointCloud&& cloud) {
  static_assert(sizeof(Point3) == 3 * sizeof(float), "Point3 is three packed floats");
  const auto n = static_cast<py::ssize_t>(cloud.size());
  auto* heap = new PointCloud(std::move(cloud));
  py::capsule owner(heap, [](void* p) { delete static_cast<PointCloud*>(p); });
  return py::array_t<float>({n, py::ssize_t{3}}, reinterpret_cast<const float*>(heap->data()), owner);
}

// `what` as a PointCloud; the Python side has checked dtype, shape and finiteness, this checks
// again (a caller of _tigris directly gets the same errors).
PointCloud to_cloud(const FloatArray& a, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw py::value_error(std::string(what) + " must have shape (N, 3), got " + std::to_string(a.ndim()) +
                          " dimension(s)");
  if (a.shape(0) == 0) throw py::value_error(std::string(what) + " is empty");
  PointCloud out(static_cast<std::size_t>(a.shape(0)));
  const float* p = a.data();
  for (std::size_t i = 0; i < out.size(); ++i, p += 3) {
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]) || std::fabs(p[0]) > kMaxCoordinate ||
        std::fabs(p[1]) > kMaxCoordinate || std::fabs(p[2]) > kMaxCoordinate)
      throw py::value_error(std::string(what) + " row " + std::to_string(i) +
                            " is not a finite coordinate within 1e18 metres");
    out[i] = {p[0], p[1], p[2]};
  }
  return out;
}

py::dict visits_dict(const VisitTotals& v) {
  py::dict d;
  for_each_count(v, [&](const char* name, std::uint64_t x) { d[name] = x; });
  return d;
}

// The golden search, as `tigris ref` runs it: the tree of `height` (-1: full) on `cloud`, the
// queries in index order. Returns (indices, dist2, offsets, per-query visits, totals, leaders,
// tree facts).
py::dict golden_search(const FloatArray& cloud_in, const FloatArray& queries_in, const std::string& mode, int k,
                       float radius, std::uint32_t max_nn, int height, const std::string& split, bool approximate,
                       float approx_thd, const std::string& leader_scope, const std::string& leader_in_flight,
                       int leader_capacity, int leader_width, double max_work, double max_results) {
  const PointCloud cloud = to_cloud(cloud_in, "cloud"), queries = to_cloud(queries_in, "queries");
  SearchParams p;
  p.mode = parse_mode(mode);
  p.k = p.mode == Mode::KNN ? k : 1;
  p.radius = radius;
  p.max_nn = max_nn;
  p.approximate = approximate;
  p.approx_thd = approx_thd;
  p.leader_scope = parse_leader_scope(leader_scope);
  p.leader_in_flight = parse_leader_in_flight(leader_in_flight);
  p.leader_capacity = leader_capacity;
  p.leader_width = leader_width;
  p.record_schedule = false;
  validate(p);
  if (height > full_height_for(cloud.size()))
    throw py::value_error("height " + std::to_string(height) + " exceeds the full height " +
                          std::to_string(full_height_for(cloud.size())) + " of the " + std::to_string(cloud.size()) +
                          "-point tree (give at most that, or 'full')");
  SearchOutput out;
  KdTree tree;
  {
    py::gil_scoped_release unlocked;  // the search is long and touches no Python object
    tree = build_kdtree(cloud, height, parse_split_rule(split));
    // The command line's work bound (tigris ref --max-work/--max-results): an hours-long job is
    // refused before it starts (std::invalid_argument: ValueError)...
    check_work(estimate_work(tree, queries, p), WorkLimits{max_work, max_results}, queries.size());
    // ... and Ctrl-C stops one that runs: the search asks Python for a pending signal every
    // few thousand queries (a KeyboardInterrupt raised here leaves through the search).
    out = search(tree, queries, p, nullptr, [](std::size_t, std::size_t) {
      py::gil_scoped_acquire locked;
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    });
  }
  std::vector<std::uint32_t> index(out.results.neighbors.size());
  std::vector<float> dist2(index.size());
  for (std::size_t i = 0; i < index.size(); ++i)
    index[i] = out.results.neighbors[i].index, dist2[i] = out.results.neighbors[i].dist2;
  std::vector<std::uint32_t> top(out.per_query.size()), leaf(out.per_query.size());
  for (std::size_t q = 0; q < top.size(); ++q) top[q] = out.per_query[q].top, leaf[q] = out.per_query[q].leaf_points;
  py::dict d;
  const auto n = static_cast<py::ssize_t>(index.size());
  const auto nq = static_cast<py::ssize_t>(top.size());
  d["indices"] = owned(std::move(index), {n});
  d["dist2"] = owned(std::move(dist2), {n});
  d["offsets"] = owned(std::move(out.results.offset), {nq + 1});
  d["visits_top"] = owned(std::move(top), {nq});
  d["visits_leaf_points"] = owned(std::move(leaf), {nq});
  d["visits"] = visits_dict(out.visits);
  py::dict leaders;
  leaders["leaders"] = out.leaders.leaders;
  leaders["followers"] = out.leaders.followers;
  leaders["leader_buffer_full"] = out.leaders.leader_buffer_full;
  d["leaders"] = leaders;
  d["top_height"] = tree.top_height;
  d["full_height"] = tree.full_height;
  d["leaves"] = tree.num_leaves();
  return d;
}

}  // namespace

PYBIND11_MODULE(_tigris, m) {
  m.doc() = "Tigris TLM's golden model and cloud readers on NumPy arrays (use the package `tigris`)";
  // The readers' and the golden model's errors carry the CLI's messages: a bad file is an
  // InputError (a ValueError), a bad setting std::invalid_argument (ValueError too).
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);
  m.def(
      "load_cloud", [](const std::string& path) { return cloud_array(load_cloud(path)); }, py::arg("path"),
      "A KITTI .bin, .pcd or .ply file's points as a float32 (N, 3) array");
  m.def(
      "synthetic_pair",
      [](std::uint64_t seed) {
        Workload w = load_workload("", "", seed);
        return py::make_tuple(cloud_array(std::move(w.cloud)), cloud_array(std::move(w.queries)));
      },
      py::arg("seed") = 1, "The built-in synthetic frames 0 and 1 of `seed` as (cloud, queries)");
  m.def("search", &golden_search, py::arg("cloud"), py::arg("queries"), py::arg("mode"), py::arg("k"),
        py::arg("radius"), py::arg("max_nn"), py::arg("height"), py::arg("split"), py::arg("approximate"),
        py::arg("approx_thd"), py::arg("leader_scope"), py::arg("leader_in_flight"), py::arg("leader_capacity"),
        py::arg("leader_width"), py::arg("max_work") = WorkLimits{}.max_work,
        py::arg("max_results") = WorkLimits{}.max_results);
  m.def(
      "full_height", [](std::size_t points) { return full_height_for(points); }, py::arg("points"));
  m.def("default_approx_thd", [](const std::string& mode, float radius) {
    SearchParams p;
    p.mode = parse_mode(mode);
    p.radius = radius;
    return default_approx_thd(p);
  });
}
