#include "workload_trace.hpp"

#include "core/input_file.hpp"

#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

#include "core/visible_text.hpp"
#include "sw_ref/arith.hpp"

namespace tigris::trace {
namespace {

constexpr char kMagic[8] = {'T', 'I', 'G', 'R', 'I', 'S', 'W', 'T'};
constexpr std::size_t kHeaderBytes = 40, kSectionHeaderBytes = 32;
enum Kind : std::uint32_t { kMeta = 1, kCloud = 2, kJob = 3 };
// A section may expand at most this much (a trace's clouds and results compress 1.5-4x; zstd
// goes past 1000x only on constant data, which encode pads to fit), so a forged size cannot make
// the reader allocate wildly.
constexpr std::uint64_t kMaxExpansion = 1024, kMaxRawSlack = 1 << 20;
// The metadata and job headers nest a few levels; nlohmann's copies and dumps recurse, so a file
// of 300,000 '[' would overflow the stack after parsing.
constexpr int kMaxJsonDepth = 64;

std::uint64_t fnv1a(const std::uint8_t* p, std::size_t n) {
  std::uint64_t h = 14695981039346656037ull;
  for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

// Little-endian writer of a section's raw bytes.
struct Out {
  std::vector<std::uint8_t> b;
  void raw(const void* p, std::size_t n) {
    const auto* c = static_cast<const std::uint8_t*>(p);
    b.insert(b.end(), c, c + n);
  }
  void u32(std::uint32_t v) { raw(&v, 4); }
  void u64(std::uint64_t v) { raw(&v, 8); }
  void varint(std::uint64_t v) {
    while (v >= 0x80) {
      b.push_back(static_cast<std::uint8_t>(v | 0x80));
      v >>= 7;
    }
    b.push_back(static_cast<std::uint8_t>(v));
  }
  void text(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    raw(s.data(), s.size());
  }
};

// Bounds-checked reader of one section's raw bytes; errors name the section's byte offset in
// the file and the offset inside the section.
struct In {
  const std::uint8_t* p;
  std::size_t size, pos = 0;
  std::string where;  // "LABEL: byte N (section S, KIND)"
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(where + ", offset " + std::to_string(pos) + " of its " + std::to_string(size) +
                     " decompressed bytes: " + what);
  }
  const std::uint8_t* take(std::size_t n) {
    if (n > size - pos) fail("truncated: " + std::to_string(n) + " more bytes needed");
    const std::uint8_t* at = p + pos;
    pos += n;
    return at;
  }
  std::uint32_t u32() {
    std::uint32_t v;
    std::memcpy(&v, take(4), 4);
    return v;
  }
  std::uint64_t u64() {
    std::uint64_t v;
    std::memcpy(&v, take(8), 8);
    return v;
  }
  std::uint64_t varint() {
    std::uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      const std::uint8_t c = *take(1);
      if (shift == 63 && c > 1) break;  // the 10th byte holds bit 63 only
      v |= std::uint64_t{c & 0x7fu} << shift;
      if (!(c & 0x80)) return v;
    }
    fail("a variable-length number longer than 64 bits");
  }
  nlohmann::json json() {
    const std::uint32_t n = u32();
    const auto* t = take(n);
    struct TooDeep {};
    struct Twice {
      std::string key;
    };
    std::vector<std::set<std::string>> keys;  // a key given twice would be kept silently (the last)
    try {
      return nlohmann::json::parse(
          t, t + n, [&](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
            using E = nlohmann::json::parse_event_t;
            if ((event == E::object_start || event == E::array_start) && depth >= kMaxJsonDepth) throw TooDeep{};
            if (event == E::object_start) keys.emplace_back();
            if (event == E::object_end && !keys.empty()) keys.pop_back();
            if (event == E::key && !keys.empty() && !keys.back().insert(parsed.get<std::string>()).second)
              throw Twice{parsed.get<std::string>()};
            return true;
          });
    } catch (const Twice& e) {
      fail("JSON key '" + visible_text(e.key, 40) + "' given twice in one object");
    } catch (const TooDeep&) {
      fail("JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    } catch (const nlohmann::json::exception& e) {
      fail(std::string("bad JSON: ") + visible_text(e.what()));
    }
  }
};

std::uint64_t zigzag(std::int64_t v) {
  return (static_cast<std::uint64_t>(v) << 1) ^ static_cast<std::uint64_t>(v >> 63);
}
std::int64_t unzigzag(std::uint64_t v) { return static_cast<std::int64_t>(v >> 1) ^ -static_cast<std::int64_t>(v & 1); }

nlohmann::json job_json(const Job& j) {
  return {{"stage", j.stage},
          {"iteration", j.iteration},
          {"backend", j.backend},
          {"tree", hash_text(j.tree)},
          {"queries", hash_text(j.queries)},
          {"tree_serial", j.tree_serial},
          {"top_height", j.top_height},
          {"mode", j.mode},
          {"k", j.k},
          {"radius", j.radius},
          {"max_nn", j.max_nn},
          {"approximate", j.approximate},
          {"approx_thd", j.approx_thd},
          {"leader_capacity", j.leader_capacity},
          {"leader_width", j.leader_width},
          {"leader_scope", j.leader_scope},
          {"leader_in_flight", j.leader_in_flight},
          {"inject_kth", j.inject_kth},
          {"shell_inner", j.shell_inner},
          {"shell_outer", j.shell_outer},
          {"search_seconds", j.search_seconds},
          {"build_seconds", j.build_seconds}};
}

// A JSON integer in T's range, nothing else: nlohmann's get<int>() truncates 1.5, wraps 2^32 + 1
// to 1 and converts 1e300 with undefined behaviour.
template <typename T>
T integer(const In& in, const nlohmann::json& j, const char* key) {
  const nlohmann::json& v = j.at(key);
  if (v.is_number_unsigned()) {
    const std::uint64_t u = v.get<std::uint64_t>();
    if (u <= static_cast<std::uint64_t>(std::numeric_limits<T>::max())) return static_cast<T>(u);
  } else if (v.is_number_integer()) {
    const std::int64_t i = v.get<std::int64_t>();
    if (i >= static_cast<std::int64_t>(std::numeric_limits<T>::min()) &&
        i <= static_cast<std::int64_t>(std::numeric_limits<T>::max()))
      return static_cast<T>(i);
  }
  in.fail(std::string("job header: '") + key + "' is not an integer in range: " + visible_text(v.dump(), 40));
}

// A JSON number a float32 holds (|x| <= FLT_MAX; rounded to the nearest float32): beyond it the
// conversion is undefined (in practice infinity, which encode would write as null).
float float32(const In& in, const nlohmann::json& j, const char* key) {
  const nlohmann::json& v = j.at(key);
  if (v.is_number()) {
    const double d = v.get<double>();
    if (std::fabs(d) <= static_cast<double>(std::numeric_limits<float>::max())) return static_cast<float>(d);
  }
  in.fail(std::string("job header: '") + key + "' is not a float32 number: " + visible_text(v.dump(), 40));
}

std::uint64_t parse_hash(const In& in, const nlohmann::json& v, const char* key) {
  const std::string s = v.get<std::string>();
  if (s.size() != 16 || s.find_first_not_of("0123456789abcdef") != std::string::npos)
    in.fail(std::string("'") + key + "' is not a 16-digit hex cloud hash: '" + visible_text(s, 40) + "'");
  return std::stoull(s, nullptr, 16);
}

Job job_from(In& in, const nlohmann::json& j) {
  Job out;
  try {
    out.stage = j.at("stage").get<std::string>();
    out.iteration = integer<int>(in, j, "iteration");
    out.backend = j.at("backend").get<std::string>();
    out.tree = parse_hash(in, j.at("tree"), "tree");
    out.queries = parse_hash(in, j.at("queries"), "queries");
    out.tree_serial = integer<int>(in, j, "tree_serial");
    out.top_height = integer<int>(in, j, "top_height");
    out.mode = j.at("mode").get<std::string>();
    out.k = integer<int>(in, j, "k");
    out.radius = float32(in, j, "radius");
    out.max_nn = integer<std::uint32_t>(in, j, "max_nn");
    out.approximate = j.at("approximate").get<bool>();
    out.approx_thd = float32(in, j, "approx_thd");
    out.leader_capacity = integer<int>(in, j, "leader_capacity");
    out.leader_width = integer<int>(in, j, "leader_width");
    out.leader_scope = j.value("leader_scope", std::string("every_leaf"));
    out.leader_in_flight = j.value("leader_in_flight", std::string("wait"));
    out.inject_kth = integer<int>(in, j, "inject_kth");
    out.shell_inner = float32(in, j, "shell_inner");
    out.shell_outer = float32(in, j, "shell_outer");
    out.search_seconds = j.at("search_seconds").get<double>();
    out.build_seconds = j.at("build_seconds").get<double>();
  } catch (const nlohmann::json::exception& e) {
    in.fail(std::string("job header: ") + visible_text(e.what()));
  }
  if (out.mode != "nn" && out.mode != "knn" && out.mode != "radius")
    in.fail("unknown mode '" + visible_text(out.mode, 20) + "'");
  if (out.stage.empty()) in.fail("a job without a stage name");
  if (out.backend != "flann" && out.backend != "exact" && out.backend != "approx")
    in.fail("unknown back-end '" + visible_text(out.backend, 20) + "' (flann, exact or approx)");
  if (out.leader_scope != "first_leaf" && out.leader_scope != "every_leaf")
    in.fail("unknown leader_scope '" + visible_text(out.leader_scope, 20) + "' (first_leaf or every_leaf)");
  if (out.leader_in_flight != "wait" && out.leader_in_flight != "finished_only")
    in.fail("unknown leader_in_flight '" + visible_text(out.leader_in_flight, 20) + "' (wait or finished_only)");
  if (out.search_seconds < 0 || out.build_seconds < 0) in.fail("a job with negative seconds");
  // (tree_serial -1 would read as "no tree sent yet" in the replay; the recorder numbers trees from 0)
  if (out.iteration < -1 || out.tree_serial < 0 || out.k < 1 || out.top_height < 0 || out.top_height > 30 ||
      out.leader_capacity < 0 || out.leader_width < 0 || out.inject_kth < 1 || !std::isfinite(out.radius) ||
      !std::isfinite(out.approx_thd) || !std::isfinite(out.shell_inner) || !std::isfinite(out.shell_outer) ||
      (out.mode == "radius" && !(out.radius > 0.0f)) || !std::isfinite(out.search_seconds) ||
      !std::isfinite(out.build_seconds))
    in.fail(
        "job parameters out of range (iteration, tree_serial, k, top_height, radius, leader settings, injection "
        "or seconds)");
  return out;
}

}  // namespace

std::uint64_t content_hash(const PointCloud& points) {
  return fnv1a(reinterpret_cast<const std::uint8_t*>(points.data()), points.size() * sizeof(Point3));
}

std::string hash_text(std::uint64_t hash) {
  char b[17];
  std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(hash));
  return b;
}

