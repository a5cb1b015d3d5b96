#include "flag_values.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace tigris {

std::pair<int, int> parse_frame_pair(const std::string& text) {
  int a = -1, b = -1;
  char comma = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &a, &comma, &b, &extra) != 3 || comma != ',' || a < 0 || b < 0)
    throw std::invalid_argument("--kitti-frames must be SOURCE,TARGET frame numbers (e.g. 1,0), got '" + text + "'");
  return {a, b};
}

double parse_number(const std::string& flag, const std::string& text) {
  std::size_t used = 0;
  double x = NAN;
  try {
    x = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(x) || x < 0)
    throw std::invalid_argument(flag + " must be a number >= 0 (metres), got '" + text + "'");
  return x;
}

int parse_kth(const std::string& text) {
  std::size_t used = 0;
  long long k = 0;
  try {
    k = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (text.empty() || used != text.size() || k < 1 || k > 100000)
    throw std::invalid_argument("--inject-kth must be an integer K in 1..100000 (1: the nearest, no error), got '" +
                                text + "'");
  return static_cast<int>(k);
}

std::pair<double, double> parse_shell(const std::string& text, double r) {
  const auto comma = text.find(',');
  const auto number = [&](const std::string& part, double& x) {
    std::size_t used = 0;
    try {
      x = std::stod(part, &used);
    } catch (const std::exception&) {
      return false;
    }
    return used == part.size() && std::isfinite(x);
  };
  double r1 = NAN, r2 = NAN;
  if (comma == std::string::npos || !number(text.substr(0, comma), r1) || !number(text.substr(comma + 1), r2))
    throw std::invalid_argument("--inject-shell must be R1,R2 in metres (e.g. 0.1,0.4), got '" + text + "'");
  char buf[160];
  if (r1 < 0 || r1 >= r2) {
    std::snprintf(buf, sizeof buf, "--inject-shell %s: needs 0 <= R1 < R2, got R1 = %g, R2 = %g", text.c_str(), r1, r2);
    throw std::invalid_argument(buf);
  }
  if (r1 >= r || r2 <= r) {
    std::snprintf(buf, sizeof buf,
                  "--inject-shell %s: needs R1 < r < R2 around the normal radius r = %g (normals.radius), got "
                  "R1 = %g, R2 = %g",
                  text.c_str(), r, r1, r2);
    throw std::invalid_argument(buf);
  }
  return {r1, r2};
}

std::pair<std::size_t, std::size_t> parse_frame_range(const std::string& text, std::size_t scans) {
  if (text.empty()) return {0, scans - 1};
  long a = -1, b = -1;
  char colon = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%ld%c%ld%c", &a, &colon, &b, &extra) != 3 || colon != ':' || a < 0 || b <= a)
    throw std::invalid_argument("--frames must be A:B, the first and the last frame (A < B), got '" + text + "'");
  if (static_cast<std::size_t>(b) >= scans)
    throw std::invalid_argument("--frames " + text + ": the sequence has frames 0.." + std::to_string(scans - 1));
  return {static_cast<std::size_t>(a), static_cast<std::size_t>(b)};
}

int parse_height(const std::string& text) {
  if (text == "full") return -1;
  std::size_t used = 0;
  int h = -1;
  try {
    h = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || h < 0 || h > 30)
    throw std::invalid_argument("--height must be 'full' or a whole number from 0 to 30, got '" + text + "'");
  return h;
}

}  // namespace tigris
