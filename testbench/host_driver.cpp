#include "host_driver.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <thread>

#include "sw_ref/search.hpp"

namespace tigris {

using namespace tlm_if;

HostJob host_job(const SearchParams& p) {
  HostJob j;
  j.mode = p.mode == Mode::NN ? SearchMode::NN : p.mode == Mode::KNN ? SearchMode::KNN : SearchMode::Radius;
  j.k = static_cast<std::uint32_t>(p.effective_k());
  j.radius = p.radius;
  j.max_nn = p.max_nn;
  j.approximate = p.approximate;
  j.first_leaf = p.leader_scope == LeaderScope::FirstLeaf;
  j.wait_for_leaders = p.leader_in_flight == LeaderInFlight::Wait;
  j.approx_thd = p.approx_thd;
  j.leader_width = static_cast<std::uint32_t>(p.effective_leader_width());
  return j;
}

HostDriver::HostDriver(sc_core::sc_module_name name, const TreeImage& image, const PointCloud& queries,
                       std::uint32_t num_points, const HostJob& job)
    : sc_module(name), socket("socket"), irq("irq"), image_(image), queries_(queries), num_points_(num_points),
      job_(job) {
  SC_THREAD(run);
}

void HostDriver::transport(tlm::tlm_command cmd, std::uint64_t addr, unsigned char* data, std::size_t len,
                           const char* what) {
  tlm::tlm_generic_payload t;
  sc_core::sc_time delay = sc_core::SC_ZERO_TIME;
  t.set_command(cmd);
  t.set_address(addr);
  t.set_data_ptr(data);
  t.set_data_length(static_cast<unsigned int>(len));
  t.set_streaming_width(static_cast<unsigned int>(len));
  socket->b_transport(t, delay);
  if (t.is_response_error()) throw std::runtime_error(std::string(what) + " failed: " + t.get_response_string());
  wait(delay);  // loosely timed: the host syncs after each transaction
}

void HostDriver::write(std::uint64_t addr, const void* data, std::size_t len, const char* what) {
  constexpr std::size_t kChunk = 64 * 1024;  // one bus burst
  auto* bytes = static_cast<unsigned char*>(const_cast<void*>(data));
  const std::string label = std::string("writing ") + what + " (" + std::to_string(len) + " bytes)";
  for (std::size_t done = 0; done < len; done += kChunk)
    transport(tlm::TLM_WRITE_COMMAND, addr + done, bytes + done, std::min(kChunk, len - done), label.c_str());
}

void HostDriver::read(std::uint64_t addr, void* data, std::size_t len) {
  constexpr std::size_t kChunk = 1024 * 1024;
  auto* bytes = static_cast<unsigned char*>(data);
  for (std::size_t done = 0; done < len; done += kChunk)
    transport(tlm::TLM_READ_COMMAND, addr + done, bytes + done, std::min(kChunk, len - done), "host read");
}

void HostDriver::write_csr(std::uint32_t offset, std::uint32_t value) { write(kCsrBase + offset, &value, 4, "a CSR"); }

std::uint32_t HostDriver::read_csr(std::uint32_t offset) {
  std::uint32_t v = 0;
  read(kCsrBase + offset, &v, 4);
  return v;
}

void HostDriver::run() {
  try {
    for (int r = 0; r < job_.runs; ++r) {
      run_once();
      if (!error_.empty()) return;
      if (on_run_done_) on_run_done_(r);
      write_csr(kStatus, 0);  // clear done and the interrupt for the next run
    }
    finished_ = true;
  } catch (const std::exception& e) {
    error_ = e.what();
  }
  // No sc_stop(): the run ends when no event is left, so several accelerators can share it.
}

void HostDriver::run_once() {
  write(kPointBufferBase, image_.bytes.data(), image_.bytes.size(), "the tree image into the Point Buffer");
  std::vector<QueryRecord> packed;
  packed.reserve(queries_.size());
  for (const Point3& q : queries_) packed.push_back({q.x, q.y, q.z});
  write(kQueryBufferBase, packed.data(), packed.size() * sizeof(QueryRecord), "the queries into the Query Buffer");
  const float r2 = job_.radius * job_.radius;
  std::uint32_t r2_bits;
  std::memcpy(&r2_bits, &r2, 4);
  write_csr(kMode, static_cast<std::uint32_t>(job_.mode));
  write_csr(kK, job_.k);
  write_csr(kRadius2Bits, r2_bits);
  write_csr(kNumPoints, num_points_);
  write_csr(kNumQueries, static_cast<std::uint32_t>(queries_.size()));
  write_csr(kTopHeight, static_cast<std::uint32_t>(image_.top_height));
  write_csr(kNumTopNodes, image_.num_top_nodes);
  write_csr(kNumLeaves, image_.num_leaves);
  write_csr(kLeafDirOffset, image_.leaf_dir_offset);
  const float thd2 = job_.approx_thd * job_.approx_thd;  // as sw_ref squares it: in float
  std::uint32_t thd2_bits;
  std::memcpy(&thd2_bits, &thd2, 4);
  write_csr(kApprox, !job_.approximate ? 0 : !job_.first_leaf ? 1 : job_.wait_for_leaders ? 2 : 3);
  write_csr(kApproxThd2Bits, thd2_bits);
  write_csr(kLeaderWidth, job_.leader_width);
  write_csr(kCtrl, 1);
  while (!irq.read()) wait(irq.value_changed_event());  // level: a fast error may beat us here
  const std::uint32_t status = read_csr(kStatus);
  if (status & kError) {
    error_ = "the accelerator reported error " + std::to_string(read_csr(kErrorCode));
    return;
  }
  cycles_ = read_csr(kCyclesLo) | (std::uint64_t{read_csr(kCyclesHi)} << 32);
  const std::uint64_t bytes = read_csr(kResultBytesLo) | (std::uint64_t{read_csr(kResultBytesHi)} << 32);
  collect(bytes);
}

void HostDriver::collect(std::uint64_t bytes) {
  // Records arrive in completion order. Two passes over the DRAM window, a chunk at a time (the
  // stream can be gigabytes for wide radius searches): count per query, then place.
  if (bytes % sizeof(ResultRecord) != 0) throw std::runtime_error("result stream is not a whole number of records");
  const std::size_t nq = queries_.size();
  std::vector<ResultRecord> chunk(1 << 16);
  auto for_each_record = [&](auto&& visit) {
    for (std::uint64_t done = 0; done < bytes;) {
      const std::uint64_t n = std::min<std::uint64_t>(chunk.size(), (bytes - done) / sizeof(ResultRecord));
      read(kResultDramBase + done, chunk.data(), n * sizeof(ResultRecord));
      for (std::uint64_t i = 0; i < n; ++i) visit(chunk[i]);
      done += n * sizeof(ResultRecord);
    }
  };
  results_ = Results{};
  std::vector<std::uint64_t>& offset = results_.offset;
  offset.assign(nq + 1, 0);
  for_each_record([&](const ResultRecord& r) {
    if (r.query >= nq) throw std::runtime_error("result stream names query " + std::to_string(r.query));
    ++offset[r.query + 1];
  });
  for (std::size_t q = 0; q < nq; ++q) offset[q + 1] += offset[q];
  std::vector<Neighbor>& flat = results_.neighbors;
  flat.resize(offset[nq]);
  std::vector<std::uint64_t> fill(offset.begin(), offset.end() - 1);
  for_each_record([&](const ResultRecord& r) { flat[fill[r.query]++] = {r.index, r.dist2}; });
  if (job_.mode != SearchMode::Radius) return;  // NN/kNN lists arrive in canonical order already
  // Radius hits come in scan order: sort each query's, keep its first max_nn, compact. The
  // queries are sorted in two halves of the hits, the second on a thread of its own (the host's
  // work after done, not the model's: the other core is idle by now).
  const auto sort_queries = [&](std::size_t from, std::size_t to) {
    for (std::size_t q = from; q < to; ++q) std::sort(flat.data() + offset[q], flat.data() + offset[q + 1], Closer{});
  };
  const std::size_t mid =
      static_cast<std::size_t>(std::upper_bound(offset.begin(), offset.end(), offset[nq] / 2) - offset.begin() - 1);
  if (flat.size() >= (std::size_t{1} << 16) && mid > 0 && mid < nq) {
    std::thread second(sort_queries, mid, nq);
    sort_queries(0, mid);
    second.join();
  } else {
    sort_queries(0, nq);
  }
  if (job_.max_nn == 0) return;
  std::uint64_t out = 0;
  for (std::size_t q = 0; q < nq; ++q) {
    Neighbor* first = flat.data() + offset[q];
    Neighbor* last = flat.data() + offset[q + 1];
    if (static_cast<std::uint64_t>(last - first) > job_.max_nn) last = first + job_.max_nn;
    offset[q] = out;
    out = static_cast<std::uint64_t>(std::copy(first, last, flat.data() + out) - flat.data());
  }
  offset[nq] = out;
  flat.resize(out);
}

}  // namespace tigris
