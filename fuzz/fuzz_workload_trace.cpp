// Fuzz target: the workload trace reader (traces/workload_trace.hpp, `tigris run --trace`).
//
// Any input is a trace file: decode gives a clean error (InputError "fuzz.trace: byte N: ...")
// or a trace that (1) matches an independent decode of the same bytes (header, section headers,
// FNV-1a checksums, zstd, then each payload: the metadata JSON, a cloud's hash and float bits,
// a job's JSON fields, counts and zig-zag varint index deltas), (2) keeps the reader's promises
// (clouds unique and matching their hashes, finite points, parameters in range, counts per query,
// indices inside the tree cloud, results() = the contract's dist2 of query and point), and (3)
// re-encodes to a file that decodes equal, field by field and bit for bit, and encodes to the
// same bytes again.
//
// Input whose first byte is 0: the rest builds a small trace (a few clouds of finite floats with
// -0 and denormals, now and then one of 1,000-120,000 points; jobs on them with counts and indices
// that fit, repeated and jumping; any mode, k, radius, stage names and seconds), which must
// decode equal after encode. Then the encoding is damaged, choices from the input:
//  - bytes flipped, cut, inserted, erased or appended (mostly in the header and the section
//    headers): a clean error naming "fuzz.trace: byte ", or, when the damage hits nothing the
//    reader checks (it never should), the same trace; a different trace is a wrong read. A
//    version above 1 must be refused naming byte 8.
//  - a section's decompressed payload edited (bytes, numbers, varints, JSON values of every kind
//    in place of a field, deep JSON, cloud points and hashes, counts) or the sections reordered,
//    dropped, repeated, re-kinded, split into several zstd frames or frames without their size,
//    and the file resealed with valid sizes and checksums: a clean error, or a trace that passes
//    (1)-(3).
#include <zstd.h>

#include <algorithm>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "fuzz_common.hpp"
#include "sw_ref/arith.hpp"
#include "traces/workload_trace.hpp"

