#include "timeline.hpp"

#include <algorithm>
#include <cmath>

namespace tigris {

using nlohmann::json;

namespace {

constexpr std::uint64_t kLaneStride = 1024;  // back-end tid = su * kLaneStride + lane

// The first lane free at `begin`, now busy until `end`: slices on one track never overlap.
std::size_t take_lane(std::vector<std::uint64_t>& lanes, std::uint64_t begin, std::uint64_t end) {
  std::size_t lane = 0;
  while (lane < lanes.size() && lanes[lane] > begin) ++lane;
  if (lane == lanes.size()) lanes.push_back(0);
  lanes[lane] = end;
  return lane;
}

}  // namespace

void TimelineRecorder::job_started(std::uint32_t num_queries) {
  events_ = json::array();
  stride_ = stride_for(num_queries, max_queries_);
  last_.assign(num_queries, {});
  lanes_.clear();
  writeback_lanes_.clear();
  qdn_lanes_.clear();
  named_.clear();
  flow_id_ = 0;
  for (auto& d : deltas_) d.clear();
  const std::string note = " (" + sampled_note() + ")";
  for (const auto& [pid, name] : {std::pair<int, std::string>{kMachine, "Whole machine: counters over all queries"},
                                  {kFrontEnd, "Front-end: Recursion Units" + note},
                                  {kQdn, "Query Distribution Network: SU ports" + note},
                                  {kBackEnd, "Back-end: Search Units" + note},
                                  {kWriteback, "Result write-back to DRAM" + note}}) {
    events_.push_back({{"ph", "M"}, {"name", "process_name"}, {"pid", pid}, {"args", {{"name", name}}}});
    events_.push_back({{"ph", "M"}, {"name", "process_sort_index"}, {"pid", pid}, {"args", {{"sort_index", pid}}}});
  }
}

std::string TimelineRecorder::sampled_note() const {
  if (stride_ <= 1) return "every query";
  const std::uint32_t r = stride_ % 100, d = stride_ % 10;
  const char* th = (r >= 11 && r <= 13) ? "th" : d == 1 ? "st" : d == 2 ? "nd" : d == 3 ? "rd" : "th";
  return "sampled: every " + std::to_string(stride_) + th + " query";
}

void TimelineRecorder::name_track(int pid, std::uint64_t tid, const std::string& name) {
  const std::uint64_t key = tid * 8 + static_cast<std::uint64_t>(pid);
  if (key >= named_.size()) named_.resize(key + 1, false);
  if (named_[key]) return;
  named_[key] = true;
  const std::string shown = stride_ > 1 ? name + " (sampled 1/" + std::to_string(stride_) + ")" : name;
  events_.push_back({{"ph", "M"}, {"name", "thread_name"}, {"pid", pid}, {"tid", tid}, {"args", {{"name", shown}}}});
  events_.push_back(
      {{"ph", "M"}, {"name", "thread_sort_index"}, {"pid", pid}, {"tid", tid}, {"args", {{"sort_index", tid}}}});
}

void TimelineRecorder::slice(int pid, std::uint64_t tid, const std::string& name, std::uint64_t begin,
                             std::uint64_t end, json args) {
  events_.push_back({{"ph", "X"},
                     {"name", name},
                     {"cat", "work"},
                     {"pid", pid},
                     {"tid", tid},
                     {"ts", us(begin)},
                     {"dur", us(end - begin)},
                     {"args", std::move(args)}});
}

void TimelineRecorder::hop(std::uint32_t query, int pid, std::uint64_t tid, std::uint64_t begin) {
  Last& l = last_[query];
  if (l.any) {
    const std::uint64_t id = ++flow_id_;
    const std::string name = "query " + std::to_string(query);
    events_.push_back(
        {{"ph", "s"}, {"name", name}, {"cat", "query"}, {"id", id}, {"pid", l.pid}, {"tid", l.tid}, {"ts", us(l.end)}});
    events_.push_back({{"ph", "f"},
                       {"bp", "e"},
                       {"name", name},
                       {"cat", "query"},
                       {"id", id},
                       {"pid", pid},
                       {"tid", tid},
                       {"ts", us(begin)}});
  }
}

void TimelineRecorder::ru_walk(std::uint32_t ru, std::uint32_t query, std::uint64_t begin, std::uint64_t end) {
  if (!sampled(query)) return;
  name_track(kFrontEnd, ru, "RU " + std::to_string(ru));
  hop(query, kFrontEnd, ru, begin);
  slice(kFrontEnd, ru, "walk q" + std::to_string(query), begin, end, {{"query", query}});
  last_[query] = {kFrontEnd, ru, end, true};
}

void TimelineRecorder::ru_blocked(std::uint32_t ru, std::uint32_t query, std::uint64_t begin, std::uint64_t end) {
  if (!sampled(query) || end <= begin) return;
  slice(kFrontEnd, ru, "BQB full q" + std::to_string(query), begin, end, {{"query", query}});
  last_[query] = {kFrontEnd, ru, end, true};
}

void TimelineRecorder::qdn_hop(std::uint32_t su, std::uint32_t query, std::uint64_t send, std::uint64_t arrive) {
  deltas_[kBqb].push_back({arrive, 1});
  if (!sampled(query)) return;
  // Hops on one port overlap in flight (a query a cycle): one lane per overlap depth.
  if (su >= qdn_lanes_.size()) qdn_lanes_.resize(su + 1);
  const std::size_t lane = take_lane(qdn_lanes_[su], send, arrive);
  const std::uint64_t tid = su * kLaneStride + lane;
  name_track(kQdn, tid, "port SU " + std::to_string(su) + (lane ? " overlap " + std::to_string(lane) : ""));
  hop(query, kQdn, tid, send);
  slice(kQdn, tid, "q" + std::to_string(query), send, arrive, {{"query", query}});
  last_[query] = {kQdn, tid, arrive, true};
}

void TimelineRecorder::su_batch(std::uint32_t su, std::uint32_t leaf, const hw::QueryToken* tokens, std::size_t n,
                                std::uint64_t issue, std::uint64_t end, std::uint64_t stream) {
  deltas_[kBqb].push_back({issue, -static_cast<std::int64_t>(n)});
  bool any = false;
  for (std::size_t i = 0; i < n && !any; ++i) any = sampled(tokens[i].query);
  if (!any) return;
  if (su >= lanes_.size()) lanes_.resize(su + 1);
  const std::size_t lane = take_lane(lanes_[su], issue, end);
  const std::uint64_t tid = su * kLaneStride + lane;
  name_track(kBackEnd, tid, "SU " + std::to_string(su) + (lane ? " lane " + std::to_string(lane) : ""));
  json queries = json::array();
  for (std::size_t i = 0; i < n; ++i) queries.push_back(tokens[i].query);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t q = tokens[i].query;
    if (!sampled(q)) continue;
    // The wait in the BE Query Buffer, as an async slice on the SU's process.
    if (issue > tokens[i].ready) {
      const json common = {
          {"name", "BQB wait q" + std::to_string(q)}, {"cat", "bqb_wait"}, {"id", q}, {"pid", kBackEnd}};
      json b = common, e = common;
      b["ph"] = "b", b["ts"] = us(tokens[i].ready), b["args"] = {{"su", su}};
      e["ph"] = "e", e["ts"] = us(issue);
      events_.push_back(b);
      events_.push_back(e);
    }
    hop(q, kBackEnd, tid, issue);
    last_[q] = {kBackEnd, tid, end, true};
  }
  slice(kBackEnd, tid, "leaf " + std::to_string(leaf), issue, end,
        {{"leaf", leaf}, {"queries", queries}, {"stream_entries", stream}});
}

