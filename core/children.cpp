#include "children.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>

namespace tigris {
namespace {

// Everything the stop handler touches is a lock-free atomic or a fixed buffer: it may run at
// any moment, on any thread.
constexpr int kSlots = 1024;
std::atomic<pid_t> g_live[kSlots];
std::atomic<int> g_defer{0};
volatile std::sig_atomic_t g_stop = 0;
const char* g_command = "tigris";

constexpr std::size_t kRecordMax = 1 << 16;
char g_record_path[4096], g_record_tmp[4096 + 64];
char g_record[kRecordMax];
std::atomic<std::size_t> g_record_size{0};  // 0: no record

void remember(pid_t pid) {
  for (auto& slot : g_live) {
    pid_t empty = 0;
    if (slot.compare_exchange_strong(empty, pid)) return;
  }
}

void forget(pid_t pid) {
  for (auto& slot : g_live) {
    pid_t p = pid;
    if (slot.compare_exchange_strong(p, 0)) return;
  }
}

void say(const char* s) {
  const ssize_t ignored = ::write(2, s, std::strlen(s));
  (void)ignored;
}

void write_record() {
  const std::size_t n = g_record_size.load();
  if (n == 0) return;
  const int fd = ::open(g_record_tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return;
  const bool ok = ::write(fd, g_record, n) == static_cast<ssize_t>(n);
  ::close(fd);
  if (ok) ::rename(g_record_tmp, g_record_path);
}

// What a rerun does with the folder the command claimed (set_rerun_note): a literal, read by
// the signal handler.
std::atomic<const char*> g_rerun{""};

void on_stop(int sig) {
  g_stop = sig;
  if (g_defer.load() > 0) return;  // the loop that deferred stops by itself
  int count = 0;
  for (auto& slot : g_live)
    if (const pid_t p = slot.load(); p > 0) {
      ::kill(-p, SIGTERM);
      ++count;
    }
  // Up to 5 s for the children to end, then SIGKILL for the rest.
  for (int tick = 0; tick < 50 && count > 0; ++tick) {
    count = 0;
    for (auto& slot : g_live)
      if (const pid_t p = slot.load(); p > 0) {
        const pid_t r = ::waitpid(p, nullptr, WNOHANG);
        if (r == p || (r < 0 && errno == ECHILD))
          slot.store(0);
        else
          ++count;
      }
    if (count > 0) {
      const struct timespec t { 0, 100 * 1000 * 1000 };
      ::nanosleep(&t, nullptr);
    }
  }
  for (auto& slot : g_live)
    if (const pid_t p = slot.load(); p > 0) ::kill(-p, SIGKILL);
  write_record();
  say(g_command);
  say(sig == SIGINT ? ": interrupted (SIGINT)" : sig == SIGHUP ? ": interrupted (SIGHUP)" : ": interrupted (SIGTERM)");
  say(": child processes stopped");
  say(g_rerun.load());
  say("\n");
  ::_exit(128 + sig);
}

// In a new child: it starts with no children and no record of its own, in its own group, and
// dies with its parent.
void become_child(pid_t parent) {
  for (auto& slot : g_live) slot.store(0);
  g_defer.store(0);
  g_rerun.store("");  // the parent's folder is not the child's
  g_stop = 0;
  g_record_size.store(0);
  ::setpgid(0, 0);
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (::getppid() != parent) ::_exit(128 + SIGTERM);  // the parent died before prctl
}

}  // namespace

void install_stop_handlers(const char* command) {
  g_command = command;
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    ::sigaction(sig, nullptr, &old);
    if (old.sa_handler == SIG_IGN) continue;  // nohup's choice is kept
    struct sigaction sa {};
    sa.sa_handler = on_stop;
    sa.sa_flags = SA_RESTART;
    sigemptyset(&sa.sa_mask);
    ::sigaction(sig, &sa, nullptr);
  }
}

pid_t fork_child(const std::function<int()>& body) {
  const pid_t parent = ::getpid();
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error(std::string("cannot start a process: ") + std::strerror(errno));
  if (pid == 0) {
    become_child(parent);
    int code = 3;
    try {
      code = body();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: %s\n", g_command, e.what());
    } catch (...) {
    }
    std::fflush(nullptr);
    ::_exit(code);
  }
  ::setpgid(pid, pid);  // also here: no window in which a stop signal misses the group
  remember(pid);
  return pid;
}

pid_t start_child(const std::vector<std::string>& args, const std::string& log, const std::string& parent_outputs) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  return fork_child([&]() -> int {
    if (!log.empty()) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) {
        ::dup2(fd, 1);
        ::dup2(fd, 2);
        ::close(fd);
      }
    }
    if (parent_outputs.empty())
      ::unsetenv("TIGRIS_PARENT_OUTPUTS");
    else
      ::setenv("TIGRIS_PARENT_OUTPUTS", parent_outputs.c_str(), 1);
    ::execv(argv[0], argv.data());
    std::fprintf(stderr, "cannot run %s: %s\n", argv[0], std::strerror(errno));
    return 127;
  });
}

