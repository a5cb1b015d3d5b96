#include "results_csv.hpp"

#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <unordered_set>

#include "core/input_file.hpp"
#include "workloads/io/reader_util.hpp"

namespace tigris {
namespace {

using io_detail::fail_line;
using io_detail::printable;

constexpr std::uint64_t kMaxInferredQueries = std::uint64_t{1} << 24;

// "a,b,c,d": three unsigned integers and a float, nothing else (no blanks, no signs).
bool parse_row(std::string_view line, std::uint64_t (&v)[3], float& d) {
  const char* p = line.data();
  const char* end = p + line.size();
  for (int i = 0; i < 3; ++i) {
    if (p == end || *p < '0' || *p > '9') return false;
    const auto r = std::from_chars(p, end, v[i]);
    if (r.ec != std::errc() || r.ptr == end || *r.ptr != ',') return false;
    p = r.ptr + 1;
  }
  if (p == end || !((*p >= '0' && *p <= '9') || *p == '.')) return false;  // no sign, no nan/inf
  const auto r = std::from_chars(p, end, d);
  return r.ec == std::errc() && r.ptr == end;
}

}  // namespace

Results parse_results_csv(const char* data, std::size_t size, const std::string& label, std::size_t num_queries) {
  // Lines: split at '\n', a '\r' before it dropped.
  std::size_t pos = 0, lineno = 0;
  auto next = [&](std::string_view& line) {
    if (pos >= size) return false;
    const void* nl = std::memchr(data + pos, '\n', size - pos);
    const std::size_t end = nl ? static_cast<std::size_t>(static_cast<const char*>(nl) - data) : size;
    std::size_t stop = end;
    if (stop > pos && data[stop - 1] == '\r') --stop;
    line = std::string_view(data + pos, stop - pos);
    pos = nl ? end + 1 : size;
    ++lineno;
    return true;
  };
  std::string_view line;
  if (!next(line) || line != "query,rank,index,dist2")
    fail_line(label, 1, "expected the header 'query,rank,index,dist2'");
  Results results;
  std::uint64_t current = 0;                  // the query of the previous row
  std::unordered_set<std::uint64_t> indices;  // the current query's neighbours
  bool any = false;
  while (next(line)) {
    if (line.empty()) continue;
    std::uint64_t v[3];
    float d = 0.0f;
    if (!parse_row(line, v, d))
      fail_line(label, lineno,
                "expected 'query,rank,index,dist2' (three unsigned integers and a "
                "number), got '" +
                    printable(line) + "'");
    const std::uint64_t q = v[0], rank = v[1], index = v[2];
    if (any && q < current)
      fail_line(label, lineno,
                "query " + std::to_string(q) + " after query " + std::to_string(current) +
                    " (queries must come in index order)");
    if (num_queries != 0 && q >= num_queries)
      fail_line(label, lineno,
                "query " + std::to_string(q) + " beyond the " + std::to_string(num_queries) + " queries");
    if (q >= 0xFFFFFFFFu) fail_line(label, lineno, "query " + std::to_string(q) + " out of range");
    // Results keep one offset per query, rows or not: an inferred count is capped (a stray
    // digit must not allocate gigabytes); callers that know more pass num_queries.
    if (num_queries == 0 && q >= kMaxInferredQueries)
      fail_line(label, lineno,
                "query " + std::to_string(q) + " beyond " + std::to_string(kMaxInferredQueries) +
                    " queries (give the query count to read more)");
    if (index >= 0xFFFFFFFFu) fail_line(label, lineno, "index " + std::to_string(index) + " out of range");
    if (!std::isfinite(d)) fail_line(label, lineno, "dist2 is not a finite float32");
    const bool same = any && q == current;
    const std::uint64_t expected_rank = same ? results.neighbors.size() - results.offset.back() : 0;
    if (rank != expected_rank)
      fail_line(label, lineno,
                "rank " + std::to_string(rank) + " of query " + std::to_string(q) + " (expected " +
                    std::to_string(expected_rank) + ")");
    if (!same) indices.clear();
    if (same && !closer(results.neighbors.back(), Neighbor{static_cast<std::uint32_t>(index), d}))
      fail_line(label, lineno, "neighbours of query " + std::to_string(q) + " out of canonical (dist2, index) order");
    if (!indices.insert(index).second)
      fail_line(label, lineno, "index " + std::to_string(index) + " appears twice in query " + std::to_string(q));
    // Close the queries before q (those without a row have no neighbour).
    while (results.num_queries() + 1 <= q) results.offset.push_back(results.neighbors.size());
    results.neighbors.push_back(Neighbor{static_cast<std::uint32_t>(index), d});
    current = q;
    any = true;
  }
  // `offset` holds one entry per closed query; the last query with rows is still open.
  if (any) results.offset.push_back(results.neighbors.size());
  while (results.num_queries() < num_queries) results.offset.push_back(results.neighbors.size());
  return results;
}

Results read_results_csv(const std::string& path, std::size_t num_queries) {
  const std::string text = read_input(path, "the results file");
  return parse_results_csv(text.data(), text.size(), path, num_queries);
}

}  // namespace tigris
