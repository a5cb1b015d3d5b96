// Fuzz target: the results CSV reader (traces/results_csv.hpp, the inverse of
// `--dump-results`). Input whose first byte is 0: the rest describes a result set (queries,
// neighbours in canonical order, any finite non-negative dist2), which is written by
// write_results_csv and must read back exactly. Any other input is a CSV file: a clean error
// naming the file, or results whose rows are the file's rows (an independent split of each
// line) and that survive a write and re-read.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "fuzz_common.hpp"
#include "traces/results_csv.hpp"

namespace {

using namespace tigris_fuzz;
const char* const kTarget = "results_csv";
const std::string kLabel = "fuzz.csv";

std::string difference(const tigris::Results& a, const tigris::Results& b) {
  if (a.offset != b.offset) return "queries or neighbour counts differ";
  for (std::size_t i = 0; i < a.neighbors.size(); ++i)
    if (a.neighbors[i].index != b.neighbors[i].index ||
        float_bits(a.neighbors[i].dist2) != float_bits(b.neighbors[i].dist2))
      return "neighbour " + std::to_string(i) + " differs";
  return "";
}

tigris::Results parse(const std::string& text, std::size_t num_queries = 0) {
  return tigris::parse_results_csv(text.data(), text.size(), kLabel, num_queries);
}

void check_generated(const std::uint8_t* data, std::size_t size) {
  ByteSource s(data + 1, size - 1);
  tigris::Results r;
  const std::size_t queries = s.range(0, 12);
  for (std::size_t q = 0; q < queries; ++q) {
    std::vector<tigris::Neighbor> list;
    const std::size_t n = s.range(0, 6);
    for (std::size_t k = 0; k < n; ++k) {
      tigris::Neighbor nb;
      nb.index = static_cast<std::uint32_t>(s.chance(50) ? s.range(0, 20) : s.range(0, 0xFFFFFFFEu));
      const std::uint32_t b = static_cast<std::uint32_t>(s.bits(32)) & 0x7FFFFFFFu;  // non-negative
      std::memcpy(&nb.dist2, &b, 4);
      if (!std::isfinite(nb.dist2) || s.chance(30)) nb.dist2 = static_cast<float>(s.range(0, 4)) * 0.25f;
      bool dup = false;
      for (const auto& o : list) dup = dup || o.index == nb.index;
      if (!dup) list.push_back(nb);
    }
    std::sort(list.begin(), list.end(), [](const auto& a, const auto& b) { return tigris::closer(a, b); });
    r.append_query(list.data(), list.data() + list.size());
  }
  std::ostringstream out;
  tigris::write_results_csv(out, r);
  tigris::Results back;
  try {
    back = parse(out.str(), queries);
  } catch (const tigris::InputError& e) {
    wrong_read(kTarget, std::string("a dump rejected: ") + e.what() + "\n" + out.str().substr(0, 400));
  }
  const std::string diff = difference(back, r);
  if (!diff.empty()) wrong_read(kTarget, diff + "\n" + out.str().substr(0, 400));
}

void check_raw(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  tigris::Results r;
  try {
    r = parse(text);
  } catch (const tigris::InputError& e) {
    if (!names_source(e.what(), kLabel)) wrong_read(kTarget, std::string("error without the file name: ") + e.what());
    return;
  }
  // Independent decode of the rows.
  std::istringstream lines(text);
  std::string line;
  std::getline(lines, line);
  std::size_t row = 0;
  while (std::getline(lines, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::size_t c1 = line.find(','), c2 = line.find(',', c1 + 1), c3 = line.find(',', c2 + 1);
    if (c3 == std::string::npos) wrong_read(kTarget, "row " + std::to_string(row) + " accepted: " + line);
    const unsigned long long q = std::stoull(line.substr(0, c1)), rank = std::stoull(line.substr(c1 + 1, c2 - c1 - 1)),
                             index = std::stoull(line.substr(c2 + 1, c3 - c2 - 1));
    const float d = std::strtof(line.c_str() + c3 + 1, nullptr);
    if (row >= r.neighbors.size() || q >= r.num_queries() || rank >= r.count(q) || r.offset[q] + rank != row ||
        r.neighbors[row].index != index || float_bits(r.neighbors[row].dist2) != float_bits(d))
      wrong_read(kTarget, "row " + std::to_string(row) + " read differently: " + line);
    ++row;
  }
  if (row != r.neighbors.size()) wrong_read(kTarget, "row count differs");
  std::ostringstream out;
  tigris::write_results_csv(out, r);
  const std::string diff = difference(parse(out.str(), r.num_queries()), r);
  if (!diff.empty()) wrong_read(kTarget, "write and re-read: " + diff);
}

}  // namespace

extern "C" int TIGRIS_FUZZ_ENTRY(const std::uint8_t* data, std::size_t size) {
  if (size > 0 && data[0] == 0)
    check_generated(data, size);
  else
    check_raw(data, size);
  return 0;
}