void TimelineRecorder::writeback(std::uint32_t query, std::size_t records, std::uint64_t accept,
                                 std::uint64_t drained) {
  count(kBacklog, accept, drained, static_cast<std::int64_t>(records));
  if (!sampled(query)) return;
  // Chunks overlap in flight (the channel pipelines them): one lane per overlap depth.
  const std::size_t lane = take_lane(writeback_lanes_, accept, drained);
  name_track(kWriteback, lane, lane ? "DRAM channel, overlap " + std::to_string(lane) : "DRAM channel");
  hop(query, kWriteback, lane, accept);
  slice(kWriteback, lane, std::to_string(records) + " records q" + std::to_string(query), accept, drained,
        {{"query", query}, {"records", records}});
}

void TimelineRecorder::activity(Activity what, std::uint32_t n, std::uint64_t begin, std::uint64_t end) {
  count(static_cast<int>(what), begin, end, n);
}

void TimelineRecorder::count(int series, std::uint64_t begin, std::uint64_t end, std::int64_t n) {
  if (end <= begin || n == 0) return;
  deltas_[series].push_back({begin, n});
  deltas_[series].push_back({end, -n});
}

double TimelineRecorder::estimated_bytes(double queries, double leaf_visits_per_query) {
  return queries * (1.0 + leaf_visits_per_query) * kBytesPerVisit;
}

