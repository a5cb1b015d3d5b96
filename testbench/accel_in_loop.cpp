#include "accel_in_loop.hpp"

#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "core/children.hpp"

namespace tigris {
namespace {

static_assert(std::is_trivially_copyable_v<Neighbor> && std::is_trivially_copyable_v<VisitTotals> &&
                  std::is_trivially_copyable_v<Point3> && std::is_trivially_copyable_v<SearchParams>,
              "sent as bytes between copies of the same program");

using Bytes = std::vector<char>;

void put(Bytes& out, const void* p, std::size_t n) {
  out.insert(out.end(), static_cast<const char*>(p), static_cast<const char*>(p) + n);
}
template <class T>
void put_value(Bytes& out, const T& v) {
  put(out, &v, sizeof v);
}
template <class T>
void put_vector(Bytes& out, const std::vector<T>& v) {
  put_value<std::uint64_t>(out, v.size());
  put(out, v.data(), v.size() * sizeof(T));
}

struct Reader {
  const Bytes& in;
  std::size_t at = 0;
  void get(void* p, std::size_t n) {
    if (in.size() - at < n) throw std::runtime_error("the accelerator model sent a truncated message");
    std::memcpy(p, in.data() + at, n);
    at += n;
  }
  template <class T>
  T value() {
    T v{};
    get(&v, sizeof v);
    return v;
  }
  template <class T>
  std::vector<T> vector() {
    const auto n = value<std::uint64_t>();
    if (n > (in.size() - at) / sizeof(T)) throw std::runtime_error("the accelerator model sent a truncated message");
    std::vector<T> v(n);
    get(v.data(), n * sizeof(T));
    return v;
  }
  std::string text() {
    const std::vector<char> v = vector<char>();
    return std::string(v.begin(), v.end());
  }
};

// Messages are a length and that many bytes. send() with MSG_NOSIGNAL: a dead peer is an
// error, not a SIGPIPE.
bool send_all(int fd, const char* p, std::size_t n) {
  while (n > 0) {
    const ssize_t k = ::send(fd, p, n, MSG_NOSIGNAL);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    p += k;
    n -= static_cast<std::size_t>(k);
  }
  return true;
}
bool send_message(int fd, const Bytes& m) {
  const std::uint64_t n = m.size();
  return send_all(fd, reinterpret_cast<const char*>(&n), sizeof n) && send_all(fd, m.data(), m.size());
}
bool recv_all(int fd, char* p, std::size_t n) {
  while (n > 0) {
    const ssize_t k = ::recv(fd, p, n, 0);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    p += k;
    n -= static_cast<std::size_t>(k);
  }
  return true;
}
bool recv_message(int fd, Bytes& m) {
  std::uint64_t n = 0;
  if (!recv_all(fd, reinterpret_cast<char*>(&n), sizeof n) || n > (std::uint64_t{1} << 40)) return false;
  m.resize(n);
  return recv_all(fd, m.data(), n);
}

// An answer: kind (0 ran, 1 cannot run, 2 failed), then the report and results, or a message.
Bytes error_answer(char kind, const std::string& message) {
  Bytes out(1, kind);
  put_vector(out, std::vector<char>(message.begin(), message.end()));
  return out;
}

// One job in this (fresh) process.
Bytes run_job(const ModelJob& mj, const hw::AcceleratorConfig& cfg, const WorkLimits& limits, int sim_threads) {
  try {
    ModelJobRun run = run_model_job(mj, cfg, limits, sim_threads);
    const std::string report = run.report.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    Bytes out(1, 0);
    put_vector(out, std::vector<char>(report.begin(), report.end()));
    put_vector(out, run.results.offset);
    put_vector(out, run.results.neighbors);
    put_value(out, run.visits);
    return out;
  } catch (const std::invalid_argument& e) {
    return error_answer(1, e.what());
  } catch (const std::exception& e) {
    return error_answer(2, e.what());
  }
}

// The model server: receives jobs (and the tree's points when they change) on `fd`, runs each
// in a child process and sends its answer back; ends when the registration closes the socket.
void serve_jobs(int fd, const hw::AcceleratorConfig& cfg, const WorkLimits& limits, int sim_threads) {
  PointCloud points;
  // Its tree, built here once for the jobs that search it (a stage's, ICP's iterations): each
  // job's process, forked from this one, moves it out instead of building its own.
  std::optional<BuiltTree> built;
  Bytes request;
  while (recv_message(fd, request)) {
    Bytes answer;
    try {
      Reader r{request};
      ModelJob mj;
      if (r.value<char>() != 0) {  // this server's tree changes
        points = r.vector<Point3>();
        built.reset();
      }
      mj.send_tree = r.value<char>() != 0;  // the modeled host link carries it
      const PointCloud queries = r.vector<Point3>();
      mj.params = r.value<SearchParams>();
      mj.top_height = r.value<int>();
      mj.points = &points;
      mj.queries = &queries;
      const int height = std::min(mj.top_height, full_height_for(points.size()));
      if (!built || built->tree.top_height != height) {
        try {
          built = BuiltTree::of(points, height, cfg.tree.split_axis);
        } catch (const std::exception&) {  // the job builds it and says why not
          built.reset();
        }
      }
      mj.built = built ? &*built : nullptr;
      int job_fds[2];
      if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, job_fds) != 0)
        throw std::runtime_error(std::string("cannot open a socket: ") + std::strerror(errno));
      pid_t pid = -1;
      try {
        // The job's process dies with the server (children.hpp), and the server with the registration.
        pid = fork_child([&]() -> int {
          ::close(job_fds[0]);
          send_message(job_fds[1], run_job(mj, cfg, limits, sim_threads));
          return 0;
        });
      } catch (...) {
        ::close(job_fds[0]);
        ::close(job_fds[1]);
        throw;
      }
      ::close(job_fds[1]);
      const bool got = recv_message(job_fds[0], answer);
      ::close(job_fds[0]);
      const int code = wait_child(pid);
      if (!got || code != 0)
        answer = error_answer(
            2, "the job's process ended without an answer (" +
                   (code > 128 ? "signal " + std::to_string(code - 128) : "exit code " + std::to_string(code)) + ")");
    } catch (const std::exception& e) {
      answer = error_answer(2, e.what());
    }
    if (!send_message(fd, answer)) break;
  }
}