const Cloud& Trace::cloud(std::uint64_t hash) const {
  for (const Cloud& c : clouds)
    if (c.hash == hash) return c;
  throw std::out_of_range("no cloud " + hash_text(hash) + " in the trace");
}

std::uint64_t Trace::add_cloud(const PointCloud& points) {
  const std::uint64_t h = content_hash(points);
  for (const Cloud& c : clouds)
    if (c.hash == h) return h;
  clouds.push_back({h, points});
  return h;
}

JobResults results(const Trace& trace, const Job& job) {
  const PointCloud& tree = trace.cloud(job.tree).points;
  const PointCloud& queries = trace.cloud(job.queries).points;
  JobResults r;
  r.index = job.indices;
  r.dist2.reserve(job.indices.size());
  std::size_t at = 0;
  for (std::size_t q = 0; q < job.counts.size(); ++q) {
    for (std::uint32_t i = 0; i < job.counts[q]; ++i, ++at) r.dist2.push_back(dist2(queries[q], tree[job.indices[at]]));
    r.offset.push_back(at);
  }
  return r;
}

std::vector<std::uint8_t> encode(const Trace& trace) {
  std::vector<std::vector<std::uint8_t>> raw;  // each section's raw bytes, with its kind
  std::vector<std::uint32_t> kinds;
  {
    nlohmann::json m = {{"meta", trace.meta}, {"total_seconds", trace.total_seconds}};
    m["stages"] = nlohmann::json::array();
    for (const Stage& s : trace.stages)
      m["stages"].push_back({{"name", s.name},
                             {"seconds", s.seconds},
                             {"kdtree_search_seconds", s.kdtree_search_seconds},
                             {"kdtree_build_seconds", s.kdtree_build_seconds}});
    Out o;
    o.text(m.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));  // a non-UTF-8 path
    raw.push_back(std::move(o.b));
    kinds.push_back(kMeta);
  }
  for (const Cloud& c : trace.clouds) {
    Out o;
    o.u64(c.hash);
    o.u64(c.points.size());
    o.raw(c.points.data(), c.points.size() * sizeof(Point3));
    raw.push_back(std::move(o.b));
    kinds.push_back(kCloud);
  }
  for (const Job& j : trace.jobs) {
    Out o;
    o.text(job_json(j).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    o.u64(j.counts.size());
    for (std::uint32_t c : j.counts) o.u32(c);
    // Indices as zig-zag deltas from the previous one: a query's neighbours, and the next
    // query's, lie close together in a scan-ordered cloud, so most deltas take one byte.
    std::int64_t prev = 0;
    for (std::uint32_t i : j.indices) {
      o.varint(zigzag(static_cast<std::int64_t>(i) - prev));
      prev = i;
    }
    raw.push_back(std::move(o.b));
    kinds.push_back(kJob);
  }
  Out file;
  file.raw(kMagic, 8);
  file.u32(kVersion);
  file.u32(static_cast<std::uint32_t>(kHeaderBytes));
  file.u64(raw.size());
  file.u64(0);  // file size, set below
  file.u64(0);  // header checksum, set below
  for (std::size_t s = 0; s < raw.size(); ++s) {
    std::vector<std::uint8_t> z(ZSTD_compressBound(raw[s].size()));
    std::size_t n = ZSTD_compress(z.data(), z.size(), raw[s].data(), raw[s].size(), 3);
    if (ZSTD_isError(n)) throw std::runtime_error(std::string("trace: zstd: ") + ZSTD_getErrorName(n));
    // The reader refuses a section that expands more than kMaxExpansion times (plus
    // kMaxRawSlack); constant data (a cloud of 200,000 equal points) compresses further, so such
    // a section gets zstd skippable frames of padding after its data, which decompression skips.
    const std::uint64_t need =
        raw[s].size() > kMaxRawSlack ? (raw[s].size() - kMaxRawSlack + kMaxExpansion - 1) / kMaxExpansion : 0;
    z.resize(n);
    while (z.size() < need) {
      const std::uint32_t pad = static_cast<std::uint32_t>(
          std::min<std::uint64_t>(need - std::min<std::uint64_t>(need, z.size() + 8), 0xffffffffu));
      const std::uint32_t magic = 0x184D2A50;  // skippable frame: magic, size, that many bytes
      z.insert(z.end(), reinterpret_cast<const std::uint8_t*>(&magic),
               reinterpret_cast<const std::uint8_t*>(&magic) + 4);
      z.insert(z.end(), reinterpret_cast<const std::uint8_t*>(&pad), reinterpret_cast<const std::uint8_t*>(&pad) + 4);
      z.resize(z.size() + pad, 0);
    }
    n = z.size();
    file.u32(kinds[s]);
    file.u32(0);
    file.u64(n);
    file.u64(raw[s].size());
    file.u64(fnv1a(z.data(), n));
    file.raw(z.data(), n);
  }
  const std::uint64_t size = file.b.size();
  std::memcpy(file.b.data() + 24, &size, 8);
  const std::uint64_t check = fnv1a(file.b.data(), 32);
  std::memcpy(file.b.data() + 32, &check, 8);
  return std::move(file.b);
}

