#include "traces/workload_trace.hpp"

#include <unistd.h>
#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>

#include "sw_ref/arith.hpp"
#include "sw_ref/visible_text.hpp"

namespace tigris::trace {
namespace {

constexpr char kMagic[8] = {'T', 'I', 'G', 'R', 'I', 'S', 'W', 'T'};
constexpr std::size_t kHeaderBytes = 40, kSectionHeaderBytes = 32;
enum Kind : std::uint32_t { kMeta = 1, kCloud = 2, kJob = 3 };
// A section may expand at most this much (zstd reaches ~1000x only on constant data; a trace's
// clouds and results compress 1.5-4x), so a forged size cannot make the reader allocate wildly.
constexpr std::uint64_t kMaxExpansion = 1024, kMaxRawSlack = 1 << 20;

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
      v |= std::uint64_t{c & 0x7fu} << shift;
      if (!(c & 0x80)) return v;
    }
    fail("a variable-length number longer than 64 bits");
  }
  nlohmann::json json() {
    const std::uint32_t n = u32();
    const auto* t = take(n);
    try {
      return nlohmann::json::parse(t, t + n);
    } catch (const nlohmann::json::exception& e) {
      fail(std::string("bad JSON: ") + visible_text(e.what()));
    }
  }
};

std::uint64_t zigzag(std::int64_t v) { return (static_cast<std::uint64_t>(v) << 1) ^ static_cast<std::uint64_t>(v >> 63); }
std::int64_t unzigzag(std::uint64_t v) { return static_cast<std::int64_t>(v >> 1) ^ -static_cast<std::int64_t>(v & 1); }

nlohmann::json job_json(const Job& j) {
  return {{"stage", j.stage}, {"iteration", j.iteration}, {"backend", j.backend},
          {"tree", hash_text(j.tree)}, {"queries", hash_text(j.queries)}, {"tree_serial", j.tree_serial},
          {"top_height", j.top_height}, {"mode", j.mode}, {"k", j.k}, {"radius", j.radius},
          {"max_nn", j.max_nn}, {"approximate", j.approximate}, {"approx_thd", j.approx_thd},
          {"leader_capacity", j.leader_capacity}, {"leader_width", j.leader_width},
          {"inject_kth", j.inject_kth}, {"shell_inner", j.shell_inner}, {"shell_outer", j.shell_outer},
          {"search_seconds", j.search_seconds}, {"build_seconds", j.build_seconds}};
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
    out.iteration = j.at("iteration").get<int>();
    out.backend = j.at("backend").get<std::string>();
    out.tree = parse_hash(in, j.at("tree"), "tree");
    out.queries = parse_hash(in, j.at("queries"), "queries");
    out.tree_serial = j.at("tree_serial").get<int>();
    out.top_height = j.at("top_height").get<int>();
    out.mode = j.at("mode").get<std::string>();
    out.k = j.at("k").get<int>();
    out.radius = j.at("radius").get<float>();
    out.max_nn = j.at("max_nn").get<std::uint32_t>();
    out.approximate = j.at("approximate").get<bool>();
    out.approx_thd = j.at("approx_thd").get<float>();
    out.leader_capacity = j.at("leader_capacity").get<int>();
    out.leader_width = j.at("leader_width").get<int>();
    out.inject_kth = j.at("inject_kth").get<int>();
    out.shell_inner = j.at("shell_inner").get<float>();
    out.shell_outer = j.at("shell_outer").get<float>();
    out.search_seconds = j.at("search_seconds").get<double>();
    out.build_seconds = j.at("build_seconds").get<double>();
  } catch (const nlohmann::json::exception& e) {
    in.fail(std::string("job header: ") + visible_text(e.what()));
  }
  if (out.mode != "nn" && out.mode != "knn" && out.mode != "radius") in.fail("unknown mode '" + visible_text(out.mode, 20) + "'");
  if (out.k < 1 || out.top_height < 0 || out.top_height > 30 || out.leader_capacity < 0 || out.leader_width < 0 ||
      out.inject_kth < 1 || !std::isfinite(out.radius) || !std::isfinite(out.approx_thd) ||
      (out.mode == "radius" && !(out.radius > 0.0f)) || !std::isfinite(out.search_seconds) ||
      !std::isfinite(out.build_seconds))
    in.fail("job parameters out of range (k, top_height, radius, leader settings, injection or seconds)");
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
      m["stages"].push_back({{"name", s.name}, {"seconds", s.seconds},
                             {"kdtree_search_seconds", s.kdtree_search_seconds},
                             {"kdtree_build_seconds", s.kdtree_build_seconds}});
    Out o;
    o.text(m.dump());
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
    o.text(job_json(j).dump());
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
    const std::size_t n = ZSTD_compress(z.data(), z.size(), raw[s].data(), raw[s].size(), 3);
    if (ZSTD_isError(n)) throw std::runtime_error(std::string("trace: zstd: ") + ZSTD_getErrorName(n));
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

