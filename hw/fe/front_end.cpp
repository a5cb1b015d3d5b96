#include "front_end.hpp"

#include <stdexcept>
#include <string>

namespace tigris::hw {

FrontEnd::FrontEnd(sc_core::sc_module_name name, const AcceleratorConfig& config, const JobDescriptor& job,
                   DistributionNetwork& qdn, ResultBuffer& result_buffer, EnergyMeter& meter, JobObserver& observer,
                   Scheduler& scheduler, ScanService& scans, bool reverse_construction)
    : sc_module(name), Scheduler::Client(Scheduler::kFrontEnd, 0), job_(job),
      observer_(observer), clock_{config.period()}, scheduler_(scheduler), stall_(config.stall, "fqq", stats_) {
  // One walk engine serves every RU: an activation is walked whole when it starts, and an RU
  // keeps nothing in the engine between activations (its query's state is in the token and
  // the buffers).
  const RecursionUnitModels::Entry* model = RecursionUnitModels::find(config.fe.recursion_unit_model);
  if (!model) throw std::invalid_argument("fe.recursion_unit_model: no model '" + config.fe.recursion_unit_model + "'");
  engine_ = model->make(config);
  if (!engine_)
    throw std::logic_error("fe.recursion_unit_model '" + config.fe.recursion_unit_model + "' made no engine");
  const RecursionUnit::Links links{*this, qdn, result_buffer, meter, observer, scheduler, scans, *engine_};
  const int n = config.fe.recursion_units;
  rus.resize(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const int i = reverse_construction ? n - 1 - k : k;
    rus[static_cast<std::size_t>(i)] =
        std::make_unique<RecursionUnit>(("ru" + std::to_string(i)).c_str(), i, config, job, links);
  }
  for (auto& ru : rus) stats_.add(ru->stats());
  scheduler_.add(*this);
}

void FrontEnd::start(std::function<void(std::uint64_t)> on_all_done) {
  on_all_done_ = std::move(on_all_done);
  stall_.start();
  fqq_.clear();
  fqq_.reserve(job_.slots);  // a slot holds one token at a time: the FQQ never holds more
  next_query_ = finished_ = 0;
  records_in_flight_ = 0;
  in_flight_.set(job_.slots);
  idle_rus_.clear();
  for (auto it = rus.rbegin(); it != rus.rend(); ++it) {
    (*it)->start_job();
    idle_rus_.push_back(it->get());
  }
  free_slots_.clear();
  for (std::uint32_t s = job_.slots; s-- > 0;) free_slots_.push_back(s);
  const std::uint64_t now = clock_.now();
  while (admit(now)) {
  }
  if (job_.num_queries == 0 && on_all_done_) on_all_done_(now);
}

bool FrontEnd::admit(std::uint64_t cycle) {
  if (free_slots_.empty() || next_query_ >= job_.num_queries) return false;
  QueryToken t;
  t.query = next_query_++;
  t.slot = free_slots_.back();
  free_slots_.pop_back();
  t.ready = cycle;
  observer_.query_admitted(t.query, cycle);
  push(t);
  return true;
}

void FrontEnd::push(const QueryToken& token) {
  fqq_.push_back(token);
  fqq_max_.max(fqq_.size());
  fqq_wave_.set(fqq_.size());
  scheduler_.now(*this);
}

void FrontEnd::reinsert(QueryToken token, std::uint64_t ready_cycle) {
  if (drop_reinserted_) return;
  token.ready = ready_cycle;
  push(token);
}

void FrontEnd::ru_idle(RecursionUnit& ru) {
  idle_rus_.push_back(&ru);
  scheduler_.now(*this);
}

void FrontEnd::query_finished(const QueryToken& token, std::uint64_t cycle) {
  ++finished_;
  finished_wave_.set(finished_);
  observer_.query_finished(token.query, cycle);
  if (progress_ && finished_ % 4096 == 0) progress_(finished_, job_.num_queries);
  free_slots_.push_back(token.slot);
  admit(cycle);
  check_all_done(cycle);
}

void FrontEnd::leader_record_delivered(std::uint64_t cycle) {
  --records_in_flight_;
  check_all_done(cycle);
}

void FrontEnd::check_all_done(std::uint64_t cycle) {
  if (finished_ == job_.num_queries && records_in_flight_ == 0 && on_all_done_) on_all_done_(cycle);
}

void FrontEnd::dispatch() {
  const std::uint64_t now = clock_.now();
  while (!idle_rus_.empty() && !fqq_.empty()) {
    if (fqq_.front().ready > now) {
      scheduler_.at(*this, fqq_.front().ready);
      return;
    }
    if (const std::uint64_t d = stall_.draw()) {  // the hand-off to an RU is held back
      fqq_.front().ready = now + d;
      scheduler_.at(*this, now + d);
      return;
    }
    RecursionUnit* ru = idle_rus_.back();
    idle_rus_.pop_back();
    const QueryToken t = fqq_.front();
    fqq_.pop_front();
    // The FQQ is served in order: warm the host's cache for the query a few dispatches ahead
    // (its token itself a few more ahead, as the query's data is found through it).
    if (fqq_.size() > 2 * kPrefetchAhead) ScanService::read_soon(&fqq_[2 * kPrefetchAhead], sizeof(QueryToken));
    if (fqq_.size() > kPrefetchAhead) ru->walk_soon(fqq_[kPrefetchAhead]);
    fqq_wave_.set(fqq_.size());
    ru->start(t);
  }
}

}  // namespace tigris::hw