namespace {

using namespace tigris_fuzz;
namespace trace = tigris::trace;
using nlohmann::json;
using Bytes = std::vector<std::uint8_t>;
const char* const kTarget = "workload_trace";
const std::string kLabel = "fuzz.trace";

// ---------------------------------------------------------------------------------------------
// The file layout, written out independently of the reader.

std::uint64_t fnv1a(const std::uint8_t* p, std::size_t n) {
  std::uint64_t h = 14695981039346656037ull;
  for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

template <typename T>
T load(const std::uint8_t* p) {  // little-endian (x86), as the format
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <typename T>
void store(Bytes& b, std::size_t at, T v) {
  std::memcpy(b.data() + at, &v, sizeof v);
}
template <typename T>
void put(Bytes& b, T v) {
  const auto* c = reinterpret_cast<const std::uint8_t*>(&v);
  b.insert(b.end(), c, c + sizeof v);
}

struct Section {
  std::uint32_t kind;  // 1 metadata, 2 cloud, 3 job
  Bytes raw;           // decompressed payload
  std::size_t at;      // offset of its 32-byte header in the file
};

// The sections of a file the reader accepted; anything that does not fit the layout there is a
// wrong read.
std::vector<Section> split(const std::uint8_t* d, std::size_t n) {
  if (n < 40 || std::memcmp(d, "TIGRISWT", 8) != 0) wrong_read(kTarget, "accepted without magic or header");
  if (load<std::uint32_t>(d + 8) != 1 || load<std::uint32_t>(d + 12) != 40)
    wrong_read(kTarget, "accepted version " + std::to_string(load<std::uint32_t>(d + 8)) + ", header size " +
                            std::to_string(load<std::uint32_t>(d + 12)));
  if (load<std::uint64_t>(d + 24) != n) wrong_read(kTarget, "accepted with a wrong file size");
  if (load<std::uint64_t>(d + 32) != fnv1a(d, 32)) wrong_read(kTarget, "accepted with a wrong header checksum");
  const std::uint64_t count = load<std::uint64_t>(d + 16);
  std::vector<Section> out;
  std::size_t at = 40;
  for (std::uint64_t s = 0; s < count; ++s) {
    if (n - at < 32) wrong_read(kTarget, "accepted with section " + std::to_string(s) + " missing");
    const std::uint32_t kind = load<std::uint32_t>(d + at), reserved = load<std::uint32_t>(d + at + 4);
    const std::uint64_t z = load<std::uint64_t>(d + at + 8), r = load<std::uint64_t>(d + at + 16);
    if (kind < 1 || kind > 3 || reserved != 0) wrong_read(kTarget, "accepted section kind/reserved");
    if ((s == 0) != (kind == 1)) wrong_read(kTarget, "accepted with the metadata not first, or twice");
    if (z > n - at - 32) wrong_read(kTarget, "accepted a section beyond the end");
    if (load<std::uint64_t>(d + at + 24) != fnv1a(d + at + 32, z)) wrong_read(kTarget, "accepted a section checksum");
    Section sec{kind, Bytes(r), at};
    const std::size_t got = ZSTD_decompress(sec.raw.data(), sec.raw.size(), d + at + 32, z);
    if (ZSTD_isError(got) || got != r) wrong_read(kTarget, "accepted a section zstd does not decompress to its size");
    out.push_back(std::move(sec));
    at += 32 + z;
  }
  if (count == 0 || at != n) wrong_read(kTarget, "accepted with no sections or bytes after them");
  return out;
}

struct Reader {  // a payload; a read past its end is a wrong read (the reader accepted it)
  const Bytes& b;
  std::size_t pos = 0;
  const std::uint8_t* take(std::size_t n) {
    if (n > b.size() - pos) wrong_read(kTarget, "accepted a payload too short for its contents");
    pos += n;
    return b.data() + pos - n;
  }
  std::uint32_t u32() { return load<std::uint32_t>(take(4)); }
  std::uint64_t u64() { return load<std::uint64_t>(take(8)); }
  json text() {
    const std::uint32_t len = u32();
    const auto* p = take(len);
    return json::parse(p, p + len);  // a nlohmann exception here escapes: the reader parsed it
  }
};

bool same_bits(double a, double b) { return std::memcmp(&a, &b, 8) == 0; }
bool same_bits(float a, float b) { return float_bits(a) == float_bits(b); }

// The JSON value holds exactly this integer (no fraction, no wrap-around).
bool integer_is(const json& v, long long want) {
  if (v.is_number_unsigned()) return want >= 0 && v.get<std::uint64_t>() == static_cast<unsigned long long>(want);
  if (v.is_number_integer()) return v.get<std::int64_t>() == want;
  return false;
}
bool float_is(const json& v, float want) {
  if (!v.is_number()) return false;
  const double d = v.get<double>();
  return std::fabs(d) <= FLT_MAX && same_bits(static_cast<float>(d), want);
}
bool double_is(const json& v, double want) { return v.is_number() && same_bits(v.get<double>(), want); }

// The trace the reader returned against an independent decode of the bytes it read.
void check_layout(const std::uint8_t* d, std::size_t n, const trace::Trace& t) {
  const std::vector<Section> sections = split(d, n);
  std::size_t clouds = 0, jobs = 0;
  for (const Section& sec : sections) {
    Reader in{sec.raw};
    const std::string where = "section at byte " + std::to_string(sec.at) + ": ";
    if (sec.kind == 1) {
      const json m = in.text();
      if (!m.is_object() || !m.contains("meta") || !m.contains("total_seconds") || !m.contains("stages"))
        wrong_read(kTarget, where + "accepted metadata without meta, total_seconds or stages");
      if (m["meta"] != t.meta || m["meta"].dump() != t.meta.dump()) wrong_read(kTarget, where + "meta differs");
      if (!double_is(m["total_seconds"], t.total_seconds)) wrong_read(kTarget, where + "total_seconds differs");
      const json& st = m["stages"];
      if (!st.is_array() || st.size() != t.stages.size()) wrong_read(kTarget, where + "stage count differs");
      for (std::size_t i = 0; i < st.size(); ++i) {
        const trace::Stage& s = t.stages[i];
        if (!st[i].is_object() || st[i].value("name", json()) != s.name ||
            !double_is(st[i].value("seconds", json()), s.seconds) ||
            !double_is(st[i].value("kdtree_search_seconds", json()), s.kdtree_search_seconds) ||
            !double_is(st[i].value("kdtree_build_seconds", json()), s.kdtree_build_seconds))
          wrong_read(kTarget, where + "stage " + std::to_string(i) + " differs");
      }
    } else if (sec.kind == 2) {
      if (clouds >= t.clouds.size()) wrong_read(kTarget, where + "more cloud sections than clouds");
      const trace::Cloud& c = t.clouds[clouds++];
      const std::uint64_t hash = in.u64(), points = in.u64();
      if (hash != c.hash || points != c.points.size()) wrong_read(kTarget, where + "cloud hash or size differs");
      const std::uint8_t* p = in.take(points * 12);
      if (points && std::memcmp(p, c.points.data(), points * 12) != 0)
        wrong_read(kTarget, where + "cloud points differ");
    } else {
      if (jobs >= t.jobs.size()) wrong_read(kTarget, where + "more job sections than jobs");
      const trace::Job& j = t.jobs[jobs++];
      const json h = in.text();
      const auto str = [&](const char* key, const std::string& want) {
        if (!h.contains(key) || h[key] != want) wrong_read(kTarget, where + "job " + key + " differs");
      };
      const auto num = [&](const char* key, bool ok) {
        if (!h.contains(key) || !ok) wrong_read(kTarget, where + "job " + key + " differs");
      };
      if (!h.is_object()) wrong_read(kTarget, where + "job header is no object");
      str("stage", j.stage);
      str("backend", j.backend);
      str("mode", j.mode);
      str("tree", trace::hash_text(j.tree));
      str("queries", trace::hash_text(j.queries));
      num("iteration", integer_is(h.value("iteration", json()), j.iteration));
      num("tree_serial", integer_is(h.value("tree_serial", json()), j.tree_serial));
      num("top_height", integer_is(h.value("top_height", json()), j.top_height));
      num("k", integer_is(h.value("k", json()), j.k));
      num("max_nn", integer_is(h.value("max_nn", json()), j.max_nn));
      num("leader_capacity", integer_is(h.value("leader_capacity", json()), j.leader_capacity));
      num("leader_width", integer_is(h.value("leader_width", json()), j.leader_width));
      num("inject_kth", integer_is(h.value("inject_kth", json()), j.inject_kth));
      num("approximate", h.value("approximate", json()) == json(j.approximate));
      num("radius", float_is(h.value("radius", json()), j.radius));
      num("approx_thd", float_is(h.value("approx_thd", json()), j.approx_thd));
      num("shell_inner", float_is(h.value("shell_inner", json()), j.shell_inner));
      num("shell_outer", float_is(h.value("shell_outer", json()), j.shell_outer));
      num("search_seconds", double_is(h.value("search_seconds", json()), j.search_seconds));
      num("build_seconds", double_is(h.value("build_seconds", json()), j.build_seconds));
      const std::uint64_t nq = in.u64();
      if (nq != j.counts.size()) wrong_read(kTarget, where + "query count differs");
      std::uint64_t total = 0;
      for (std::uint64_t q = 0; q < nq; ++q) {
        const std::uint32_t c = in.u32();
        if (c != j.counts[q]) wrong_read(kTarget, where + "count " + std::to_string(q) + " differs");
        total += c;
      }
      if (total != j.indices.size()) wrong_read(kTarget, where + "index count differs");
      std::uint64_t prev = 0;  // wraps like two's complement; a valid file never does
      for (std::uint64_t i = 0; i < total; ++i) {
        std::uint64_t v = 0;
        for (int shift = 0;; shift += 7) {
          if (shift > 63) wrong_read(kTarget, where + "accepted a varint of more than 10 bytes");
          const std::uint8_t c = *in.take(1);
          if (shift == 63 && c > 1) wrong_read(kTarget, where + "accepted a varint beyond 64 bits");
          v |= std::uint64_t{c & 0x7fu} << shift;
          if (!(c & 0x80)) break;
        }
        prev += (v >> 1) ^ (~(v & 1) + 1);  // zig-zag: 2n -> n, 2n+1 -> -n-1
        if (prev != j.indices[i]) wrong_read(kTarget, where + "index " + std::to_string(i) + " differs");
      }
    }
    if (in.pos != sec.raw.size()) wrong_read(kTarget, where + "accepted unread payload bytes");
  }
  if (clouds != t.clouds.size() || jobs != t.jobs.size()) wrong_read(kTarget, "section counts differ");
}

// ---------------------------------------------------------------------------------------------
// Equality and the reader's promises.

std::string difference(const trace::Trace& a, const trace::Trace& b) {
  if (a.meta != b.meta || a.meta.dump() != b.meta.dump()) return "meta differs";
  if (!same_bits(a.total_seconds, b.total_seconds)) return "total_seconds differs";
  if (a.stages.size() != b.stages.size()) return "stage count differs";
  for (std::size_t i = 0; i < a.stages.size(); ++i) {
    const trace::Stage &x = a.stages[i], &y = b.stages[i];
    if (x.name != y.name || !same_bits(x.seconds, y.seconds) ||
        !same_bits(x.kdtree_search_seconds, y.kdtree_search_seconds) ||
        !same_bits(x.kdtree_build_seconds, y.kdtree_build_seconds))
      return "stage " + std::to_string(i) + " differs";
  }
  if (a.clouds.size() != b.clouds.size()) return "cloud count differs";
  for (std::size_t i = 0; i < a.clouds.size(); ++i) {
    const trace::Cloud &x = a.clouds[i], &y = b.clouds[i];
    if (x.hash != y.hash || x.points.size() != y.points.size() ||
        (!x.points.empty() && std::memcmp(x.points.data(), y.points.data(), x.points.size() * 12) != 0))
      return "cloud " + std::to_string(i) + " differs";
  }
  if (a.jobs.size() != b.jobs.size()) return "job count differs";
  for (std::size_t i = 0; i < a.jobs.size(); ++i) {
    const trace::Job &x = a.jobs[i], &y = b.jobs[i];
    const std::string w = "job " + std::to_string(i) + " ";
    if (x.stage != y.stage || x.iteration != y.iteration || x.backend != y.backend)
      return w + "stage/iteration/backend";
    if (x.tree != y.tree || x.queries != y.queries || x.tree_serial != y.tree_serial || x.top_height != y.top_height)
      return w + "tree/queries/serial/top_height";
    if (x.mode != y.mode || x.k != y.k || !same_bits(x.radius, y.radius) || x.max_nn != y.max_nn)
      return w + "mode/k/radius/max_nn";
    if (x.approximate != y.approximate || !same_bits(x.approx_thd, y.approx_thd) ||
        x.leader_capacity != y.leader_capacity || x.leader_width != y.leader_width)
      return w + "approximate settings";
    if (x.inject_kth != y.inject_kth || !same_bits(x.shell_inner, y.shell_inner) ||
        !same_bits(x.shell_outer, y.shell_outer))
      return w + "injection";
    if (!same_bits(x.search_seconds, y.search_seconds) || !same_bits(x.build_seconds, y.build_seconds))
      return w + "seconds";
    if (x.counts != y.counts) return w + "counts";
    if (x.indices != y.indices) return w + "indices";
  }
  return "";
}

const trace::Cloud* find_cloud(const trace::Trace& t, std::uint64_t hash) {
  const trace::Cloud* found = nullptr;
  for (const trace::Cloud& c : t.clouds)
    if (c.hash == hash) {
      if (found) wrong_read(kTarget, "cloud " + trace::hash_text(hash) + " accepted twice");
      found = &c;
    }
  return found;
}

void check_promises(const trace::Trace& t) {
  if (!t.meta.is_object()) wrong_read(kTarget, "a metadata 'meta' that is no object accepted");
  for (const trace::Cloud& c : t.clouds) {
    find_cloud(t, c.hash);
    if (trace::content_hash(c.points) != c.hash) wrong_read(kTarget, "a cloud's points do not match its hash");
    for (const tigris::Point3& p : c.points)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) wrong_read(kTarget, "a non-finite point");
  }
  for (std::size_t n = 0; n < t.jobs.size(); ++n) {
    const trace::Job& j = t.jobs[n];
    const std::string w = "job " + std::to_string(n) + ": ";
    const trace::Cloud *tree = find_cloud(t, j.tree), *queries = find_cloud(t, j.queries);
    if (!tree || !queries) wrong_read(kTarget, w + "names a missing cloud");
    if (j.mode != "nn" && j.mode != "knn" && j.mode != "radius") wrong_read(kTarget, w + "mode " + j.mode);
    if (j.iteration < -1 || j.tree_serial < 0 || j.k < 1 || j.top_height < 0 || j.top_height > 30 ||
        j.leader_capacity < 0 || j.leader_width < 0 || j.inject_kth < 1 || !std::isfinite(j.radius) ||
        !std::isfinite(j.approx_thd) || !std::isfinite(j.shell_inner) || !std::isfinite(j.shell_outer) ||
        (j.mode == "radius" && !(j.radius > 0.0f)) || !std::isfinite(j.search_seconds) ||
        !std::isfinite(j.build_seconds) || j.search_seconds < 0 || j.build_seconds < 0 || j.stage.empty() ||
        (j.backend != "flann" && j.backend != "exact" && j.backend != "approx"))
      wrong_read(kTarget, w + "parameters out of range accepted");
    if (j.counts.size() != queries->points.size()) wrong_read(kTarget, w + "counts do not match the queries");
    std::uint64_t total = 0;
    for (std::uint32_t c : j.counts) total += c;
    if (total != j.indices.size()) wrong_read(kTarget, w + "counts do not add up to the indices");
    for (std::uint32_t i : j.indices)
      if (i >= tree->points.size()) wrong_read(kTarget, w + "an index beyond its tree cloud");
    const trace::JobResults r = trace::results(t, j);
    if (r.index != j.indices || r.dist2.size() != j.indices.size() || r.offset.size() != j.counts.size() + 1 ||
        r.offset[0] != 0)
      wrong_read(kTarget, w + "results() shape");
    std::size_t at = 0;
    for (std::size_t q = 0; q < j.counts.size(); ++q) {
      for (std::uint32_t k = 0; k < j.counts[q]; ++k, ++at)
        if (!same_bits(r.dist2[at], tigris::dist2(queries->points[q], tree->points[j.indices[at]])))
          wrong_read(kTarget, w + "dist2 of result " + std::to_string(at) + " is not the contract's");
      if (r.offset[q + 1] != at) wrong_read(kTarget, w + "results() offsets");
    }
  }
}

trace::Trace decode(const Bytes& b) { return trace::decode(b.data(), b.size(), kLabel); }

// An accepted trace (`d`, `n` its bytes): layout, promises, round trip.
void check_accepted(const trace::Trace& t, const std::uint8_t* d, std::size_t n) {
  check_layout(d, n, t);
  check_promises(t);
  const Bytes again = trace::encode(t);
  trace::Trace back;
  try {
    back = decode(again);
  } catch (const tigris::InputError& e) {
    wrong_read(kTarget, std::string("its own encoding rejected: ") + e.what());
  }
  const std::string diff = difference(t, back);
  if (!diff.empty()) wrong_read(kTarget, "encode and decode: " + diff);
  if (trace::encode(back) != again) wrong_read(kTarget, "encoding the decoded trace gives other bytes");
}

// A damaged file: a clean error or (when `same` is given) that trace exactly, or (when not) any
// trace that passes check_accepted.
void check_damaged(const Bytes& b, const trace::Trace* same, const std::string& what) {
  trace::Trace t;
  try {
    t = decode(b);
  } catch (const tigris::InputError& e) {
    const std::string m = e.what();
    if (m.compare(0, kLabel.size() + 7, kLabel + ": byte ") != 0)
      wrong_read(kTarget, what + ": error without the byte: " + m);
    if (b.size() >= 40 && std::memcmp(b.data(), "TIGRISWT", 8) == 0 && load<std::uint32_t>(b.data() + 8) > 1 &&
        m.find(": byte 8: trace format version ") == std::string::npos)
      wrong_read(kTarget, what + ": a newer version not refused as such: " + m);
    return;
  }
  if (same) {
    const std::string diff = difference(*same, t);
    if (!diff.empty()) wrong_read(kTarget, what + ": accepted, read differently: " + diff);
  }
  check_accepted(t, b.data(), b.size());
}

// ---------------------------------------------------------------------------------------------
// The generator.

float any_float(ByteSource& s) {
  switch (s.range(0, 7)) {
    case 0: return 0.0f;
    case 1: return -0.0f;
    case 2: {  // denormal
      std::uint32_t b = static_cast<std::uint32_t>(s.range(1, 0x007fffff)) | (s.flag() ? 0x80000000u : 0u);
      float f;
      std::memcpy(&f, &b, 4);
      return f;
    }
    case 3: return static_cast<float>(static_cast<int>(s.range(0, 200)) - 100) * 0.25f;
    case 4: {
      const float v[] = {FLT_MAX, -FLT_MAX, FLT_MIN, -FLT_MIN, std::numeric_limits<float>::denorm_min(), 1e-30f, 3e30f};
      return v[s.range(0, 6)];
    }
    default: {
      std::uint32_t b = static_cast<std::uint32_t>(s.bits(32));
      if ((b & 0x7f800000u) == 0x7f800000u) b &= 0xbfffffffu;  // inf/NaN -> finite
      float f;
      std::memcpy(&f, &b, 4);
      return f;
    }
  }
}

double any_double(ByteSource& s) {
  switch (s.range(0, 5)) {
    case 0: return 0.0;
    case 1: return -0.0;
    case 2: return std::numeric_limits<double>::denorm_min() * static_cast<double>(s.range(1, 1000));
    case 3: return static_cast<double>(s.range(0, 100000)) * 1e-6;
    default: {
      std::uint64_t b = s.bits(64);
      if ((b & 0x7ff0000000000000ull) == 0x7ff0000000000000ull) b &= ~(std::uint64_t{1} << 62);
      double d;
      std::memcpy(&d, &b, 8);
      return d;
    }
  }
}

// What a recorder writes for a time: any finite double that is not negative.
double any_seconds(ByteSource& s) { return std::fabs(any_double(s)); }

int any_int(ByteSource& s, int lo, int hi) {
  const std::uint64_t span = static_cast<std::uint64_t>(static_cast<std::int64_t>(hi) - lo);
  switch (s.range(0, 3)) {
    case 0: return lo;
    case 1: return hi;
    case 2: return static_cast<int>(lo + static_cast<std::int64_t>(s.range(0, std::min<std::uint64_t>(span, 40))));
    default: return static_cast<int>(lo + static_cast<std::int64_t>(s.range(0, span)));
  }
}

// Valid UTF-8 (nlohmann's dump refuses anything else): ASCII, control bytes, 2-4 byte sequences.
std::string any_text(ByteSource& s, const std::vector<std::string>& names) {
  if (!names.empty() && s.chance(60)) return names[s.range(0, names.size() - 1)];
  static const char* const pieces[] = {"a",
                                       "Z",
                                       "_",
                                       " ",
                                       "0",
                                       "\n",
                                       "\t",
                                       "\x01",
                                       "\x7f",
                                       "\"",
                                       "\\",
                                       "/",
                                       "\xc3\xa9",
                                       "\xe2\x82\xac",
                                       "\xf0\x9f\x98\x80",
                                       "icp",
                                       "normals"};
  std::string out;
  for (std::size_t n = s.range(0, 8); n > 0; --n) out += pieces[s.range(0, sizeof pieces / sizeof *pieces - 1)];
  return out;
}

json any_json(ByteSource& s, int depth) {
  switch (s.range(0, depth > 0 ? 8 : 6)) {
    case 0: return nullptr;
    case 1: return s.flag();
    case 2: return static_cast<std::int64_t>(s.bits(64));
    case 3: return s.bits(64);
    case 4: return any_double(s);
    case 5: return static_cast<double>(any_float(s));
    case 6: return any_text(s, {});
    case 7: {
      json a = json::array();
      for (std::size_t n = s.range(0, 3); n > 0; --n) a.push_back(any_json(s, depth - 1));
      return a;
    }
    default: {
      json o = json::object();
      for (std::size_t n = s.range(0, 3); n > 0; --n) o[any_text(s, {"x", "y", "points", ""})] = any_json(s, depth - 1);
      return o;
    }
  }
}

const std::vector<std::string> kStages = {"outlier_removal", "normals", "keypoints", "descriptors", "icp"};
const char* const kBackends[] = {"flann", "exact", "approx"};

// A stage's name: any text but the empty one (a recorder names every stage).
std::string any_name(ByteSource& s, const std::vector<std::string>& names) {
  std::string t = any_text(s, names);
  return t.empty() ? names.back() : t;
}

trace::Trace generate(ByteSource& s) {
  trace::Trace t;
  t.meta = {{"tool", "tigris"}, {"command_line", any_text(s, {"tigris register a.pcd b.pcd --record-trace t"})}};
  for (std::size_t n = s.range(0, 3); n > 0; --n)
    t.meta[any_text(s, {"preset", "search", "transform"})] = any_json(s, 3);
  for (std::size_t n = s.range(0, 4); n > 0; --n)
    t.stages.push_back({any_name(s, kStages), any_seconds(s), any_seconds(s), any_seconds(s)});
  t.total_seconds = any_seconds(s);

  for (std::size_t n = s.range(1, 4); n > 0; --n) {
    tigris::PointCloud c;
    if (!s.chance(97)) {  // a large cloud (index deltas of several varint bytes), a short pattern repeated
      tigris::PointCloud base(s.range(1, 4));
      for (auto& p : base) p = {any_float(s), any_float(s), any_float(s)};
      // now and then 90,000-120,000 (1 MiB past the reader's expansion bound: encode pads it)
      c.resize(s.chance(90) ? s.range(1000, 20000) : s.range(90000, 120000));
      for (std::size_t i = 0; i < c.size(); ++i) c[i] = base[i % base.size()];
      c.back().x = static_cast<float>(c.size());
    } else {
      c.resize(s.range(0, 8));
      for (auto& p : c) p = {any_float(s), any_float(s), any_float(s)};
    }
    t.add_cloud(c);  // an equal cloud twice stays one
  }
  for (std::size_t n = s.range(0, 5); n > 0; --n) {
    trace::Job j;
    const trace::Cloud& tree = t.clouds[s.range(0, t.clouds.size() - 1)];
    const trace::Cloud& queries = t.clouds[s.range(0, t.clouds.size() - 1)];
    j.tree = tree.hash;
    j.queries = queries.hash;
    j.stage = any_name(s, kStages);
    j.iteration = s.chance(50) ? -1 : any_int(s, -1, INT_MAX);
    j.backend = kBackends[s.range(0, 2)];
    j.tree_serial = any_int(s, 0, INT_MAX);
    j.top_height = any_int(s, 0, 30);
    const int mode = static_cast<int>(s.range(0, 2));
    j.mode = mode == 0 ? "nn" : mode == 1 ? "knn" : "radius";
    j.k = mode == 0 && s.chance(80) ? 1 : any_int(s, 1, INT_MAX);
    j.radius = any_float(s);
    if (mode == 2) {
      j.radius = std::fabs(j.radius);
      if (!(j.radius > 0.0f)) j.radius = 0.75f;
    }
    j.max_nn = static_cast<std::uint32_t>(s.chance(50) ? 0 : s.bits(32));
    j.approximate = s.flag();
    j.approx_thd = any_float(s);
    j.leader_capacity = any_int(s, 0, INT_MAX);
    j.leader_width = any_int(s, 0, INT_MAX);
    j.inject_kth = s.chance(70) ? 1 : any_int(s, 1, INT_MAX);
    if (s.chance(30)) {
      j.shell_inner = any_float(s);
      j.shell_outer = any_float(s);
    }
    j.search_seconds = any_seconds(s);
    j.build_seconds = any_seconds(s);
    // Results: per query, indices into the tree that repeat, step, jump to either end or anywhere.
    const std::uint64_t points = tree.points.size();
    std::uint64_t prev = 0;
    for (std::size_t q = 0; q < queries.points.size(); ++q) {
      const std::uint32_t count =
          points == 0 ? 0 : static_cast<std::uint32_t>(s.chance(5) ? s.range(0, 300) : s.range(0, 5));
      j.counts.push_back(count);
      for (std::uint32_t k = 0; k < count; ++k) {
        switch (s.range(0, 5)) {
          case 0: break;  // the same again
          case 1: prev = std::min(points - 1, prev + s.range(1, 3)); break;
          case 2: prev -= std::min(prev, static_cast<std::uint64_t>(s.range(1, 3))); break;
          case 3: prev = s.flag() ? 0 : points - 1; break;
          default: prev = s.range(0, points - 1); break;
        }
        j.indices.push_back(static_cast<std::uint32_t>(prev));
      }
    }
    t.jobs.push_back(std::move(j));
  }
  return t;
}

// ---------------------------------------------------------------------------------------------
// Damage.

// A file from sections, sizes and checksums right unless told otherwise; `frames`: 0 one zstd
// frame with its size, 1 without it, 2 split in two frames, 3 after a skippable frame.
struct Seal {
  std::uint32_t version = 1, header_bytes = 40;
  std::int64_t count_delta = 0;
  int frames = 0;
  std::size_t odd_section = SIZE_MAX;  // this section gets the oddities below
  std::uint32_t reserved = 0;
  std::int64_t raw_delta = 0;
};

Bytes compress(const std::uint8_t* p, std::size_t n, bool with_size) {
  ZSTD_CCtx* cx = ZSTD_createCCtx();
  ZSTD_CCtx_setParameter(cx, ZSTD_c_compressionLevel, 1);
  ZSTD_CCtx_setParameter(cx, ZSTD_c_contentSizeFlag, with_size ? 1 : 0);
  Bytes z(ZSTD_compressBound(n));
  std::size_t got;
  if (with_size) {
    got = ZSTD_compress2(cx, z.data(), z.size(), p, n);
  } else {  // streamed: the frame does not say its size
    ZSTD_outBuffer out{z.data(), z.size(), 0};
    ZSTD_inBuffer in{p, n, 0};
    do got = ZSTD_compressStream2(cx, &out, &in, ZSTD_e_end);
    while (got != 0 && !ZSTD_isError(got));
    got = ZSTD_isError(got) ? got : out.pos;
  }
  ZSTD_freeCCtx(cx);
  if (ZSTD_isError(got)) wrong_read(kTarget, std::string("fuzz target's zstd: ") + ZSTD_getErrorName(got));
  z.resize(got);
  return z;
}

Bytes seal(const std::vector<Section>& sections, const Seal& o) {
  Bytes f;
  f.insert(f.end(), {'T', 'I', 'G', 'R', 'I', 'S', 'W', 'T'});
  put<std::uint32_t>(f, o.version);
  put<std::uint32_t>(f, o.header_bytes);
  put<std::uint64_t>(f, sections.size() + static_cast<std::uint64_t>(o.count_delta));  // wraps
  put<std::uint64_t>(f, 0);
  put<std::uint64_t>(f, 0);
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const Bytes& raw = sections[i].raw;
    const bool odd = i == o.odd_section;
    Bytes z;
    const int frames = odd ? o.frames : 0;
    if (frames == 2) {
      z = compress(raw.data(), raw.size() / 2, true);
      const Bytes rest = compress(raw.data() + raw.size() / 2, raw.size() - raw.size() / 2, true);
      z.insert(z.end(), rest.begin(), rest.end());
    } else if (frames == 3) {
      z = {0x50, 0x2a, 0x4d, 0x18, 3, 0, 0, 0, 'x', 'y', 'z'};  // skippable frame, 3 bytes
      const Bytes rest = compress(raw.data(), raw.size(), true);
      z.insert(z.end(), rest.begin(), rest.end());
    } else {
      z = compress(raw.data(), raw.size(), frames != 1);
    }
    put<std::uint32_t>(f, sections[i].kind);
    put<std::uint32_t>(f, odd ? o.reserved : 0);
    put<std::uint64_t>(f, z.size());
    put<std::uint64_t>(f, raw.size() + static_cast<std::uint64_t>(odd ? o.raw_delta : 0));  // wraps
    put<std::uint64_t>(f, fnv1a(z.data(), z.size()));
    f.insert(f.end(), z.begin(), z.end());
  }
  store<std::uint64_t>(f, 24, f.size());
  store<std::uint64_t>(f, 32, fnv1a(f.data(), 32));
  return f;
}

std::uint64_t interesting(ByteSource& s) {
  static const std::uint64_t v[] = {0,
                                    1,
                                    2,
                                    7,
                                    0x7f,
                                    0x80,
                                    0xff,
                                    0x7fffffff,
                                    0x80000000u,
                                    0xffffffffu,
                                    0x100000000ull,
                                    0x7fffffffffffffffull,
                                    0x8000000000000000ull,
                                    ~0ull};
  return s.chance(70) ? v[s.range(0, sizeof v / sizeof *v - 1)] : s.bits(64);
}

// The byte offsets a damage most likely breaks: the header's fields and the section headers.
std::size_t pick_offset(ByteSource& s, const Bytes& b, const std::vector<Section>& sections) {
  if (b.empty()) return 0;
  switch (s.range(0, 3)) {
    case 0: return s.range(0, std::min<std::size_t>(39, b.size() - 1));
    case 1: {
      const Section& sec = sections[s.range(0, sections.size() - 1)];
      return std::min(b.size() - 1, sec.at + s.range(0, 31));
    }
    default: return s.range(0, b.size() - 1);
  }
}

void damage_bytes(ByteSource& s, const Bytes& file, const std::vector<Section>& sections, const trace::Trace& t) {
  Bytes b = file;
  for (std::size_t n = s.range(1, 3); n > 0; --n) {
    const std::size_t at = pick_offset(s, b, sections);
    switch (s.range(0, 5)) {
      case 0:
      case 1:
        if (at < b.size()) b[at] ^= static_cast<std::uint8_t>(s.range(1, 255));
        break;
      case 2: b.resize(std::min(b.size(), at)); break;
      case 3:
        for (std::size_t k = s.range(1, 8); k > 0; --k) b.push_back(s.byte());
        break;
      case 4: b.insert(b.begin() + static_cast<std::ptrdiff_t>(std::min(at, b.size())), s.range(1, 8), s.byte()); break;
      default: {
        const std::size_t from = std::min(at, b.size()), len = std::min<std::size_t>(b.size() - from, s.range(1, 16));
        b.erase(b.begin() + static_cast<std::ptrdiff_t>(from), b.begin() + static_cast<std::ptrdiff_t>(from + len));
        break;
      }
    }
  }
  check_damaged(b, &t, "bytes damaged");
}

const char* const kJobKeys[] = {
    "stage",        "iteration",  "backend",     "tree",        "queries",        "tree_serial",  "top_height",
    "mode",         "k",          "radius",      "max_nn",      "approximate",    "approx_thd",   "leader_capacity",
    "leader_width", "inject_kth", "shell_inner", "shell_outer", "search_seconds", "build_seconds"};
const char* const kMetaKeys[] = {"meta", "total_seconds", "stages"};

// A JSON text in place of a value: every kind, numbers at and beyond the fields' ranges.
std::string odd_json(ByteSource& s, const json& was) {
  static const char* const v[] = {
      "1.5",
      "-1",
      "0",
      "-0.0",
      "1e300",
      "-1e300",
      "1e-300",
      "3.4028235677973366e38",
      "3.4028236e38",
      "1e39",
      "2147483647",
      "2147483648",
      "-2147483648",
      "-2147483649",
      "4294967295",
      "4294967296",
      "4294967297",
      "9223372036854775807",
      "9223372036854775808",
      "18446744073709551615",
      "18446744073709551616",
      "-9223372036854775808",
      "1e20",
      "31",
      "30",
      "true",
      "false",
      "null",
      "\"\"",
      "\"nn\"",
      "\"knn\"",
      "\"radius\"",
      "\"NN\"",
      "\"0123456789abcdef\"",
      "\"0123456789ABCDEF\"",
      "\"0123456789abcde\"",
      "\"-123456789abcdef\"",
      "\"0x23456789abcdef\"",
      "\" 123456789abcdef\"",
      "[]",
      "{}",
      "[1]",
      "{\"name\":\"x\",\"seconds\":1,\"kdtree_search_seconds\":0,\"kdtree_build_seconds\":0}",
      "[{\"name\":\"x\",\"seconds\":1,\"kdtree_search_seconds\":0,\"kdtree_build_seconds\":0}]",
      "[{\"name\":\"x\",\"seconds\":1e999,\"kdtree_search_seconds\":0,\"kdtree_build_seconds\":0}]"};
  switch (s.range(0, 5)) {
    case 0: {  // deeply nested
      const std::size_t depth = s.chance(80) ? s.range(1, 300) : s.range(300, 100000);
      const bool obj = s.flag();
      std::string out;
      for (std::size_t i = 0; i < depth; ++i) out += obj ? "{\"a\":" : "[";
      out += "0";
      for (std::size_t i = 0; i < depth; ++i) out += obj ? "}" : "]";
      return out;
    }
    case 1:  // the old value's number, one off
      if (was.is_number_integer()) return std::to_string(was.get<std::int64_t>() + (s.flag() ? 1 : -1));
      return was.dump();
    case 2: return json(any_double(s)).dump();
    case 3: return any_json(s, 2).dump();
    default: return v[s.range(0, sizeof v / sizeof *v - 1)];
  }
}

// Edits a section's JSON text (metadata or job header), keeping the payload around it.
bool edit_json(ByteSource& s, Bytes& raw) {
  if (raw.size() < 4) return false;
  const std::uint32_t len = load<std::uint32_t>(raw.data());
  if (len > raw.size() - 4) return false;
  json h = json::parse(raw.begin() + 4, raw.begin() + 4 + len);
  if (!h.is_object()) return false;
  const bool job = h.contains("mode");
  const std::string key = job ? kJobKeys[s.range(0, sizeof kJobKeys / sizeof *kJobKeys - 1)]
                              : kMetaKeys[s.range(0, sizeof kMetaKeys / sizeof *kMetaKeys - 1)];
  std::string text;
  if (s.chance(10)) {
    h.erase(key);
    text = h.dump();
  } else {
    const json was = h.value(key, json());
    h[key] = "\x01placeholder";
    text = h.dump();
    const std::string mark = json("\x01placeholder").dump();
    text.replace(text.find(mark), mark.size(), odd_json(s, was));
  }
  if (s.chance(5)) text += s.flag() ? " " : "x";
  Bytes out;
  put<std::uint32_t>(out, static_cast<std::uint32_t>(text.size()));
  out.insert(out.end(), text.begin(), text.end());
  out.insert(out.end(), raw.begin() + 4 + len, raw.end());
  raw = std::move(out);
  return true;
}

void damage_payload(ByteSource& s, std::vector<Section> sections, const std::vector<trace::Cloud>& clouds) {
  Section& sec = sections[s.range(0, sections.size() - 1)];
  Bytes& raw = sec.raw;
  const std::size_t at = raw.empty() ? 0 : s.range(0, raw.size() - 1);
  switch (s.range(0, 9)) {
    case 0:
      if (!raw.empty()) raw[at] ^= static_cast<std::uint8_t>(s.range(1, 255));
      break;
    case 1: {  // a number over 1, 4 or 8 bytes
      const std::uint64_t v = interesting(s);
      const std::size_t width = std::size_t{1} << s.range(0, 3);
      for (std::size_t k = 0; k < width && at + k < raw.size(); ++k)
        raw[at + k] = static_cast<std::uint8_t>(v >> (8 * k));
      break;
    }
    case 2: raw.resize(at); break;
    case 3:
      for (std::size_t k = s.range(1, 10); k > 0; --k) raw.push_back(s.byte());
      break;
    case 4: {  // a long or huge varint in place of the bytes there
      Bytes v;
      const std::size_t len = s.range(1, 12);
      for (std::size_t k = 0; k + 1 < len; ++k) v.push_back(static_cast<std::uint8_t>(0x80 | s.byte()));
      v.push_back(static_cast<std::uint8_t>(s.byte() & 0x7f));
      raw.erase(raw.begin() + static_cast<std::ptrdiff_t>(std::min(at, raw.size())),
                raw.begin() + static_cast<std::ptrdiff_t>(std::min(at + s.range(0, 3), raw.size())));
      raw.insert(raw.begin() + static_cast<std::ptrdiff_t>(std::min(at, raw.size())), v.begin(), v.end());
      break;
    }
    case 5:
    case 6:
      if (sec.kind != 2 && edit_json(s, raw)) break;
      [[fallthrough]];
    case 7:  // a cloud: a point made non-finite or moved, the hash made right or not
      if (sec.kind == 2 && raw.size() >= 16) {
        const std::uint64_t n = load<std::uint64_t>(raw.data() + 8);
        if (n > 0 && raw.size() >= 16 + n * 12) {
          const std::size_t f = 16 + 4 * s.range(0, n * 3 - 1);
          const std::uint32_t v = s.chance(50) ? 0x7f800000u | static_cast<std::uint32_t>(s.range(0, 1))
                                               : static_cast<std::uint32_t>(s.bits(32));
          std::memcpy(raw.data() + f, &v, 4);
        }
        if (s.chance(80)) {
          tigris::PointCloud p((raw.size() - 16) / 12);
          if (!p.empty()) std::memcpy(p.data(), raw.data() + 16, p.size() * 12);
          store<std::uint64_t>(raw, 0, trace::content_hash(p));
        }
        break;
      }
      [[fallthrough]];
    case 8:  // a job: its query count or a count one off; or a cloud's size
      if (raw.size() >= 16) {
        const std::uint32_t len = load<std::uint32_t>(raw.data());
        const std::size_t counts = sec.kind == 3 ? 4 + std::size_t{len} : 8;
        if (counts <= raw.size() - 8) {
          const std::uint64_t nq = load<std::uint64_t>(raw.data() + counts);
          if (s.flag() || nq == 0 || sec.kind == 2) {
            store<std::uint64_t>(raw, counts, nq + (s.flag() ? 1 : -1));
          } else {
            const std::size_t c = counts + 8 + 4 * s.range(0, nq - 1);
            if (c + 4 <= raw.size())
              store<std::uint32_t>(raw, c, load<std::uint32_t>(raw.data() + c) + (s.flag() ? 1 : -1));
          }
        }
      }
      break;
    default:  // another cloud section: one the jobs do not name, or a cloud stored twice
      if (!clouds.empty()) {
        tigris::PointCloud c = clouds[s.range(0, clouds.size() - 1)].points;
        if (s.flag()) c.push_back({any_float(s), any_float(s), any_float(s)});
        Section extra{2, {}, 0};
        put<std::uint64_t>(extra.raw, trace::content_hash(c));
        put<std::uint64_t>(extra.raw, c.size());
        const auto* p = reinterpret_cast<const std::uint8_t*>(c.data());
        if (!c.empty()) extra.raw.insert(extra.raw.end(), p, p + c.size() * 12);
        sections.insert(sections.begin() + static_cast<std::ptrdiff_t>(s.range(0, sections.size())), std::move(extra));
      }
      break;
  }
  Seal o;
  if (s.chance(20)) {
    o.odd_section = s.range(0, sections.size() - 1);
    o.frames = static_cast<int>(s.range(1, 3));
  }
  check_damaged(seal(sections, o), nullptr, "payload edited, resealed");
}

void damage_structure(ByteSource& s, std::vector<Section> sections) {
  Seal o;
  const std::size_t a = s.range(0, sections.size() - 1), b = s.range(0, sections.size() - 1);
  switch (s.range(0, 8)) {
    case 0: std::swap(sections[a], sections[b]); break;
    case 1: sections.insert(sections.begin() + static_cast<std::ptrdiff_t>(b), sections[a]); break;
    case 2: sections.erase(sections.begin() + static_cast<std::ptrdiff_t>(a)); break;
    case 3: sections[a].kind = static_cast<std::uint32_t>(s.chance(50) ? s.range(1, 3) : interesting(s)); break;
    case 4: o.version = static_cast<std::uint32_t>(s.chance(70) ? s.range(0, 3) : interesting(s)); break;
    case 5: o.header_bytes = static_cast<std::uint32_t>(s.chance(70) ? s.range(32, 48) : interesting(s)); break;
    case 6: o.count_delta = s.chance(70) ? (s.flag() ? 1 : -1) : static_cast<std::int64_t>(interesting(s)); break;
    case 7:
      o.odd_section = a;
      o.reserved = static_cast<std::uint32_t>(s.range(1, 255));
      break;
    default:
      o.odd_section = a;
      o.frames = static_cast<int>(s.range(0, 3));
      o.raw_delta = s.chance(50) ? 0 : (s.flag() ? 1 : -1);
      break;
  }
  check_damaged(seal(sections, o), nullptr, "sections rearranged, resealed");
}

void check_generated(const std::uint8_t* data, std::size_t size) {
  ByteSource s(data + 1, size - 1);
  const trace::Trace t = generate(s);
  const Bytes file = trace::encode(t);
  trace::Trace back;
  try {
    back = decode(file);
  } catch (const tigris::InputError& e) {
    wrong_read(kTarget, std::string("a written trace rejected: ") + e.what());
  }
  const std::string diff = difference(t, back);
  if (!diff.empty()) wrong_read(kTarget, "written and read back: " + diff);
  check_accepted(back, file.data(), file.size());

  const std::vector<Section> sections = split(file.data(), file.size());
  for (std::size_t n = s.range(1, 4); n > 0 && s.remaining() > 0; --n) {
    switch (s.range(0, 2)) {
      case 0: damage_bytes(s, file, sections, t); break;
      case 1: damage_payload(s, sections, t.clouds); break;
      default: damage_structure(s, sections); break;
    }
  }
}

void check_raw(const std::uint8_t* data, std::size_t size) {
  trace::Trace t;
  try {
    t = trace::decode(data, size, kLabel);
  } catch (const tigris::InputError& e) {
    if (!names_source(e.what(), kLabel)) wrong_read(kTarget, std::string("error without the file name: ") + e.what());
    return;
  }
  check_accepted(t, data, size);
}

}  // namespace

extern "C" int TIGRIS_FUZZ_ENTRY(const std::uint8_t* data, std::size_t size) {
  if (size > 0 && data[0] == 0)
    check_generated(data, size);
  else
    check_raw(data, size);
  return 0;
}