// The server process: never returns (an exception must not let it go on as the registration).
[[noreturn]] void serve(int fd, const hw::AcceleratorConfig& cfg, const WorkLimits& limits, int sim_threads) {
  try {
    serve_jobs(fd, cfg, limits, sim_threads);
  } catch (...) {
    ::_exit(3);
  }
  std::fflush(nullptr);
  ::_exit(0);
}

}  // namespace

ModelInTheLoop::ModelInTheLoop(hw::AcceleratorConfig config, WorkLimits limits, int sim_threads, int side_by_side) {
  // Forked here, from the main thread, before any job: one server per job run at a time.
  for (int i = 0; i < std::max(1, std::min(side_by_side, 2)); ++i) {
    int fds[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0)
      throw std::runtime_error(std::string("cannot open a socket to the accelerator model: ") + std::strerror(errno));
    Server server;
    try {
      server.pid = fork_child([&]() -> int {
        ::close(fds[0]);
        for (const Server& other : servers_) ::close(other.socket);
        serve(fds[1], config, limits, sim_threads);  // never returns
      });
    } catch (const std::exception& e) {
      ::close(fds[0]);
      ::close(fds[1]);
      stop();
      throw std::runtime_error(std::string("cannot start the accelerator model: ") + e.what());
    }
    ::close(fds[1]);
    server.socket = fds[0];
    servers_.push_back(server);
  }
}

void ModelInTheLoop::stop() noexcept {
  for (Server& server : servers_) {
    if (server.socket >= 0) ::close(server.socket);
    server.socket = -1;
  }
  if (pending_ && servers_.size() > 1) ::kill(servers_[1].pid, SIGKILL);  // a job nobody will take
  for (Server& server : servers_) {
    if (server.pid <= 0) continue;
    try {
      wait_child(server.pid);
    } catch (...) {  // a destructor does not throw
    }
    server.pid = -1;
  }
}