// Each series' level integrated over bins of `width` cycles: the exact mean level per bin.
void TimelineRecorder::add_counters(json& events) const {
  std::uint64_t last = 0;
  for (const auto& d : deltas_)
    for (const auto& e : d) last = std::max(last, e.first);
  if (last == 0) return;
  const std::uint64_t width = (last + kCounterBins - 1) / kCounterBins, bins = (last + width - 1) / width;
  std::vector<std::vector<double>> mean(kSeries, std::vector<double>(bins, 0.0));
  for (int s = 0; s < kSeries; ++s) {
    std::vector<std::pair<std::uint64_t, std::int64_t>> d = deltas_[s];
    std::sort(d.begin(), d.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::int64_t level = 0;
    std::uint64_t prev = 0;
    for (const auto& [t, change] : d) {
      for (std::uint64_t b = prev / width; level != 0 && prev < t && b < bins; ++b) {
        const std::uint64_t lo = std::max(prev, b * width), hi = std::min(t, (b + 1) * width);
        if (hi > lo) mean[s][b] += static_cast<double>(level) * static_cast<double>(hi - lo);
        if (hi == t) break;
      }
      level += change;
      prev = t;
    }
    for (double& m : mean[s]) m /= static_cast<double>(width);
  }
  const auto round3 = [](double v) { return std::round(v * 1000.0) / 1000.0; };
  struct Track {
    const char* name;
    std::vector<std::pair<int, const char*>> series;
  };
  const Track tracks[] = {{"RUs", {{0, "busy"}, {1, "SRAM stall"}, {2, "BQB-full stall"}, {3, "write-back stall"}}},
                          {"PEs", {{4, "busy"}, {5, "waiting for data"}, {6, "held by write-back"}}},
                          {"BQB occupancy (queries, all SUs)", {{kBqb, "queries"}}},
                          {"write-back backlog (records)", {{kBacklog, "records"}}}};
  for (const Track& tr : tracks) {
    const std::string name = std::string(tr.name) + ", mean per " + std::to_string(width) + "-cycle bin";
    for (std::uint64_t b = 0; b <= bins; ++b) {
      json args = json::object();
      for (const auto& [s, label] : tr.series) args[label] = b < bins ? round3(mean[s][b]) : 0.0;
      events.push_back({{"ph", "C"},
                        {"name", name},
                        {"pid", kMachine},
                        {"ts", us(std::min(b * width, last))},
                        {"args", std::move(args)}});
    }
  }
}

json TimelineRecorder::trace() const {
  json events = events_;
  add_counters(events);
  std::uint64_t last = 0;
  for (const auto& d : deltas_)
    for (const auto& e : d) last = std::max(last, e.first);
  return {{"traceEvents", std::move(events)},
          {"displayTimeUnit", "ns"},
          {"otherData",
           {{"sampled_every", stride_},
            {"sampled", sampled_note()},
            {"cycle_ns", period_ns_},
            {"counter_bin_cycles", last ? (last + kCounterBins - 1) / kCounterBins : 0}}}};
}

}  // namespace tigris