namespace {

// The metadata section: the registration's report, its total and per-stage times.
void read_meta(In& in, Trace& t) {
  const nlohmann::json m = in.json();
  try {
    t.meta = m.at("meta");
    if (!t.meta.is_object()) in.fail("metadata: 'meta' is not an object");
    t.total_seconds = m.at("total_seconds").get<double>();
    const nlohmann::json& stages = m.at("stages");
    // (nlohmann iterates null as empty and an object as its values)
    if (!stages.is_array()) in.fail("metadata: 'stages' is not an array");
    for (const auto& st : stages)
      t.stages.push_back({st.at("name").get<std::string>(), st.at("seconds").get<double>(),
                          st.at("kdtree_search_seconds").get<double>(), st.at("kdtree_build_seconds").get<double>()});
    // Times are measured: finite and not negative (a forged -5e12 s would print as a speed-up).
    const auto bad = [](double x) { return !std::isfinite(x) || x < 0; };
    if (bad(t.total_seconds)) in.fail("metadata: total_seconds is negative or not finite");
    for (const Stage& st : t.stages)
      if (st.name.empty() || bad(st.seconds) || bad(st.kdtree_search_seconds) || bad(st.kdtree_build_seconds))
        in.fail("metadata: stage '" + visible_text(st.name, 40) + "' has no name or negative or non-finite seconds");
  } catch (const nlohmann::json::exception& e) {
    in.fail(std::string("metadata: ") + visible_text(e.what()));
  }
}

// A cloud section: its points, checked against their hash; stored once.
void read_cloud(In& in, Trace& t, std::map<std::uint64_t, std::size_t>& cloud_at) {
  Cloud c;
  c.hash = in.u64();
  const std::uint64_t n_points = in.u64();
  if (n_points > (in.size - in.pos) / sizeof(Point3))
    in.fail("truncated: " + std::to_string(n_points) + " points announced");
  c.points.resize(n_points);
  const std::uint8_t* bytes = in.take(n_points * sizeof(Point3));
  if (n_points > 0)
    std::memcpy(c.points.data(), bytes, n_points * sizeof(Point3));  // an empty vector's data() may be null
  if (content_hash(c.points) != c.hash) in.fail("corrupt: the points do not match their hash " + hash_text(c.hash));
  for (const Point3& p : c.points)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) in.fail("a point is not finite");
  if (!cloud_at.emplace(c.hash, t.clouds.size()).second) in.fail("cloud " + hash_text(c.hash) + " is stored twice");
  t.clouds.push_back(std::move(c));
}

