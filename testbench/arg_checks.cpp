#include "arg_checks.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace tigris {

namespace fs = std::filesystem;

void reject_empty_arguments(int argc, const char* const* argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    std::string flag;
    if (arg.empty()) flag = i > 1 && argv[i - 1][0] == '-' ? argv[i - 1] : "an argument";
    else if (arg.rfind("--", 0) == 0 && arg.back() == '=') flag = arg.substr(0, arg.size() - 1);
    if (!flag.empty())
      throw std::invalid_argument(flag + " was given an empty value; leave the flag out for its default "
                                  "(--help lists them)");
  }
}

std::string command_line(int argc, const char* const* argv) {
  std::string out;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    if (i) out += ' ';
    if (!a.empty() && a.find_first_of(" \t\n'\"\\$`*?;&|<>()") == std::string::npos) {
      out += a;
      continue;
    }
    out += '\'';
    for (char c : a) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    out += '\'';
  }
  return out;
}

namespace {

// The path as the file system will resolve it: absolute, symbolic links of the existing part
// followed, "." and ".." folded.
fs::path resolved(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return ec ? fs::absolute(path).lexically_normal() : p;
}

bool same_file(const std::string& a, const std::string& b) {
  if (resolved(a) == resolved(b)) return true;
  struct stat sa {}, sb {};
  return stat(a.c_str(), &sa) == 0 && stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev &&
         sa.st_ino == sb.st_ino && S_ISREG(sa.st_mode);
}

}  // namespace

void check_distinct_paths(const std::vector<PathUse>& inputs, const std::vector<PathUse>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const PathUse& out = outputs[i];
    if (out.path.empty()) continue;
    for (const PathUse& in : inputs)
      if (!in.path.empty() && same_file(in.path, out.path))
        throw std::invalid_argument(out.flag + " " + out.path + " would overwrite the input " + in.flag + " " +
                                    in.path + "; write the output elsewhere");
    for (std::size_t j = 0; j < i; ++j)
      if (!outputs[j].path.empty() && same_file(outputs[j].path, out.path))
        throw std::invalid_argument(out.flag + " " + out.path + " and " + outputs[j].flag + " " +
                                    outputs[j].path + " are the same file; give each output its own path");
  }
}

CLI::Validator uint64_text() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        if (s.empty() || s.size() > 20 || s.find_first_not_of("0123456789") != std::string::npos ||
            (s.size() == 20 && s > "18446744073709551615"))
          return "must be a whole number from 0 to 18446744073709551615, got '" + s + "'";
        return {};
      },
      "UINT64");
}

namespace {
std::string g(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", x);
  return b;
}
}  // namespace

CLI::Validator finite_range(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& s) -> std::string {
        char* end = nullptr;
        errno = 0;
        const double x = std::strtod(s.c_str(), &end);
        // Underflow (ERANGE with a tiny result) is a number; overflow and NaN are not.
        if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(x) ||
            s.find_first_of("xXnN") != std::string::npos)
          return "must be a finite number from " + g(lo) + " to " + g(hi) + ", got '" + s + "'";
        if (x < lo || x > hi) return "must be from " + g(lo) + " to " + g(hi) + ", got '" + s + "'";
        return {};
      },
      "NUMBER in [" + g(lo) + ", " + g(hi) + "]");
}

CLI::Validator whole_range(long long lo, long long hi) {
  return CLI::Validator(
      [lo, hi](std::string& s) -> std::string {
        char* end = nullptr;
        errno = 0;
        const long long x = std::strtoll(s.c_str(), &end, 10);
        if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE || x < lo || x > hi)
          return "must be a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got '" + s +
                 "'";
        return {};
      },
      "INT in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

}  // namespace tigris
