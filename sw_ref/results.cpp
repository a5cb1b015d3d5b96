#include "results.hpp"

#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <sstream>

namespace tigris {

namespace {

std::uint32_t bits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

std::string describe(const Results& r, std::size_t q) {
  std::ostringstream s;
  s << "[";
  const std::size_t shown = std::min<std::size_t>(r.count(q), 8);
  for (std::size_t i = 0; i < shown; ++i) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s(%" PRIu32 ", %.9g)", i ? " " : "", r.begin(q)[i].index,
                  static_cast<double>(r.begin(q)[i].dist2));
    s << buf;
  }
  if (r.count(q) > shown) s << " ... " << r.count(q) << " in all";
  s << "]";
  return s.str();
}

}  // namespace

std::optional<std::string> first_difference(const Results& expected, const Results& actual) {
  if (expected.num_queries() != actual.num_queries())
    return "query counts differ: expected " + std::to_string(expected.num_queries()) + ", got " +
           std::to_string(actual.num_queries());
  for (std::size_t q = 0; q < expected.num_queries(); ++q) {
    bool same = expected.count(q) == actual.count(q);
    for (std::size_t i = 0; same && i < expected.count(q); ++i) {
      const Neighbor &a = expected.begin(q)[i], &b = actual.begin(q)[i];
      same = a.index == b.index && bits(a.dist2) == bits(b.dist2);
    }
    if (!same)
      return "query " + std::to_string(q) + ": expected " + describe(expected, q) + ", got " + describe(actual, q);
  }
  return std::nullopt;
}

void write_results_csv(std::ostream& out, const Results& results) {
  out << "query,rank,index,dist2\n";
  char line[96];
  for (std::size_t q = 0; q < results.num_queries(); ++q) {
    for (std::size_t i = 0; i < results.count(q); ++i) {
      const Neighbor& n = results.begin(q)[i];
      std::snprintf(line, sizeof line, "%zu,%zu,%" PRIu32 ",%.9g\n", q, i, n.index, static_cast<double>(n.dist2));
      out << line;
    }
  }
}

}  // namespace tigris
