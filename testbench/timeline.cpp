#include "timeline.hpp"

#include <algorithm>

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
  stride_ = std::max<std::uint32_t>(1, (num_queries + std::max<std::uint32_t>(max_queries_, 1) - 1) /
                                           std::max<std::uint32_t>(max_queries_, 1));
  last_.assign(num_queries, {});
  lanes_.clear();
  writeback_lanes_.clear();
  qdn_lanes_.clear();
  named_.clear();
  flow_id_ = 0;
  for (const auto& [pid, name] : {std::pair<int, const char*>{kFrontEnd, "Front-end: Recursion Units"},
                                  {kQdn, "Query Distribution Network: SU ports"},
                                  {kBackEnd, "Back-end: Search Units"},
                                  {kWriteback, "Result write-back to DRAM"}}) {
    events_.push_back({{"ph", "M"}, {"name", "process_name"}, {"pid", pid}, {"args", {{"name", name}}}});
    events_.push_back({{"ph", "M"}, {"name", "process_sort_index"}, {"pid", pid}, {"args", {{"sort_index", pid}}}});
  }
}

void TimelineRecorder::name_track(int pid, std::uint64_t tid, const std::string& name) {
  const std::uint64_t key = tid * 8 + static_cast<std::uint64_t>(pid);
  if (key >= named_.size()) named_.resize(key + 1, false);
  if (named_[key]) return;
  named_[key] = true;
  events_.push_back({{"ph", "M"}, {"name", "thread_name"}, {"pid", pid}, {"tid", tid}, {"args", {{"name", name}}}});
  events_.push_back({{"ph", "M"}, {"name", "thread_sort_index"}, {"pid", pid}, {"tid", tid}, {"args", {{"sort_index", tid}}}});
}

void TimelineRecorder::slice(int pid, std::uint64_t tid, const std::string& name, std::uint64_t begin,
                             std::uint64_t end, json args) {
  events_.push_back({{"ph", "X"}, {"name", name}, {"cat", "work"}, {"pid", pid}, {"tid", tid}, {"ts", us(begin)},
                     {"dur", us(end - begin)}, {"args", std::move(args)}});
}

void TimelineRecorder::hop(std::uint32_t query, int pid, std::uint64_t tid, std::uint64_t begin) {
  Last& l = last_[query];
  if (l.any) {
    const std::uint64_t id = ++flow_id_;
    const std::string name = "query " + std::to_string(query);
    events_.push_back({{"ph", "s"}, {"name", name}, {"cat", "query"}, {"id", id}, {"pid", l.pid}, {"tid", l.tid},
                       {"ts", us(l.end)}});
    events_.push_back({{"ph", "f"}, {"bp", "e"}, {"name", name}, {"cat", "query"}, {"id", id}, {"pid", pid},
                       {"tid", tid}, {"ts", us(begin)}});
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
      const json common = {{"name", "BQB wait q" + std::to_string(q)}, {"cat", "bqb_wait"}, {"id", q}, {"pid", kBackEnd}};
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

void TimelineRecorder::writeback(std::uint32_t query, std::size_t records, std::uint64_t accept, std::uint64_t drained) {
  if (!sampled(query)) return;
  // Chunks overlap in flight (the channel pipelines them): one lane per overlap depth.
  const std::size_t lane = take_lane(writeback_lanes_, accept, drained);
  name_track(kWriteback, lane, lane ? "DRAM channel, overlap " + std::to_string(lane) : "DRAM channel");
  hop(query, kWriteback, lane, accept);
  slice(kWriteback, lane, std::to_string(records) + " records q" + std::to_string(query), accept, drained,
        {{"query", query}, {"records", records}});
}

json TimelineRecorder::trace() const {
  return {{"traceEvents", events_},
          {"displayTimeUnit", "ns"},
          {"otherData", {{"sampled_every", stride_}, {"cycle_ns", period_ns_}}}};
}

}  // namespace tigris
