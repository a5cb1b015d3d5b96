#include "sampling.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "config/key_table.hpp"
#include "hw/area_model.hpp"
#include "hw/top.hpp"

namespace tigris {

namespace {

constexpr std::uint32_t kMinMeasured = 64;  // queries per window: fewer measure noise, not throughput

SamplingPlan full(SamplingPlan p, std::string why) {
  p.sampled = false;
  p.why = std::move(why);
  p.stream.clear();
  p.windows.clear();
  return p;
}

}  // namespace

double student_t95(std::size_t dof) {
  static const double table[] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
                                 2.201,  2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
                                 2.080,  2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
  if (dof == 0) return std::numeric_limits<double>::infinity();
  if (dof <= 30) return table[dof - 1];
  return 1.96 + 2.4 / static_cast<double>(dof);  // within 0.002 of the quantile above 30
}

nlohmann::json sampling_setting(double sampling) {
  if (sampling == 0) return "off";
  if (sampling == hw::AcceleratorConfig::Sim::kAuto) return "auto";
  return sampling;
}

SamplingPlan plan_sampling(const hw::AcceleratorConfig::Sim& sim, std::uint32_t queries, std::uint32_t in_flight,
                           bool approximate) {
  SamplingPlan p;
  p.requested = sim.sampling;
  p.queries = queries;
  p.in_flight = in_flight;
  if (sim.sampling == 0) return full(p, "sim.sampling is off");
  if (approximate)
    return full(p, "approximate search: which queries lead depends on every query before, so every query is simulated");
  const bool automatic = sim.sampling == hw::AcceleratorConfig::Sim::kAuto;
  const std::uint64_t n = static_cast<std::uint64_t>(sim.windows);
  const auto or_in_flight = [&](int v) {
    return v == hw::AcceleratorConfig::Sim::kAuto ? std::max<std::uint64_t>(in_flight, kMinMeasured)
                                                  : static_cast<std::uint64_t>(v);
  };
  // A query's cycles show only once the machine holds queries like it: warming and windows of
  // one in-flight generation each by default (docs/sampling.md has the measurements).
  const std::uint64_t warm = or_in_flight(sim.warm_queries);
  const std::uint64_t fill = std::uint64_t{in_flight} + warm;  // every slot taken, then warming
  std::uint64_t measured;
  if (automatic) {
    measured = or_in_flight(sim.window_queries);
  } else {
    // fill + n windows (all but the first after warming) + the drain (warm + measured) = the share.
    const double budget = sim.sampling * queries - static_cast<double>(fill + n * warm);
    if (budget < static_cast<double>((n + 1) * kMinMeasured))
      return full(p, "sim.sampling = " + config::number_text(sim.sampling) + " leaves fewer than " +
                         std::to_string(kMinMeasured) + " measured queries per window");
    measured = static_cast<std::uint64_t>(budget / static_cast<double>(n + 1));
  }
  const std::uint64_t drain = warm + measured;
  const std::uint64_t simulated = fill + n * measured + (n - 1) * warm + drain;
  if (simulated >= queries || (queries - fill - drain) / n < warm + measured)
    return full(p, "the job is too short to sample: its " + std::to_string(queries) + " queries, " +
                       std::to_string(in_flight) + " in flight at a time, leave no room for " + std::to_string(n) +
                       " windows of " + std::to_string(measured) + " queries after " + std::to_string(warm) +
                       " of warming, a fill of " + std::to_string(fill) + " and a drain of " + std::to_string(drain));
  if (automatic && 3 * simulated > queries)
    return full(p, "auto: the job is too short to gain: sampling would simulate " + std::to_string(simulated) + " of " +
                       std::to_string(queries) + " queries (" + std::to_string(in_flight) + " in flight at a time)");
  p.sampled = true;
  p.fill = static_cast<std::uint32_t>(fill);
  p.warm = static_cast<std::uint32_t>(warm);
  p.measured = static_cast<std::uint32_t>(measured);
  p.drain = static_cast<std::uint32_t>(drain);
  const double period = static_cast<double>(queries - fill - drain) / static_cast<double>(n);
  for (std::uint32_t q = 0; q < fill; ++q) p.stream.push_back(q);
  for (std::uint64_t j = 0; j < n; ++j) {
    const auto start = static_cast<std::uint32_t>(fill + std::floor(static_cast<double>(j) * period));
    for (std::uint32_t q = j == 0 ? start : start - p.warm; q < start; ++q) p.stream.push_back(q);
    const auto from = static_cast<std::uint32_t>(p.stream.size());
    for (std::uint32_t q = start; q < start + p.measured; ++q) p.stream.push_back(q);
    p.windows.push_back({from, from + p.measured});
  }
  for (std::uint32_t q = queries - p.drain; q < queries; ++q) p.stream.push_back(q);
  return p;
}

SampleController::SampleController(const SamplingPlan& plan, hw::TigrisAccelerator& accel, QueryWork work)
    : plan_(plan), accel_(accel), work_(std::move(work)) {
  for (const auto& w : plan.windows) {
    marks_.push_back(w.from);
    marks_.push_back(w.to);
  }
}

void SampleController::query_admitted(std::uint32_t query, std::uint64_t cycle) {
  // A loop: without warming, a window's end is the next one's start, one admission for both.
  while (snaps_.size() < marks_.size() && query == marks_[snaps_.size()]) {
    snaps_.push_back({cycle, accel_.stats().values()});
    if (snaps_.size() % 2 == 0) warm_writeback(snaps_.size() / 2 - 1, cycle);
  }
}

void SampleController::warm_writeback(std::size_t window, std::uint64_t cycle) {
  const SamplingPlan::Window& w = plan_.windows[window];
  // The skipped queries' own pace, unthrottled: a window held back by the write-back runs at its
  // results' pace, not at theirs; the fastest window so far is the best guess at what the units
  // do when nothing holds them (a full stream buffer then holds them as in a full simulation).
  const double pace = static_cast<double>(cycle - snaps_[2 * window].cycle) / (w.to - w.from);  // cycles/query
  fastest_ = window == 0 ? pace : std::min(fastest_, pace);
  hw::ResultWriteback& wb = accel_.writeback();
  const double drained = accel_.config().dram.bytes_per_cycle * fastest_;  // bytes per skipped query
  const double cap = static_cast<double>(wb.buffer_bytes());
  double backlog = wb.backlog_bytes(cycle);
  // The skipped queries lie between the window's last query and the next stretch's first.
  for (std::uint32_t q = plan_.stream[w.to - 1] + 1; q < plan_.stream[w.to]; ++q)
    backlog = std::clamp(backlog + work_.records[q] * double{sizeof(tlm_if::ResultRecord)} - drained, 0.0, cap);
  wb.set_backlog(cycle, backlog);
}

RatioEstimate ratio_estimate(const std::vector<double>& y, const std::vector<double>& x) {
  RatioEstimate e;
  const std::size_t n = y.size();
  double sy = 0, sx = 0;
  for (std::size_t k = 0; k < n; ++k) sy += y[k], sx += x[k];
  if (sx <= 0) return e;
  e.ratio = sy / sx;
  if (n < 2) return e;
  // Successive differences of the residuals (Wolter, Introduction to Variance Estimation, 8.2):
  // the segments are a systematic sample, and a trend along the job (a scan's near and far
  // halves) is no sampling error; the variance of independent samples would count it as one.
  double ss = 0;
  for (std::size_t k = 1; k < n; ++k) {
    const double d = (y[k] - e.ratio * x[k]) - (y[k - 1] - e.ratio * x[k - 1]);
    ss += d * d;
  }
  const double mean_x = sx / static_cast<double>(n);
  const double variance = ss / (2.0 * static_cast<double>(n - 1));  // of one segment's residual
  e.half = student_t95(n - 1) * std::sqrt(variance / static_cast<double>(n)) / mean_x;
  return e;
}

namespace {

using ValueKind = hw::StatGroup::ValueKind;

// The stream between fill and drain as segments: segment k runs from window k's first admission
// to window k+1's (the last: to the drain's), seams included. With every slot taken, its
// admissions follow the completions of the queries `in_flight` positions earlier, so its
// auxiliary totals are those queries'.
struct Segments {
  std::vector<double> cycles, per_query;
  std::vector<std::vector<std::uint64_t>> grown;  // the statistics' growth, per segment
  std::vector<std::string> aux_names;
  std::vector<std::vector<double>> aux;  // [candidate][segment]
  std::vector<double> aux_job;           // [candidate]: the job's queries between fill and drain
};

std::vector<std::uint64_t> growth(const std::vector<std::uint64_t>& a, const std::vector<std::uint64_t>& b,
                                  const std::vector<ValueKind>& kinds) {
  std::vector<std::uint64_t> d(a.size());
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = kinds[i] == ValueKind::Maximum ? 0 : b[i] - std::min(a[i], b[i]);
  return d;
}

Segments measure(const SamplingPlan& plan, const SampleController& control, const std::vector<ValueKind>& kinds) {
  const auto& s = control.snapshots();
  const std::size_t n = plan.windows.size();
  const std::uint32_t band = plan.in_flight;
  const QueryWork& w = control.work();
  const std::pair<const char*, const std::vector<std::uint32_t>*> candidates[] = {{"queries", nullptr},
                                                                                  {"result_records", &w.records},
                                                                                  {"leaf_points", &w.leaf_points},
                                                                                  {"top_nodes", &w.top_nodes}};
  Segments seg;
  std::vector<std::uint32_t> from, to;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t a = 2 * k, b = k + 1 < n ? 2 * k + 2 : 2 * k + 1;
    from.push_back(plan.windows[k].from);
    to.push_back(k + 1 < n ? plan.windows[k + 1].from : plan.windows[k].to);
    seg.cycles.push_back(static_cast<double>(s[b].cycle - s[a].cycle));
    seg.per_query.push_back(seg.cycles.back() / (to.back() - from.back()));
    seg.grown.push_back(growth(s[a].values, s[b].values, kinds));
  }
  for (const auto& [name, x] : candidates) {
    const auto total = [x = x](auto id, std::uint32_t lo, std::uint32_t hi) {
      double t = 0;
      for (std::uint32_t i = lo; i < hi; ++i) t += x ? (*x)[id(i)] : 1.0;
      return t;
    };
    std::vector<double> per_segment;
    for (std::size_t k = 0; k < n; ++k)
      per_segment.push_back(total([&](std::uint32_t i) { return plan.stream[i]; }, from[k] - band, to[k] - band));
    seg.aux_names.push_back(name);
    seg.aux.push_back(per_segment);
    seg.aux_job.push_back(total([](std::uint32_t i) { return i; }, plan.fill - band, plan.queries - plan.drain - band));
  }
  return seg;
}

// The auxiliary that gives y the narrowest interval, and y's ratio to it.
struct Choice {
  std::size_t aux = 0;
  RatioEstimate r;
  double total = 0, half = 0;  // the job's queries between fill and drain: y's estimate, its half width
};

Choice best_ratio(const std::vector<double>& y, const Segments& seg) {
  Choice best;
  best.half = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < seg.aux.size(); ++c) {
    double sx = 0;
    for (double x : seg.aux[c]) sx += x;
    if (sx <= 0 || seg.aux_job[c] <= 0) continue;  // counted nothing (top nodes at height 0): no scale
    const RatioEstimate r = ratio_estimate(y, seg.aux[c]);
    if (r.ratio < 0 || r.half * seg.aux_job[c] >= best.half) continue;
    best = {c, r, r.ratio * seg.aux_job[c], r.half * seg.aux_job[c]};
  }
  if (!std::isfinite(best.half)) best.half = 0;  // y grew nowhere: nothing to estimate
  return best;
}

}  // namespace