void write_trace(const std::string& path, const Trace& trace) {
  const std::vector<std::uint8_t> bytes = encode(trace);
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream f(tmp, std::ios::binary);
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    f.flush();
    if (!f) {
      std::filesystem::remove(tmp, ec);
      throw std::runtime_error(path + ": cannot write the trace");
    }
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot write the trace");
  }
}

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
    if (kind < kMeta || kind > kJob || reserved != 0) fail(at, "unknown section kind " + std::to_string(kind));
    if ((s == 0) != (kind == kMeta)) fail(at, "the first section, and only it, must be the metadata");
    if (zbytes > size - body) fail(body, "truncated: section " + std::to_string(s) + " needs " + std::to_string(zbytes) + " bytes");
    if (rbytes > zbytes * kMaxExpansion + kMaxRawSlack) fail(at + 16, "corrupt: implausible decompressed size");
    if (fnv1a(data + body, zbytes) != zcheck) fail(body, "corrupt: section " + std::to_string(s) + "'s checksum does not match");
    std::vector<std::uint8_t> raw(rbytes);
    const std::size_t n = ZSTD_decompress(raw.data(), raw.size(), data + body, zbytes);
    if (ZSTD_isError(n) || n != rbytes) fail(body, "corrupt: section " + std::to_string(s) + " does not decompress");
    static const char* names[] = {"", "metadata", "cloud", "job"};
    In in{raw.data(), raw.size(), 0,
          label + ": byte " + std::to_string(body) + " (section " + std::to_string(s) + ", " + names[kind] + ")"};
    if (kind == kMeta) {
      const nlohmann::json m = in.json();
      try {
        t.meta = m.at("meta");
        t.total_seconds = m.at("total_seconds").get<double>();
        for (const auto& st : m.at("stages"))
          t.stages.push_back({st.at("name").get<std::string>(), st.at("seconds").get<double>(),
                              st.at("kdtree_search_seconds").get<double>(), st.at("kdtree_build_seconds").get<double>()});
      } catch (const nlohmann::json::exception& e) {
        in.fail(std::string("metadata: ") + visible_text(e.what()));
      }
    } else if (kind == kCloud) {
      Cloud c;
      c.hash = in.u64();
      const std::uint64_t n_points = in.u64();
      if (n_points > (in.size - in.pos) / sizeof(Point3)) in.fail("truncated: " + std::to_string(n_points) + " points announced");
      c.points.resize(n_points);
      std::memcpy(c.points.data(), in.take(n_points * sizeof(Point3)), n_points * sizeof(Point3));
      if (content_hash(c.points) != c.hash) in.fail("corrupt: the points do not match their hash " + hash_text(c.hash));
      for (const Point3& p : c.points)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) in.fail("a point is not finite");
      if (!cloud_at.emplace(c.hash, t.clouds.size()).second) in.fail("cloud " + hash_text(c.hash) + " is stored twice");
      t.clouds.push_back(std::move(c));
    } else {
      Job j = job_from(in, in.json());
      const auto tree = cloud_at.find(j.tree), queries = cloud_at.find(j.queries);
      if (tree == cloud_at.end() || queries == cloud_at.end())
        in.fail("the job names a cloud stored nowhere before it");
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
      std::int64_t prev = 0;
      for (auto& i : j.indices) {
        prev += unzigzag(in.varint());
        if (prev < 0 || static_cast<std::uint64_t>(prev) >= points)
          in.fail("a result index " + std::to_string(prev) + " beyond its cloud of " + std::to_string(points) + " points");
        i = static_cast<std::uint32_t>(prev);
      }
      t.jobs.push_back(std::move(j));
    }
    if (in.pos != in.size) in.fail("unread bytes at the end of the section");
    at = body + zbytes;
  }
  if (sections == 0) fail(16, "no sections: a trace holds at least its metadata");
  if (at != size) fail(at, "bytes after the last section");
  return t;
}

Trace read_trace(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a folder, not a trace");
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path + ": cannot open the trace: " + std::strerror(errno));
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (f.bad()) throw InputError(path + ": cannot read the trace");
  return decode(bytes.data(), bytes.size(), path);
}

}  // namespace tigris::trace