// A job section: the search, its clouds (stored before it) and its results, each index within its cloud.
void read_job(In& in, Trace& t, const std::map<std::uint64_t, std::size_t>& cloud_at) {
  Job j = job_from(in, in.json());
  const auto tree = cloud_at.find(j.tree), queries = cloud_at.find(j.queries);
  if (tree == cloud_at.end() || queries == cloud_at.end()) in.fail("the job names a cloud stored nowhere before it");
  const std::uint64_t nq = in.u64();
  if (nq != t.clouds[queries->second].points.size())
    in.fail(std::to_string(nq) + " result counts for " + std::to_string(t.clouds[queries->second].points.size()) +
            " queries");
  j.counts.resize(nq);
  std::uint64_t total = 0;
  for (auto& c : j.counts) total += (c = in.u32());
  if (total > in.size - in.pos) in.fail("truncated: " + std::to_string(total) + " result indices announced");
  j.indices.resize(total);
  const std::uint64_t points = t.clouds[tree->second].points.size();
  // Indices are uint32: a cloud of more points still takes only the first 2^32.
  const std::uint64_t limit = std::min<std::uint64_t>(points, std::uint64_t{1} << 32);
  std::uint64_t prev = 0;  // the previous index, < limit: prev + delta is checked without overflowing
  for (auto& i : j.indices) {
    const std::int64_t delta = unzigzag(in.varint());
    const std::uint64_t step = delta < 0 ? 0 - static_cast<std::uint64_t>(delta) : static_cast<std::uint64_t>(delta);
    if (delta < 0 ? step > prev : step >= limit - prev)
      in.fail("a result index " + std::to_string(prev) + (delta < 0 ? " - " : " + ") + std::to_string(step) +
              " beyond its cloud of " + std::to_string(points) + " points");
    prev = delta < 0 ? prev - step : prev + step;
    i = static_cast<std::uint32_t>(prev);
  }
  t.jobs.push_back(std::move(j));
}

}  // namespace

