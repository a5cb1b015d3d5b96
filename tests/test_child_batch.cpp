// The child-batch runner (core/child_batch.hpp) here, with /bin/sh as the program: every task
// runs in its folder with its log, a failure stops the scheduling, a task's result file is what
// the caller sees, and the tasks' arguments are the caller's.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "core/child_batch.hpp"

using namespace tigris;
namespace fs = std::filesystem;

namespace {

// A fresh folder under the system's temporary one.
std::string scratch(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("tigris-child-batch-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}

// Task k writes "k" into DIR/result.txt, or fails (exit 3, a line in its log) when k is in `failing`.
ChildBatch sh_batch(const std::string& out, std::size_t count, std::set<std::size_t> failing, int parallel) {
  ChildBatch b;
  b.program = "/bin/sh";
  b.count = count;
  b.dir = [out](std::size_t k) { return out + "/task" + std::to_string(k); };
  b.result = "result.txt";
  b.args = [out, failing](std::size_t k, bool) -> std::vector<std::string> {
    const std::string dir = out + "/task" + std::to_string(k);
    if (failing.count(k)) return {"-c", "echo 'task " + std::to_string(k) + " broke'; exit 3"};
    return {"-c", "echo " + std::to_string(k) + " > '" + dir + "/result.txt'"};
  };
  b.parallel = parallel;
  b.out = out;
  b.name = "test";
  b.noun = "tasks";
  return b;
}

}  // namespace

TEST_CASE("a child batch runs every task in its folder, the pool's width at a time", "[child_batch]") {
  const std::string out = scratch("all");
  std::set<std::size_t> ended;
  const bool waited = run_batch(sh_batch(out, 5, {}, 2), [&](const TaskEnd& e) {
    CHECK(e.code == 0);
    CHECK(e.has_result);
    CHECK(e.job.empty());
    ended.insert(e.k);
    return true;
  });
  CHECK(waited);
  CHECK(ended == std::set<std::size_t>{0, 1, 2, 3, 4});
  std::string text;
  std::ifstream(out + "/task3/result.txt") >> text;
  CHECK(text == "3");
  CHECK(fs::exists(out + "/task3/log.txt"));
  fs::remove_all(out);
}

TEST_CASE("a child batch stops scheduling at the first failure and names it by its log", "[child_batch]") {
  const std::string out = scratch("fail");
  std::size_t calls = 0;
  run_batch(sh_batch(out, 6, {1}, 1), [&](const TaskEnd& e) {
    ++calls;
    if (e.k == 1) {
      CHECK(e.code == 3);
      CHECK_FALSE(e.has_result);
      CHECK(last_log_line(out + "/task1") == "task 1 broke");
      return false;
    }
    return true;
  });
  CHECK(calls == 2);  // tasks 0 and 1: one at a time, none after the failure
  CHECK_FALSE(fs::exists(out + "/task2"));
  fs::remove_all(out);
}

TEST_CASE("an empty child batch runs nothing", "[child_batch]") {
  bool called = false;
  CHECK(run_batch(sh_batch("/nonexistent", 0, {}, 2), [&](const TaskEnd&) { return called = true; }));
  CHECK_FALSE(called);
}
