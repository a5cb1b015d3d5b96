#include "arg_checks.hpp"
#include "out_folder.hpp"

#include <algorithm>

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
    if (arg.empty())
      flag = i > 1 && argv[i - 1][0] == '-' ? argv[i - 1] : "an argument";
    else if (arg.rfind("--", 0) == 0 && arg.back() == '=')
      flag = arg.substr(0, arg.size() - 1);
    if (!flag.empty())
      throw std::invalid_argument(flag +
                                  " was given an empty value; leave the flag out for its default "
                                  "(--help lists them)");
  }
}

std::string closest(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = ~std::size_t{0};
  for (const std::string& c : candidates) {
    // Levenshtein distance, two rows.
    std::vector<std::size_t> prev(c.size() + 1), cur(c.size() + 1);
    for (std::size_t j = 0; j <= c.size(); ++j) prev[j] = j;
    for (std::size_t i = 1; i <= word.size(); ++i) {
      cur[0] = i;
      for (std::size_t j = 1; j <= c.size(); ++j)
        cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (word[i - 1] == c[j - 1] ? 0 : 1)});
      std::swap(prev, cur);
    }
    if (prev[c.size()] < best_d) best_d = prev[c.size()], best = c;
  }
  const std::string letters =
      word.substr(word.find_first_not_of('-') == std::string::npos ? 0 : word.find_first_not_of('-'));
  return best_d <= 2 && best_d < letters.size() ? best : std::string();
}

std::string parse_suggestions(CLI::App& app, int argc, const char* const* argv, const std::string& error) {
  std::vector<std::string> commands;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    commands.push_back(sub->get_name());
  if (argc < 2) return "";
  const std::string first = argv[1];
  if (first.empty() || first[0] == '-') return "";
  CLI::App* sub = nullptr;
  for (CLI::App* s : app.get_subcommands([](const CLI::App*) { return true; }))
    if (s->get_name() == first) sub = s;
  if (!sub) {
    const std::string guess = closest(first, commands);
    std::string list;
    for (const std::string& c : commands) list += (list.empty() ? "" : ", ") + c;
    return "'" + first + "' is not a tigris command" + (guess.empty() ? "" : "; did you mean '" + guess + "'?") +
           " (commands: " + list + ")\n";
  }
  const auto flags_of = [](const CLI::App* a) {
    std::vector<std::string> names;
    for (const CLI::Option* o : a->get_options())
      for (const std::string& n : o->get_lnames()) names.push_back("--" + n);
    return names;
  };
  const std::vector<std::string> own = flags_of(sub);
  std::string out;
  // CLI11's "VALUE not in {a,b,c}": the closest allowed value.
  if (const auto in = error.find(" not in {"); in != std::string::npos && error.find('}', in) != std::string::npos) {
    const std::size_t colon = error.rfind(": ", in);
    const std::string value =
        error.substr(colon == std::string::npos ? 0 : colon + 2, in - (colon == std::string::npos ? 0 : colon + 2));
    std::vector<std::string> allowed;
    std::string list = error.substr(in + 9, error.find('}', in) - in - 9);
    for (std::size_t p = 0; p <= list.size();) {
      const std::size_t comma = std::min(list.find(',', p), list.size());
      allowed.push_back(list.substr(p, comma - p));
      p = comma + 1;
    }
    const std::string guess = closest(value, allowed);
    const std::string flag = colon == std::string::npos ? std::string() : error.substr(0, colon) + " ";
    if (!guess.empty()) out += flag + value + ": did you mean " + flag + guess + "?\n";
  }
  const auto takes_value = [&](const std::string& flag) {
    const CLI::Option* o = sub->get_option_no_throw(flag);
    return o && o->get_expected_min() > 0;
  };
  std::vector<std::string> names;  // the flags without their dashes
  for (const std::string& f : own) names.push_back(f.substr(2));
  for (int i = 2; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--") break;
    if (arg.rfind("-", 0) != 0) {  // a bare word that is no flag's value
      const std::string prev = i > 2 ? std::string(argv[i - 1]) : "";
      const bool known = std::find(own.begin(), own.end(), prev) != own.end();
      // (a value of a flag that takes one, or of a flag we do not know, is not the question)
      if (!(prev.rfind("--", 0) == 0 && prev.find('=') == std::string::npos && (takes_value(prev) || !known)) &&
          sub->get_options([](const CLI::Option* o) { return o->get_positional(); }).empty()) {
        std::string guess;
        for (const std::string& n : names)
          if (n.rfind(arg, 0) == 0 && takes_value("--" + n)) guess = guess.empty() ? n : "-";  // a unique prefix
        if (guess.empty() || guess == "-") guess = closest(arg, names);
        out += "tigris " + sub->get_name() + " takes flags, not the word '" + arg + "'" +
               (guess.empty() || guess == "-" ? " (tigris " + sub->get_name() + " --help lists them)"
                                              : "; did you mean --" + guess + " " + arg + "?") +
               "\n";
      }
      continue;
    }
    if (arg.rfind("--", 0) != 0) continue;
    arg = arg.substr(0, arg.find('='));
    if (std::find(own.begin(), own.end(), arg) != own.end()) continue;
    std::string elsewhere;
    for (const CLI::App* other : app.get_subcommands([](const CLI::App*) { return true; })) {
      const auto other_flags = flags_of(other);
      if (other != sub && std::find(other_flags.begin(), other_flags.end(), arg) != other_flags.end())
        elsewhere += (elsewhere.empty() ? "tigris " : " and tigris ") + other->get_name();
    }
    const std::string guess = closest(arg, own);
    out += "tigris " + sub->get_name() + " takes no " + arg + (guess.empty() ? "" : "; did you mean " + guess + "?") +
           (elsewhere.empty() ? "" : " (" + arg + " is a flag of " + elsewhere + ")") + "\n";
  }
  return out;
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
  struct stat sa {
  }, sb{};
  return stat(a.c_str(), &sa) == 0 && stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino &&
         S_ISREG(sa.st_mode);
}

}  // namespace

void check_distinct_paths(const std::vector<PathUse>& inputs, const std::vector<PathUse>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const PathUse& out = outputs[i];
    if (out.path.empty() || is_stream_path(out.path)) continue;  // /dev/null twice discards twice
    for (const PathUse& in : inputs)
      if (!in.path.empty() && same_file(in.path, out.path))
        throw std::invalid_argument(out.flag + " " + out.path + " would overwrite the input " + in.flag + " " +
                                    in.path + "; write the output elsewhere");
    for (std::size_t j = 0; j < i; ++j)
      if (!outputs[j].path.empty() && same_file(outputs[j].path, out.path))
        throw std::invalid_argument(out.flag + " " + out.path + " and " + outputs[j].flag + " " + outputs[j].path +
                                    " are the same file; give each output its own path");
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