Trace decode(const std::uint8_t* data, std::size_t size, const std::string& label) {
  const auto fail = [&](std::uint64_t at, const std::string& what) -> void {
    throw InputError(label + ": byte " + std::to_string(at) + ": " + what);
  };
  if (size < 8 || std::memcmp(data, kMagic, 8) != 0)
    fail(0, "not a Tigris workload trace (it does not start with TIGRISWT)");
  if (size < kHeaderBytes) fail(size, "truncated: the header needs 40 bytes, the file has " + std::to_string(size));
  std::uint32_t version, header_bytes;
  std::uint64_t sections, file_size, check;
  std::memcpy(&version, data + 8, 4);
  std::memcpy(&header_bytes, data + 12, 4);
  std::memcpy(&sections, data + 16, 8);
  std::memcpy(&file_size, data + 24, 8);
  std::memcpy(&check, data + 32, 8);
  if (version > kVersion)
    fail(8, "trace format version " + std::to_string(version) + " is newer than this tigris reads (" +
                std::to_string(kVersion) + "); use a newer tigris");
  if (version == 0 || header_bytes != kHeaderBytes) fail(8, "bad version or header size");
  if (fnv1a(data, 32) != check) fail(32, "corrupt: the header checksum does not match");
  if (file_size != size)
    fail(size < file_size ? size : file_size,
         size < file_size ? "truncated: the header says " + std::to_string(file_size) + " bytes, the file has " +
                                std::to_string(size)
                          : "the file goes on past its end (" + std::to_string(size - file_size) + " bytes more)");
  Trace t;
  std::uint64_t at = kHeaderBytes;
  std::map<std::uint64_t, std::size_t> cloud_at;
  for (std::uint64_t s = 0; s < sections; ++s) {
    if (size - at < kSectionHeaderBytes) fail(at, "truncated: section " + std::to_string(s) + " has no header");
    std::uint32_t kind, reserved;
    std::uint64_t zbytes, rbytes, zcheck;
    std::memcpy(&kind, data + at, 4);
    std::memcpy(&reserved, data + at + 4, 4);
    std::memcpy(&zbytes, data + at + 8, 8);
    std::memcpy(&rbytes, data + at + 16, 8);
    std::memcpy(&zcheck, data + at + 24, 8);
    const std::uint64_t body = at + kSectionHeaderBytes;
    if (kind < kMeta || kind > kJob) fail(at, "unknown section kind " + std::to_string(kind));
    if (reserved != 0) fail(at + 4, "section " + std::to_string(s) + "'s reserved field is not 0");
    if ((s == 0) != (kind == kMeta)) fail(at, "the first section, and only it, must be the metadata");
    if (zbytes > size - body)
      fail(body, "truncated: section " + std::to_string(s) + " needs " + std::to_string(zbytes) + " bytes");
    if (rbytes > zbytes * kMaxExpansion + kMaxRawSlack) fail(at + 16, "corrupt: implausible decompressed size");
    if (fnv1a(data + body, zbytes) != zcheck)
      fail(body, "corrupt: section " + std::to_string(s) + "'s checksum does not match");
    std::vector<std::uint8_t> raw(rbytes);
    const std::size_t n = ZSTD_decompress(raw.data(), raw.size(), data + body, zbytes);
    if (ZSTD_isError(n) || n != rbytes) fail(body, "corrupt: section " + std::to_string(s) + " does not decompress");
    static const char* names[] = {"", "metadata", "cloud", "job"};
    In in{raw.data(), raw.size(), 0,
          label + ": byte " + std::to_string(body) + " (section " + std::to_string(s) + ", " + names[kind] + ")"};
    if (kind == kMeta)
      read_meta(in, t);
    else if (kind == kCloud)
      read_cloud(in, t, cloud_at);
    else
      read_job(in, t, cloud_at);
    if (in.pos != in.size) in.fail("unread bytes at the end of the section");
    at = body + zbytes;
  }
  if (sections == 0) fail(16, "no sections: a trace holds at least its metadata");
  if (at != size) fail(at, "bytes after the last section");
  return t;
}

Trace read_trace(const std::string& path) {
  const std::string bytes = read_input(path, "the trace");
  return decode(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), path);
}

}  // namespace tigris::trace