std::uint64_t apply_estimate(const SamplingPlan& plan, const SampleController& control, hw::TigrisAccelerator& accel,
                             std::uint64_t stream_cycles, nlohmann::json& report) {
  const auto& s = control.snapshots();
  if (s.size() != 2 * plan.windows.size()) throw std::logic_error("sampled simulation: a window was not measured");
  const hw::AcceleratorConfig& cfg = accel.config();
  const std::vector<std::uint64_t> last = accel.stats().values();
  const std::vector<ValueKind> kinds = accel.stats().value_kinds();
  const auto energy = [&](const std::vector<std::uint64_t>& v, double cycles) {
    accel.set_stat_values(v);
    return accel.energy_pj(hw::leakage_pj(cfg, static_cast<std::uint64_t>(cycles))).at("total").get<double>();
  };
  const Segments seg = measure(plan, control, kinds);
  const Choice time = best_ratio(seg.cycles, seg);
  const std::uint64_t fill_cycles = s.front().cycle - accel.start_cycle();
  const std::uint64_t drain_cycles = accel.start_cycle() + stream_cycles - s.back().cycle;
  const auto cycles =
      static_cast<std::uint64_t>(std::llround(static_cast<double>(fill_cycles + drain_cycles) + time.total));

  // The counters: fill and drain as simulated, the queries between scaled by one auxiliary per
  // kind, so that sums over banks or units stay their totals: busy and stall cycles by the
  // cycles' (their shares of the cycles stay consistent), events and bytes by the energy's (what
  // they are priced for).
  std::vector<double> joules;
  for (std::size_t k = 0; k < seg.cycles.size(); ++k) joules.push_back(energy(seg.grown[k], seg.cycles[k]));
  const Choice work = best_ratio(joules, seg);
  std::vector<std::uint64_t> est(last.size());
  const std::vector<std::uint64_t> between = growth(s.front().values, s.back().values, kinds);
  std::vector<double> y(seg.cycles.size());
  for (std::size_t i = 0; i < est.size(); ++i) {
    if (kinds[i] == ValueKind::Maximum) {
      est[i] = last[i];
      continue;
    }
    for (std::size_t k = 0; k < y.size(); ++k) y[k] = static_cast<double>(seg.grown[k][i]);
    const std::size_t aux = kinds[i] == ValueKind::Cycles ? time.aux : work.aux;
    const double scaled = ratio_estimate(y, seg.aux[aux]).ratio * seg.aux_job[aux];
    est[i] = static_cast<std::uint64_t>(std::llround(static_cast<double>(last[i] - between[i]) + scaled));
  }
  const double e_half = work.half;
  const double energy_total = energy(est, static_cast<double>(cycles));  // leaves the estimate in the statistics
  const double c_half = time.half;
  const std::size_t n = plan.windows.size();
  const std::vector<double>& per_query = seg.per_query;
  const std::string aux = seg.aux_names[time.aux];

  nlohmann::json& j = report;
  j["requested"] = sampling_setting(plan.requested);
  j["sampled"] = true;
  j["queries"] = plan.queries;
  j["simulated"] = plan.stream.size();
  j["checked"] = plan.stream.size();
  j["in_flight"] = plan.in_flight;
  j["fill"] = plan.fill;
  j["drain"] = plan.drain;
  j["windows"] = n;
  j["warm_per_window"] = plan.warm;
  j["measured_per_window"] = plan.measured;
  j["simulated_cycles"] = stream_cycles;
  j["fill_cycles"] = fill_cycles;
  j["drain_cycles"] = drain_cycles;
  j["segment_cycles_per_query"] = per_query;
  j["auxiliary"] = aux;
  j["cycles_ci95"] = {std::max(0.0, static_cast<double>(cycles) - c_half), static_cast<double>(cycles) + c_half};
  j["energy_pj_ci95"] = {std::max(0.0, energy_total - e_half), energy_total + e_half};
  j["relative_half_width"] = cycles ? c_half / static_cast<double>(cycles) : 0.0;
  return cycles;
}

