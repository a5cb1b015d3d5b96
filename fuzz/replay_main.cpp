// fuzz_corpus_regression (a ctest of the normal build, no libFuzzer): feeds every file under
// fuzz/corpus/<target>/ to that target's fuzz entry point, plus 2000 deterministic
// generator inputs per target, so the corpus and the structure-aware checks run in CI. A clean
// read or a clean error passes; an unexpected exception fails the test, a wrong read or a crash
// stops it (the file being run is printed first).
//
// Usage: fuzz_corpus_regression CORPUS_DIR [GENERATED_INPUTS_PER_TARGET (default 2000)]
#include <algorithm>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

extern "C" {
int tigris_fuzz_kitti_bin(const std::uint8_t*, std::size_t);
int tigris_fuzz_pcd(const std::uint8_t*, std::size_t);
int tigris_fuzz_ply(const std::uint8_t*, std::size_t);
int tigris_fuzz_config(const std::uint8_t*, std::size_t);
int tigris_fuzz_schedule_csv(const std::uint8_t*, std::size_t);
int tigris_fuzz_results_csv(const std::uint8_t*, std::size_t);
int tigris_fuzz_register_config(const std::uint8_t*, std::size_t);
int tigris_fuzz_workload_trace(const std::uint8_t*, std::size_t);
}

namespace {

struct Target {
  const char* name;
  int (*run)(const std::uint8_t*, std::size_t);
  bool generator;  // inputs starting with byte 0 drive a generator
};

const Target kTargets[] = {{"kitti_bin", tigris_fuzz_kitti_bin, false},
                           {"pcd", tigris_fuzz_pcd, true},
                           {"ply", tigris_fuzz_ply, true},
                           {"config", tigris_fuzz_config, true},
                           {"schedule_csv", tigris_fuzz_schedule_csv, false},
                           {"results_csv", tigris_fuzz_results_csv, true},
                           {"register_config", tigris_fuzz_register_config, true},
                           {"workload_trace", tigris_fuzz_workload_trace, true}};

char g_current[4096] = "";

void on_signal(int sig) {
  const char msg[] = "\nfuzz_corpus_regression: crashed (signal) on input: ";
  ssize_t ignored = ::write(2, msg, sizeof msg - 1);
  ignored = ::write(2, g_current, std::strlen(g_current));
  ignored = ::write(2, "\n", 1);
  (void)ignored;
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

bool run_one(const Target& t, const std::string& what, const std::vector<std::uint8_t>& bytes) {
  std::snprintf(g_current, sizeof g_current, "%s: %s", t.name, what.c_str());
  try {
    t.run(bytes.data(), bytes.size());
    return true;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "FAIL %s: %s: unexpected exception: %s\n", t.name, what.c_str(), e.what());
  } catch (...) {
    std::fprintf(stderr, "FAIL %s: %s: unexpected exception\n", t.name, what.c_str());
  }
  return false;
}

}  // namespace

// The readers link the model's libraries, and SystemC's library wants an sc_main; this program
// runs from its own main().
extern "C" int sc_main(int, char**) { return 2; }

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR [GENERATED_INPUTS_PER_TARGET]\n", argv[0]);
    return 2;
  }
  for (int sig : {SIGSEGV, SIGILL, SIGABRT, SIGFPE, SIGBUS}) std::signal(sig, on_signal);
  const std::filesystem::path root = argv[1];
  const long generated = argc > 2 ? std::atol(argv[2]) : 2000;
  int failures = 0;
  for (const Target& t : kTargets) {
    const std::filesystem::path dir = root / t.name;
    std::vector<std::filesystem::path> files;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec))
      if (entry.is_regular_file()) files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    if (files.empty()) {
      std::fprintf(stderr, "FAIL %s: no corpus files in %s\n", t.name, dir.c_str());
      ++failures;
      continue;
    }
    for (const auto& f : files) {
      std::ifstream in(f, std::ios::binary);
      const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      failures += run_one(t, f.string(), bytes) ? 0 : 1;
    }
    long extra = 0;
    std::mt19937_64 rng(20240611);
    for (; t.generator && extra < generated; ++extra) {
      std::vector<std::uint8_t> bytes(1 + rng() % 300);
      for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
      bytes[0] = 0;
      failures += run_one(t, "generated input " + std::to_string(extra), bytes) ? 0 : 1;
    }
    std::printf("%-13s %4zu corpus files, %4ld generated inputs\n", t.name, files.size(), extra);
  }
  if (failures) std::printf("%d failures\n", failures);
  return failures ? 1 : 0;
}
