// Workload traces (traces/workload_trace.hpp, registration/trace_recorder.hpp): a
// registration of the (thinned) synthetic pair recorded at test time; every stage's searches in
// its jobs; recorded results equal the golden model's; recording changes nothing; the file reads
// back equal; truncated, corrupt, foreign and newer-version files are refused naming the byte.
#include <zstd.h>

#include <algorithm>
#include <catch2/catch.hpp>

#include <cstring>
#include <map>
#include <set>

#include "registration/pipeline.hpp"
#include "traces/workload_trace.hpp"
#include "workloads/synthetic.hpp"

using namespace tigris;
using namespace tigris::registration;

namespace {

struct Recorded {
  RegistrationResult plain, recorded;
  trace::Trace trace;
};

// DP4 (or `preset`) on the synthetic pair thinned to 900 azimuth steps, with and without a recorder.
const Recorded& recorded(const std::string& preset_name = "dp4", const std::string& backend = "exact") {
  static std::map<std::string, Recorded> cache;
  const std::string key = preset_name + "/" + backend;
  if (auto it = cache.find(key); it != cache.end()) return it->second;
  SyntheticConfig sc;
  sc.azimuth_steps = 900;
  const SyntheticPair p = make_synthetic_pair(sc);
  PipelineConfig c = preset(preset_name);
  c.search.backend = parse_backend(backend);
  Recorded r;
  r.plain = register_clouds(p.frame1, p.frame0, c);
  PipelineHooks hooks;
  hooks.recorder = std::make_shared<TraceRecorder>();
  r.recorded = register_clouds(p.frame1, p.frame0, c, hooks);
  r.trace = hooks.recorder->finish();
  r.trace.meta = {{"test", key}};
  r.trace.total_seconds = r.recorded.total_seconds;
  for (const auto& s : r.recorded.stages)
    r.trace.stages.push_back({s.name, s.seconds, s.kdtree.search_seconds, s.kdtree.build_seconds});
  return cache.emplace(key, std::move(r)).first->second;
}

bool same_job(const trace::Job& a, const trace::Job& b) {
  return a.stage == b.stage && a.iteration == b.iteration && a.backend == b.backend && a.tree == b.tree &&
         a.queries == b.queries && a.tree_serial == b.tree_serial && a.top_height == b.top_height && a.mode == b.mode &&
         a.k == b.k && a.radius == b.radius && a.max_nn == b.max_nn && a.approximate == b.approximate &&
         a.approx_thd == b.approx_thd && a.leader_capacity == b.leader_capacity && a.leader_width == b.leader_width &&
         a.inject_kth == b.inject_kth && a.shell_inner == b.shell_inner && a.shell_outer == b.shell_outer &&
         a.search_seconds == b.search_seconds && a.build_seconds == b.build_seconds && a.counts == b.counts &&
         a.indices == b.indices;
}

std::string error_of(const std::vector<std::uint8_t>& bytes) {
  try {
    trace::decode(bytes.data(), bytes.size(), "t.trace");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("trace: a recorded registration holds every search grouped into jobs", "[trace]") {
  const Recorded& r = recorded();
  // Recording observes: the transform is the same bit for bit.
  CHECK(r.recorded.transform == r.plain.transform);
  std::map<std::string, std::uint64_t> queries;
  std::map<std::string, int> iterations;
  for (const trace::Job& j : r.trace.jobs) {
    queries[j.stage] += j.counts.size();
    if (j.stage == "icp") iterations[j.stage] = std::max(iterations[j.stage], j.iteration + 1);
    CHECK(j.counts.size() == r.trace.cloud(j.queries).points.size());
  }
  for (const StageReport& s : r.recorded.stages) {
    INFO("stage " << s.name);
    CHECK(queries[s.name] == s.kdtree.searches);
  }
  // DP4: one-way RPCE, one job per ICP iteration on the target tree.
  const int icp_iterations = r.recorded.stages.back().info["iterations"].get<int>();
  CHECK(iterations["icp"] == icp_iterations);
  int icp_jobs = 0;
  for (const trace::Job& j : r.trace.jobs) icp_jobs += j.stage == "icp";
  CHECK(icp_jobs == icp_iterations);
}

TEST_CASE("trace: reciprocal RPCE records two jobs per iteration, one per tree", "[trace]") {
  const Recorded& r = recorded("dp7");
  std::map<int, std::set<int>> trees;  // iteration -> trees searched
  for (const trace::Job& j : r.trace.jobs)
    if (j.stage == "icp") trees[j.iteration].insert(j.tree_serial);
  REQUIRE(!trees.empty());
  for (const auto& [it, t] : trees) {
    INFO("iteration " << it);
    CHECK(t.size() == 2);
  }
}

TEST_CASE("trace: recorded results are the golden model's search of the job", "[trace]") {
  const Recorded& r = recorded();
  for (const trace::Job& j : r.trace.jobs) {
    INFO("job " << j.stage << " iteration " << j.iteration << " mode " << j.mode);
    const PointCloud& cloud = r.trace.cloud(j.tree).points;
    const PointCloud& queries = r.trace.cloud(j.queries).points;
    SearchParams p;
    p.mode = j.mode == "nn" ? Mode::NN : j.mode == "knn" ? Mode::KNN : Mode::Radius;
    p.k = j.k;
    p.radius = j.radius;
    p.max_nn = j.max_nn;
    const KdTree tree = build_kdtree(cloud, std::min(j.top_height, full_height_for(cloud.size())));
    const SearchOutput out = search(tree, queries, p);
    const trace::JobResults rec = trace::results(r.trace, j);
    REQUIRE(out.results.neighbors.size() == rec.index.size());
    bool same = true;
    for (std::size_t i = 0; i < rec.index.size() && same; ++i)
      same = out.results.neighbors[i].index == rec.index[i] &&
             std::memcmp(&out.results.neighbors[i].dist2, &rec.dist2[i], 4) == 0;
    CHECK(same);
    CHECK(std::vector<std::uint64_t>(out.results.offset.begin(), out.results.offset.end()) == rec.offset);
  }
}

TEST_CASE("trace: the file reads back equal and damaged files are refused naming the byte", "[trace]") {
  const Recorded& r = recorded();
  const std::vector<std::uint8_t> bytes = trace::encode(r.trace);
  const trace::Trace back = trace::decode(bytes.data(), bytes.size(), "t.trace");
  CHECK(back.meta == r.trace.meta);
  CHECK(back.total_seconds == r.trace.total_seconds);
  REQUIRE(back.stages.size() == r.trace.stages.size());
  REQUIRE(back.clouds.size() == r.trace.clouds.size());
  for (std::size_t i = 0; i < back.clouds.size(); ++i) {
    CHECK(back.clouds[i].hash == r.trace.clouds[i].hash);
    CHECK(std::memcmp(back.clouds[i].points.data(), r.trace.clouds[i].points.data(),
                      back.clouds[i].points.size() * sizeof(Point3)) == 0);
  }
  REQUIRE(back.jobs.size() == r.trace.jobs.size());
  for (std::size_t i = 0; i < back.jobs.size(); ++i) CHECK(same_job(back.jobs[i], r.trace.jobs[i]));
  // Each cloud stored once: normal estimation's queries are its tree's points.
  for (std::size_t i = 0; i < back.clouds.size(); ++i)
    for (std::size_t k = 0; k < i; ++k) CHECK(back.clouds[i].hash != back.clouds[k].hash);

  SECTION("truncated") {
    for (std::size_t n : {std::size_t{0}, std::size_t{7}, std::size_t{39}, std::size_t{40}, std::size_t{100},
                          bytes.size() / 2, bytes.size() - 1}) {
      INFO("first " << n << " bytes");
      const std::vector<std::uint8_t> cut(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n));
      CHECK_THAT(error_of(cut), Catch::StartsWith("t.trace: byte "));
    }
  }
  SECTION("corrupt") {
    for (std::size_t at : {std::size_t{30}, std::size_t{60}, std::size_t{200}, bytes.size() / 3, bytes.size() - 5}) {
      INFO("byte " << at << " flipped");
      std::vector<std::uint8_t> bad = bytes;
      bad[at] ^= 0x5a;
      CHECK_THAT(error_of(bad), Catch::StartsWith("t.trace: byte ") && Catch::Contains("corrupt"));
    }
  }
  SECTION("foreign") {
    std::vector<std::uint8_t> bad = bytes;
    std::memcpy(bad.data(), "PK\3\4", 4);
    CHECK_THAT(error_of(bad), Catch::Contains("byte 0: not a Tigris workload trace"));
  }
  SECTION("newer version") {
    std::vector<std::uint8_t> bad = bytes;
    bad[8] = 2;
    CHECK_THAT(error_of(bad), Catch::Contains("byte 8: trace format version 2 is newer"));
  }
  SECTION("appended") {
    std::vector<std::uint8_t> bad = bytes;
    bad.push_back(0);
    CHECK_THAT(error_of(bad), Catch::StartsWith("t.trace: byte "));
  }
}

// Forged traces: well-formed bytes, checksums right (encode computes them), values no recorder
// writes. Each must be refused naming what is wrong, never replayed into nonsense figures.
TEST_CASE("trace: forged values with valid checksums are refused", "[trace]") {
  const Recorded& r = recorded();
  REQUIRE(!r.trace.jobs.empty());
  const auto refused = [](const trace::Trace& t) {
    const std::vector<std::uint8_t> bytes = trace::encode(t);
    return error_of(bytes);
  };
  trace::Trace t = r.trace;
  t.total_seconds = -5e12;
  CHECK_THAT(refused(t), Catch::Contains("total_seconds is negative"));
  t = r.trace;
  t.stages.at(0).seconds = -1;
  CHECK_THAT(refused(t), Catch::Contains("negative or non-finite seconds"));
  t = r.trace;
  t.jobs[0].search_seconds = -0.5;
  CHECK_THAT(refused(t), Catch::Contains("negative seconds"));
  t = r.trace;
  t.jobs[0].stage = "";
  CHECK_THAT(refused(t), Catch::Contains("without a stage name"));
  t = r.trace;
  t.jobs[0].backend = "gpu";
  CHECK_THAT(refused(t), Catch::Contains("unknown back-end 'gpu'"));
  t = r.trace;
  t.jobs[0].leader_scope = "last_leaf";
  CHECK_THAT(refused(t), Catch::Contains("unknown leader_scope 'last_leaf'"));
  t = r.trace;
  t.jobs[0].leader_in_flight = "never";
  CHECK_THAT(refused(t), Catch::Contains("unknown leader_in_flight 'never'"));
  t = r.trace;  // the approximate reading goes with the job
  t.jobs[0].leader_scope = "every_leaf", t.jobs[0].leader_in_flight = "finished_only";
  const std::vector<std::uint8_t> bytes = trace::encode(t);
  const trace::Trace back = trace::decode(bytes.data(), bytes.size(), "t.trace");
  CHECK(back.jobs[0].leader_scope == "every_leaf");
  CHECK(back.jobs[0].leader_in_flight == "finished_only");
  CHECK(refused(r.trace).empty());  // the unforged trace reads
}

// The first section (the metadata) of an encoded trace, decompressed, edited and sealed again
// with right sizes and checksums: what a forger with the format description can do.
std::vector<std::uint8_t> forge_meta(const std::vector<std::uint8_t>& bytes, const std::string& from,
                                     const std::string& to) {
  const auto fnv1a = [](const std::uint8_t* p, std::size_t n) {
    std::uint64_t h = 14695981039346656037ull;
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
    return h;
  };
  const std::size_t at = 40;  // the header's 40 bytes, then the first section's 32-byte header
  std::uint64_t z = 0, raw = 0;
  std::memcpy(&z, &bytes[at + 8], 8);
  std::memcpy(&raw, &bytes[at + 16], 8);
  std::string text(raw, '\0');
  REQUIRE(ZSTD_decompress(&text[0], raw, &bytes[at + 32], z) == raw);
  const std::size_t hit = text.find(from);
  REQUIRE(hit != std::string::npos);
  REQUIRE(from.size() == to.size());  // the JSON's length prefix stays right
  text.replace(hit, from.size(), to);
  std::vector<std::uint8_t> packed(ZSTD_compressBound(text.size()));
  packed.resize(ZSTD_compress(packed.data(), packed.size(), text.data(), text.size(), 3));
  const std::size_t rest = bytes.size() - (at + 32 + z);  // the sections after the first
  std::vector<std::uint8_t> out(at + 32 + packed.size() + rest);
  std::copy_n(bytes.begin(), at + 32, out.begin());
  std::copy(packed.begin(), packed.end(), out.begin() + static_cast<std::ptrdiff_t>(at + 32));
  std::copy(bytes.end() - static_cast<std::ptrdiff_t>(rest), bytes.end(),
            out.end() - static_cast<std::ptrdiff_t>(rest));
  const std::uint64_t n = packed.size(), check = fnv1a(packed.data(), packed.size());
  std::memcpy(&out[at + 8], &n, 8);
  std::memcpy(&out[at + 24], &check, 8);
  const std::uint64_t size = out.size();
  std::memcpy(&out[24], &size, 8);
  const std::uint64_t head = fnv1a(out.data(), 32);  // over the header with its new size
  std::memcpy(&out[32], &head, 8);
  return out;
}

TEST_CASE("trace: a JSON key given twice in a section is refused", "[trace]") {
  trace::Trace t = recorded().trace;
  t.meta = {{"test", "a"}, {"dup_marker", 1}};
  const std::vector<std::uint8_t> bytes = trace::encode(t);
  // Sealed again unchanged, the forgery helper gives a trace that reads: the check below is the key.
  CHECK(error_of(forge_meta(bytes, "\"dup_marker\"", "\"dup_marker\"")).empty());
  const std::vector<std::uint8_t> forged = forge_meta(bytes, "\"dup_marker\"", "\"test\"      ");
  CHECK_THAT(error_of(forged), Catch::Contains("JSON key 'test' given twice"));
}

TEST_CASE("trace: approximate and FLANN registrations record what they searched", "[trace]") {
  const Recorded& a = recorded("dp4", "approx");
  bool approximate = false;
  for (const trace::Job& j : a.trace.jobs) approximate |= j.approximate;
  CHECK(approximate);
  CHECK(a.recorded.transform == a.plain.transform);
  const Recorded& f = recorded("dp4", "flann");
  for (const trace::Job& j : f.trace.jobs) {
    CHECK(j.backend == "flann");
    for (std::uint32_t i : j.indices) REQUIRE(i < f.trace.cloud(j.tree).points.size());
  }
  CHECK(f.recorded.transform == f.plain.transform);
}
