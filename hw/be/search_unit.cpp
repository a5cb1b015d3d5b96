#include "search_unit.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include "hw/fe/front_end.hpp"
#include "hw/mem/result_buffer.hpp"
#include "hw/qdn/distribution_network.hpp"

namespace tigris::hw {

SearchUnit::SearchUnit(sc_core::sc_module_name name, std::uint32_t id, const AcceleratorConfig& config,
                       const JobDescriptor& job, Links links)
    : sc_module(name), Scheduler::Client(Scheduler::kSearchUnit, id), points("points"), results("results"), id_(id),
      config_(config), job_(job), links_(links), clock_{config.period()},
      capacity_(static_cast<std::size_t>(config.be.bqb_entries)),
      pes_(static_cast<std::uint32_t>(config.be.pes_per_su)), free_pes_(pes_), policy_(make_issue_policy(config)),
      leader_buffer_(id, config, links.meter), stats_(basename(), "search_unit"),
      distance_energy_(links.meter.line("pe.distance", EnergyMeter::Component::Pe, links.meter.table().distance_pj)),
      leader_check_(stats_, links.meter), stall_(config.stall, "su" + std::to_string(id), stats_) {
  stats_.add(leader_buffer_.stats());
  links.scheduler.add(*this);
}

void SearchUnit::start() {
  stall_.start();
  bqb_.clear();
  active_ = 0;
  free_pes_ = pes_;
  ledger_.start(clock_.now());
  policy_->start();
  tree_ = TreeView(points.data(), job_);
  pe_array_.start(job_, tree_, ResultSlots(results.data(), job_.k));
  leader_buffer_.start(job_, results.data());
  arrivals_.clear();
  ready_followers_.clear();
}

void SearchUnit::leader_arrives(LeaderRecord record) {
  const std::uint64_t at = record.ready;
  arrivals_.push_back(std::move(record));  // the QDN port delivers in order
  links_.scheduler.at(*this, std::max(at, clock_.now()));
}

void SearchUnit::apply_leader_records(std::uint64_t now) {
  while (!arrivals_.empty() && arrivals_.front().ready <= now) {
    LeaderRecord& r = arrivals_.front();
    if (job_.wait_for_leaders) {  // its list into its entry; its parked followers may go
      LeaderBuffer::Leader& l = leader_buffer_.leader(r.leaf, r.entry);
      leader_buffer_.fill(r.leaf, r.entry, r.list);
      l.ready = list_access(now, l, true);
      for (QueryToken& t : l.waiters) t.ready = now, ready_followers_.push_back(t);
      l.waiters.clear();
    } else {  // finished_only: its point into the Leader Buffer, if it has room, and its list
      const bool taken = !leader_buffer_.full(r.leaf);
      if (taken) {
        LeaderBuffer::Leader& l = leader_buffer_.leader(r.leaf, leader_buffer_.append(r.leaf, r.point, r.list));
        l.ready = list_access(now, l, true);
      }
      leader_check_.joined(taken);
      links_.observer.leader_finished(r.query, r.leaf, taken);
    }
    arrivals_.pop_front();
    links_.fe.leader_record_delivered(now);
  }
}

void SearchUnit::accept(const QueryToken& token) {
  bqb_.push_back(token);
  links_.scans.queued(pe_array_, token);  // host prefetch hints
  bqb_wave_.set(bqb_.size());
  bqb_max_.max(bqb_.size());
  const std::uint64_t now = clock_.now();
  links_.scheduler.at(*this, std::max(token.ready, now));
}

void SearchUnit::step() {
  const std::uint64_t now = clock_.now();
  ledger_.settle(now);
  apply_leader_records(now);  // before this cycle's Leader Checks
  // Retire batches whose stream has drained: their queries go back to the front-end (a
  // first_leaf follower has finished: it leaves the machine).
  for (std::size_t i = 0; i < active_;) {
    if (running_[i].end > now) {
      ++i;
      continue;
    }
    // Results leave first; a full write-back stream holds the batch (and its PEs) back.
    const std::uint64_t accepted = retire(running_[i]);
    if (accepted > now) {
      const auto held = static_cast<std::int64_t>(running_[i].tokens.size());
      writeback_pes_wave_.add_at(clock_, now, held);
      writeback_pes_wave_.add_at(clock_, accepted, -held);
      links_.observer.activity(JobObserver::Activity::PeWritebackHold, static_cast<std::uint32_t>(held), now, accepted);
      running_[i].end = accepted;
      ++i;
      continue;
    }
    const std::uint64_t back = now + static_cast<std::uint64_t>(config_.cost.be_to_fe) + stall_.draw();
    for (const QueryToken& t : running_[i].tokens)
      if (t.finished)
        links_.fe.query_finished(t, now);
      else if (!t.parked)  // a parked follower waits with its leader
        links_.fe.reinsert(t, back);
    free_pes_ += static_cast<std::uint32_t>(running_[i].tokens.size());
    std::swap(running_[i], running_[--active_]);  // the last running batch takes its place
  }
  // Followers whose leader's list has been written go first: they wait for nothing but PEs.
  while (!ready_followers_.empty() && free_pes_ > 0) {
    Batch& batch = add_batch();
    const QueryToken& head = ready_followers_.front();
    const std::uint32_t leaf = head.first_leaf, leader = head.follows;
    while (!ready_followers_.empty() && batch.tokens.size() < free_pes_ &&
           ready_followers_.front().first_leaf == leaf && ready_followers_.front().follows == leader) {
      batch.tokens.push_back(ready_followers_.front());
      ready_followers_.pop_front();
    }
    issue_followers(batch, now);
  }
  // Issue while the policy finds batches for the free PEs.
  bool issued = false;
  for (;;) {
    const IssueDecision& d = decision_;
    policy_->pick(IssueView{bqb_, free_pes_, pes_, now, links_.cache}, decision_);
    if (d.batches() == 0) break;
    const std::size_t first_new = active_;
    taken_.assign(bqb_.size(), 0);
    for (std::size_t b = 0, p = 0; b < d.batches(); ++b) {
      Batch& batch = add_batch();
      for (; p < d.ends[b]; ++p) batch.tokens.push_back(bqb_[d.positions[p]]), taken_[d.positions[p]] = 1;
    }
    std::size_t kept = 0;  // the rest keep their order
    for (std::size_t i = 0; i < bqb_.size(); ++i)
      if (!taken_[i]) bqb_[kept++] = bqb_[i];
    bqb_.resize(kept);
    const std::uint64_t setup = d.search_cycles + static_cast<std::uint64_t>(config_.cost.issue_cycle);
    ledger_.book(kIssue, now, now + setup);
    for (std::size_t b = first_new; b < active_; ++b) issue(running_[b], now, setup);
    issued = true;
  }
  if (issued) links_.qdn.space_freed(id_);
  bqb_wave_.set(bqb_.size());
  // Sleep until a batch drains or a queued query arrives.
  std::uint64_t next = std::numeric_limits<std::uint64_t>::max();
  for (std::size_t b = 0; b < active_; ++b) next = std::min(next, running_[b].end);
  // Queries arrive in order (the QDN port to this SU serialises them): the first one still on
  // its way arrives next.
  const auto on_way =
      std::upper_bound(bqb_.begin(), bqb_.end(), now, [](std::uint64_t c, const QueryToken& t) { return c < t.ready; });
  if (on_way != bqb_.end()) next = std::min(next, on_way->ready);
  if (!arrivals_.empty()) next = std::min(next, std::max(arrivals_.front().ready, now + 1));
  if (next != std::numeric_limits<std::uint64_t>::max()) links_.scheduler.at(*this, next);
}

SearchUnit::Batch& SearchUnit::add_batch() {
  if (active_ == running_.size()) running_.emplace_back();
  Batch& b = running_[active_++];
  b.tokens.clear(), b.hits.clear(), b.end = 0, b.written = false;
  return b;
}

void SearchUnit::issue(Batch& batch, std::uint64_t now, std::uint64_t setup) {
  std::vector<QueryToken>& tokens = batch.tokens;
  const std::uint64_t start = now + setup;  // buffers are read during the issue search
  const std::uint32_t leaf = tokens.front().leaf;
  for (const QueryToken& t : tokens)  // one Node Set streams past the batch's PEs
    if (t.leaf != leaf)
      throw std::logic_error("issue policy " + config_.be.issue_policy + " put queries of leaves " +
                             std::to_string(leaf) + " and " + std::to_string(t.leaf) +
                             " in one batch (a batch streams one Node Set)");
  const std::uint64_t n = tree_.leaf_size(leaf);
  const std::uint64_t b = tokens.size();
  const int depth = config_.cost.pe_pipeline_depth;
  free_pes_ -= static_cast<std::uint32_t>(b);
  leaf_wave_.set(leaf);
  ++batches_;
  queries_ += b;

  // Function, one query at a time in BQB order (the recorded order): the Leader Check decides
  // how each is served, then its PE scans the Node Set or its leader's local list.
  const Plan plan = serve(tokens, leaf, now, batch.hits);

  // Timing. The batch's stream: the Leader Check (the leaf's leaders past the PEs), then the
  // Node Set for the exact scans, then each followed leader's list, back to back through the
  // array (a PE computes on its own group's entries only).
  std::uint64_t check_end = start;
  if (plan.max_checks > 0)
    check_end +=
        PeArray::stream_cycles(plan.max_checks, b, depth) + static_cast<std::uint64_t>(config_.cost.leader_check);
  std::uint64_t data_ready = start, stream = 0;
  if (plan.exact > 0) {
    // Node Set: from the Node Cache on a hit, else one burst from the Point Buffer.
    stream += n;
    const std::uint64_t set_bytes = n * sizeof(tlm_if::PointEntry);
    data_ready = start + static_cast<std::uint64_t>(config_.cost.node_cache_hit);
    if (!links_.cache.lookup(leaf, set_bytes)) {
      tlm_if::AccessProfile a;
      a.first_byte = tree_.leaf_address(leaf);
      a.bytes = set_bytes;
      data_ready = points.charge(now, a, clock_.period);
    }
  }
  // New leaders' lists are written to the Result Buffer (or DRAM) once their scan is done.
  const std::uint64_t scan_end = PeArray::stream_end(check_end, data_ready, n, plan.exact, depth);
  for (std::size_t i : plan.new_leaders) {
    LeaderBuffer::Leader& l = leader_buffer_.leader(leaf, i);
    l.ready = list_access(scan_end, l, true);
  }
  for (std::size_t i : plan.followed) {
    const LeaderBuffer::Leader& l = leader_buffer_.leader(leaf, i);
    stream += l.list_length;
    data_ready = std::max(data_ready, list_access(std::max(now, l.ready), l, false));
  }
  stream_batch(batch, leaf, now, start, check_end, data_ready, stream);
}

void SearchUnit::issue_followers(Batch& batch, std::uint64_t now) {
  // first_leaf, wait: the followers of one leader, parked until its list was written, stream
  // that list past their PEs (their Leader Check was made when they arrived).
  const std::vector<QueryToken>& tokens = batch.tokens;
  const std::uint32_t leaf = tokens.front().first_leaf;
  const LeaderBuffer::Leader& l = leader_buffer_.leader(leaf, tokens.front().follows);
  const std::uint64_t start = now + static_cast<std::uint64_t>(config_.cost.issue_cycle);
  ledger_.book(kIssue, now, start);
  free_pes_ -= static_cast<std::uint32_t>(tokens.size());
  leaf_wave_.set(leaf);
  ++batches_;
  const tlm_if::PointEntry* list = leader_buffer_.list(l);
  for (const QueryToken& t : tokens) {
    pe_array_.scan(t, list, l.list_length, batch.hits);
    distance_energy_ += l.list_length;
    links_.observer.follower_served(t.query, l.list_length);
  }
  const std::uint64_t data_ready = list_access(std::max(now, l.ready), l, false);
  stream_batch(batch, leaf, now, start, start, data_ready, l.list_length);
}

void SearchUnit::stream_batch(Batch& batch, std::uint32_t leaf, std::uint64_t now, std::uint64_t start,
                              std::uint64_t check_end, std::uint64_t data_ready, std::uint64_t stream) {
  const std::vector<QueryToken>& tokens = batch.tokens;
  const std::uint64_t b = tokens.size();
  const int depth = config_.cost.pe_pipeline_depth;
  // Result Buffer: each query's NN/kNN slot is read into its PE (written back at retire).
  if (!job_.radius()) data_ready = std::max(data_ready, results.charge(now, slot_access(tokens, false), clock_.period));
  const std::uint64_t compute_end = check_end + PeArray::stream_cycles(stream, b, depth);
  const std::uint64_t end = PeArray::stream_end(check_end, data_ready, stream, b, depth);
  // Busy: checks and streaming as the formulas say; stall: the stream waiting for its data
  // beyond that (the ledger counts a cycle once when batches of MQMN overlap).
  ledger_.book(kBusy, start, compute_end);
  ledger_.book(kSram, compute_end, end);
  pe_busy_cycles_ += b * (compute_end - start);
  pes_wave_.add_at(clock_, start, static_cast<std::int64_t>(b));
  pes_wave_.add_at(clock_, compute_end, -static_cast<std::int64_t>(b));
  links_.observer.activity(JobObserver::Activity::PeBusy, static_cast<std::uint32_t>(b), start, compute_end);
  links_.observer.activity(JobObserver::Activity::PeSramStall, static_cast<std::uint32_t>(b), compute_end, end);
  if (end > compute_end) {
    sram_pes_wave_.add_at(clock_, compute_end, static_cast<std::int64_t>(b));
    sram_pes_wave_.add_at(clock_, end, -static_cast<std::int64_t>(b));
  }
  links_.observer.su_batch(id_, leaf, tokens.data(), tokens.size(), now, end, stream);
  batch.end = end;
}

void SearchUnit::exact_scan(const QueryToken& t, std::uint32_t leaf, const tlm_if::PointEntry* set, std::uint32_t n,
                            std::vector<tlm_if::ResultRecord>& hits) {
  if (!job_.radius())  // the slot is next read by the query's next walk (which waits for it)
    links_.scans.scan(pe_array_, t, leaf, set, n);
  else if (job_.first_leaf && t.first_leaf != kNoLeaf)  // a first_leaf leader stages its list
    pe_array_.scan(t, set, n, hits, &links_.result_buffer.leader_staging().staged(t.slot));
  else
    links_.scans.scan_now(pe_array_, t, leaf, set, n, hits);
}

SearchUnit::Plan SearchUnit::serve(std::vector<QueryToken>& tokens, std::uint32_t leaf, std::uint64_t now,
                                   std::vector<tlm_if::ResultRecord>& hits) {
  Plan plan;
  const tlm_if::PointEntry* set = pe_array_.node_set(leaf);
  const auto n = static_cast<std::uint32_t>(tree_.leaf_size(leaf));
  for (QueryToken& t : tokens) {
    LeafVisit v;
    if (!job_.approximate || (job_.first_leaf && t.first_leaf != kNoLeaf)) {
      exact_scan(t, leaf, set, n, hits);  // exact search, or a first_leaf leader's later visits
      v.leaf_points = n;
      ++plan.exact;
    } else {
      const LeaderCheck::Decision d = leader_check_.decide(leader_buffer_, leaf, t.point, job_.thd2, job_.first_leaf);
      v.kind = d.kind;
      v.leader_checks = d.checks;
      plan.max_checks = std::max<std::uint64_t>(plan.max_checks, d.checks);
      if (job_.first_leaf) t.first_leaf = leaf;
      if (d.kind == LeafVisit::Kind::Follower && leader_buffer_.leader(leaf, d.leader).pending) {
        // wait: its leader is still searching: the follower parks with it, off the PEs and
        // the BE Query Buffer, until the leader's list is written.
        t.parked = true;
        QueryToken waiter = t;
        waiter.parked = false, waiter.finished = true, waiter.follows = static_cast<std::uint32_t>(d.leader);
        leader_buffer_.leader(leaf, d.leader).waiters.push_back(waiter);
      } else if (d.kind == LeafVisit::Kind::Follower) {
        const LeaderBuffer::Leader& l = leader_buffer_.leader(leaf, d.leader);
        pe_array_.scan(t, leader_buffer_.list(l), l.list_length, hits);  // not the leaf's box: a final list is anywhere
        v.follower_points = l.list_length;
        t.finished = job_.first_leaf;  // the authors' code: a follower does not backtrack
        if (std::find(plan.followed.begin(), plan.followed.end(), d.leader) == plan.followed.end())
          plan.followed.push_back(d.leader);
      } else if (d.kind == LeafVisit::Kind::Exact) {  // first_leaf: searches on, joins when done
        exact_scan(t, leaf, set, n, hits);
        v.leaf_points = n;
        ++plan.exact;
        if (job_.wait_for_leaders) {  // wait: a leader from now on, its list to come
          const bool taken = !leader_buffer_.full(leaf);
          if (taken) t.leader_entry = static_cast<std::uint32_t>(leader_buffer_.reserve(leaf, t.point));
          leader_check_.joined(taken);
          v.kind = taken ? LeafVisit::Kind::Leader : LeafVisit::Kind::LeaderBufferFull;
        }
      } else if (d.kind == LeafVisit::Kind::Leader) {
        local_.clear();
        pe_array_.scan(t, set, n, hits, &local_);
        plan.new_leaders.push_back(leader_buffer_.append(leaf, t.point, local_));
        v.leaf_points = n;
        ++plan.exact;
      } else {
        links_.scans.scan_now(pe_array_, t, leaf, set, n, hits);
        v.leaf_points = n;
        ++plan.exact;
      }
    }
    distance_energy_ += v.leaf_points + v.follower_points;
    links_.observer.bqb_waited(t.query, now - t.ready);
    links_.observer.leaf_scanned(t.query, t.leaf, v);
  }
  // The check stream reads the leaf's leaders once per batch (as many as the last check saw).
  leader_buffer_.read(plan.max_checks);
  return plan;
}

std::uint64_t SearchUnit::list_access(std::uint64_t at, const LeaderBuffer::Leader& l, bool write) {
  const std::uint64_t bytes = l.list_length * LeaderBuffer::kListEntryBytes;
  if (bytes == 0) return at;
  if (leader_buffer_.in_dram(l)) return links_.result_buffer.dram_transfer(at, bytes, write);
  tlm_if::AccessProfile a;
  a.write = write;
  a.first_byte = leader_buffer_.bank_address(l);
  a.bytes = bytes;
  return results.charge(at, a, clock_.period);
}

tlm_if::AccessProfile SearchUnit::slot_access(const std::vector<QueryToken>& tokens, bool write) {
  slot_addrs_.clear();
  for (const QueryToken& t : tokens) slot_addrs_.push_back(job_.result_slot_address(t.slot));
  tlm_if::AccessProfile a;
  a.write = write;
  a.scatter = slot_addrs_.data();
  a.scatter_size = static_cast<std::uint32_t>(job_.result_slot_bytes);
  a.scatter_count = static_cast<std::uint32_t>(slot_addrs_.size());
  a.bytes = tokens.size() * job_.result_slot_bytes;
  return a;
}

std::uint64_t SearchUnit::retire(Batch& batch) {
  // The PEs' insert stage writes NN/kNN slots back (posted) or streams the radius hits out.
  const std::uint64_t now = clock_.now();
  if (batch.written) return now;
  batch.written = true;
  if (!job_.radius()) {
    results.charge(now, slot_access(batch.tokens, true), clock_.period);  // posted
    for (const QueryToken& t : batch.tokens)
      if (t.finished && !t.parked) pe_array_.finish(t, batch.hits);  // a follower's list leaves from here
  }
  if (batch.hits.empty()) return now;
  const std::uint64_t accepted = links_.result_buffer.stream(now, batch.hits.data(), batch.hits.size());
  ledger_.book(kWriteback, now, accepted);
  return accepted;
}

}  // namespace tigris::hw