int wait_child(pid_t pid, pid_t* ended) {
  int status = 0;
  pid_t r;
  while ((r = ::waitpid(pid, &status, 0)) < 0 && errno == EINTR) {
  }
  if (r < 0) throw std::runtime_error(std::string("lost a child process: ") + std::strerror(errno));
  forget(r);
  if (ended) *ended = r;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::vector<int> run_pool(std::size_t count, int parallel, const std::function<pid_t(std::size_t)>& start,
                          const std::function<bool(std::size_t, int)>& done) {
  std::vector<int> codes(count, -1);
  std::map<pid_t, std::size_t> running;
  std::size_t next = 0;
  bool go_on = true;
  try {
    while (true) {
      while (go_on && next < count && running.size() < static_cast<std::size_t>(std::max(1, parallel))) {
        const std::size_t k = next++;
        running[start(k)] = k;
      }
      if (running.empty()) break;
      pid_t pid = 0;
      const int code = wait_child(-1, &pid);
      const auto it = running.find(pid);
      if (it == running.end()) continue;  // a child started elsewhere
      const std::size_t k = it->second;
      running.erase(it);
      codes[k] = code;
      go_on = done(k, code) && go_on;
    }
  } catch (...) {  // no task left running behind the error
    for (const auto& [pid, k] : running) {
      ::kill(-pid, SIGTERM);
      wait_child(pid);
    }
    throw;
  }
  return codes;
}

DeferStop::DeferStop() { ++g_defer; }
DeferStop::~DeferStop() { --g_defer; }
int stop_signal() { return g_stop; }

Interrupted::Interrupted(int sig)
    : std::runtime_error(std::string("interrupted (") +
                         (sig == SIGINT   ? "SIGINT"
                          : sig == SIGHUP ? "SIGHUP"
                                          : "SIGTERM") +
                         ")"),
      signal(sig) {}

void set_rerun_note(bool resumes) {
  g_rerun.store(resumes ? "; a rerun of the same command resumes where it can"
                        : "; a rerun of the same command starts afresh (the folder's results are replaced)");
}

void set_interrupted_record(const std::string& path, const std::string& bytes) {
  g_record_size.store(0);
  if (path.empty() || bytes.size() > kRecordMax || path.size() >= sizeof g_record_path) return;
  std::memcpy(g_record_path, path.c_str(), path.size() + 1);
  // Beside it under the core's temporary prefix, so a later claim clears a leftover.
  const std::size_t slash = path.rfind('/');
  const std::string dir = slash == std::string::npos ? "." : path.substr(0, slash);
  const std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  std::snprintf(g_record_tmp, sizeof g_record_tmp, "%s/.tigris-tmp-%s-%d", dir.c_str(), base.c_str(),
                static_cast<int>(::getpid()));
  std::memcpy(g_record, bytes.data(), bytes.size());
  g_record_size.store(bytes.size());
}

std::vector<std::string> rerun_args(const std::vector<std::string>& argv, const std::vector<std::string>& drop_switches,
                                    const std::vector<std::string>& drop_options,
                                    const std::vector<std::string>& extra) {
  const auto in = [](const std::vector<std::string>& v, const std::string& x) {
    return std::find(v.begin(), v.end(), x) != v.end();
  };
  std::vector<std::string> args{"/proc/self/exe"};
  for (std::size_t i = 1; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    if (in(drop_switches, a)) continue;
    if (in(drop_options, a)) {
      ++i;  // and its value
      continue;
    }
    const std::size_t eq = a.find('=');
    if (a.rfind("--", 0) == 0 && eq != std::string::npos && in(drop_options, a.substr(0, eq))) continue;
    args.push_back(a);
  }
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

}  // namespace tigris