std::string sampling_summary(const nlohmann::json& j) {
  if (j.at("requested") == "off") return "";
  if (!j.at("sampled").get<bool>()) return "  sampled no: " + j.at("why").get<std::string>() + "\n";
  const auto u = [&](const char* k) { return static_cast<unsigned long long>(j.at(k).get<std::uint64_t>()); };
  const auto& ci = j.at("cycles_ci95");
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "  sampled %llu of %llu queries simulated and checked (fill %llu, %llu windows of %llu after %llu "
                "warming, drain %llu); cycles, energy and the shares below are estimates: cycles 95%% interval "
                "[%.0f, %.0f] (+-%.2f%%)\n",
                u("simulated"), u("queries"), u("fill"), u("windows"), u("measured_per_window"), u("warm_per_window"),
                u("drain"), ci[0].get<double>(), ci[1].get<double>(), 100 * j.at("relative_half_width").get<double>());
  return buf;
}

nlohmann::json full_simulation_json(const SamplingPlan& plan, std::uint64_t cycles) {
  return {{"requested", sampling_setting(plan.requested)},
          {"sampled", false},
          {"why", plan.why},
          {"queries", plan.queries},
          {"in_flight", plan.in_flight},
          {"simulated", plan.queries},
          {"checked", plan.queries},
          {"cycles_ci95", {cycles, cycles}},
          {"relative_half_width", 0.0}};
}

}  // namespace tigris
