// Progress on stderr for long runs: silent for the first two seconds, then a line every two.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace tigris {

class ProgressReporter {
 public:
  explicit ProgressReporter(std::string what) : what_(std::move(what)) {}
  void operator()(std::size_t done, std::size_t total) {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < std::chrono::seconds(2)) return;
    last_ = now;
    std::fprintf(stderr, "%s: %zu/%zu (%.0f%%)\n", what_.c_str(), done, total,
                 total ? 100.0 * static_cast<double>(done) / static_cast<double>(total) : 100.0);
  }

 private:
  std::string what_;
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace tigris