ModelInTheLoop::~ModelInTheLoop() { stop(); }

namespace {

// A job request: the tree's points when `server` does not hold them, whether the modeled host
// link carries the tree image, the queries and parameters.
Bytes request_for(const registration::AccelJob& job, std::uint64_t& server_tree, bool send_tree) {
  Bytes request;
  const bool points = job.tree_id != server_tree;
  put_value<char>(request, points ? 1 : 0);
  if (points) put_vector(request, *job.points);
  put_value<char>(request, send_tree ? 1 : 0);
  put_vector(request, *job.queries);
  put_value(request, job.params);
  put_value(request, job.top_height);
  server_tree = job.tree_id;
  return request;
}

bool same_job(const registration::AccelJob& a, const registration::AccelJob& b, const PointCloud& b_queries) {
  return registration::same_search(a.params, b.params) && a.tree_id == b.tree_id && a.top_height == b.top_height &&
         a.queries->size() == b_queries.size() &&
         std::memcmp(a.queries->data(), b_queries.data(), b_queries.size() * sizeof(Point3)) == 0;
}

}  // namespace

void ModelInTheLoop::prefetch(const registration::AccelJob& job) {
  if (servers_.size() < 2 || pending_) return;
  // Taken by run() only as the job after one on another tree (it models the tree image sent).
  const Bytes request = request_for(job, servers_[1].tree, true);
  if (!send_message(servers_[1].socket, request)) return;  // run() will run it itself
  pending_ = Pending{job, *job.queries};
}

registration::AccelAnswer ModelInTheLoop::run(const registration::AccelJob& job) {
  const std::uint64_t number = ++jobs_;
  char what[160];
  std::snprintf(what, sizeof what, "accelerator job %llu (%s, %zu queries on %zu points)",
                static_cast<unsigned long long>(number), to_string(job.params.mode), job.queries->size(),
                job.points->size());
  const bool send_tree = job.tree_id != last_tree_;
  Bytes in;
  if (pending_ && send_tree && same_job(job, pending_->job, pending_->queries)) {  // it ran beside the one before
    pending_.reset();
    if (!recv_message(servers_[1].socket, in))
      throw std::runtime_error(std::string(what) + ": the accelerator model's server is gone");
  } else {
    const Bytes request = request_for(job, servers_[0].tree, send_tree);
    if (!send_message(servers_[0].socket, request) || !recv_message(servers_[0].socket, in))
      throw std::runtime_error(std::string(what) + ": the accelerator model's server is gone");
  }
  last_tree_ = job.tree_id;
  Reader r{in};
  const char kind = r.value<char>();
  if (kind == 1) throw std::invalid_argument(std::string(what) + ": " + r.text());
  if (kind != 0) throw std::runtime_error(std::string(what) + ": " + r.text());
  const nlohmann::json report = nlohmann::json::parse(r.text());
  registration::AccelAnswer a;
  a.results.offset = r.vector<std::uint64_t>();
  a.results.neighbors = r.vector<Neighbor>();
  a.visits = r.value<VisitTotals>();
  if (on_job) on_job(number, job, report);
  const std::string verdict = report.value("verdict", "");
  if (verdict != "match") {
    std::string first;
    if (report.contains("mismatches"))
      for (const auto& m : report["mismatches"]["first"]) first += "\n  " + m.get<std::string>();
    if (report.contains("deadlock")) first = "\n  " + report["deadlock"].dump();
    throw registration::AcceleratorFailure(std::string(what) + ": " + verdict + " against the golden model" + first);
  }
  a.cycles = report["cycles"].get<std::uint64_t>();
  a.search_seconds = report["modeled_seconds"]["search"].get<double>();
  a.host_seconds = report["modeled_seconds"]["host"].get<double>();
  a.energy_pj = report["energy_pj"].get<double>();
  return a;
}

}  // namespace tigris
