#include "banked_sram.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace tigris::hw {

namespace {

// The paper's name of a global buffer, for the statistics schema.
std::string title(const std::string& name) {
  if (name == "points") return "Point Buffer";
  if (name == "queries") return "Query Buffer";
  if (name == "query_stack") return "Query Stack Buffer";
  if (name == "results") return "Result Buffer";
  return name;
}

}  // namespace

BankedSram::BankedSram(sc_core::sc_module_name name, const SramConfig& config, Clock clock, EnergyMeter& meter,
                       const AcceleratorConfig::Stall& stall)
    : sc_module(name), socket("socket"), config_(config), clock_(clock), data_(config.bytes),
      word_bytes_(static_cast<std::uint64_t>(config.word_bytes)), num_banks_(static_cast<std::uint64_t>(config.banks)),
      word_shift_((word_bytes_ & (word_bytes_ - 1)) == 0 ? __builtin_ctzll(word_bytes_) : -1),
      bank_mask_((num_banks_ & (num_banks_ - 1)) == 0 ? num_banks_ - 1 : 0), word_div_(word_bytes_),
      bank_div_(num_banks_), lanes_(static_cast<std::uint64_t>(std::min(config.banks, config.ports))),
      lanes_shift_((lanes_ & (lanes_ - 1)) == 0 ? __builtin_ctzll(lanes_) : -1),
      banks_(static_cast<std::uint32_t>(config.banks)), ports_bind_(config.ports < config.banks),
      word_in_row_(!ports_bind_ && word_shift_ >= 0 && bank_mask_ != 0),
      ports_(static_cast<std::uint32_t>(config.ports)),
#ifdef TIGRIS_CHECK_SRAM
      reference_(word_bytes_, num_banks_, static_cast<std::uint64_t>(config.ports)),
#endif
      stats_(basename(), "buffer", title(basename())),
      read_energy_(meter.line(std::string("sram.") + basename() + ".read_bytes", EnergyMeter::Component::SramRead,
                              meter.table().sram_price(config.bytes, config.banks, false))),
      write_energy_(meter.line(std::string("sram.") + basename() + ".write_bytes", EnergyMeter::Component::SramWrite,
                               meter.table().sram_price(config.bytes, config.banks, true))),
      stall_(stall, basename(), stats_) {
  socket.register_b_transport(this, &BankedSram::b_transport);
  socket.register_get_direct_mem_ptr(this, &BankedSram::get_direct_mem_ptr);
  socket.register_transport_dbg(this, &BankedSram::transport_dbg);
}

std::uint64_t BankedSram::charge(std::uint64_t start, const tlm_if::AccessProfile& a) {
  if (a.pipeline) return charge_in_order(start, a);
  std::uint32_t bank;  // a burst within one word (a NN slot, a query record): as charge_one()
  if (!a.scatter && in_one_word(a.first_byte, a.bytes, bank)) return charge_word(start, bank, a.bytes, a.write);
  const std::uint64_t now = std::min(start, clock_.now());
  // Each bank serves its accesses one a cycle, in the first free cycles of its calendar.
  std::uint64_t n = 0, finish = start;
  std::uint32_t critical = 0;  // the bank served last
  if (a.scatter) {
    for (std::uint32_t i = 0; i < a.scatter_count; ++i) {
      const auto [first, words] = words_of(a.scatter[i], a.scatter_size);
      std::uint32_t c = 0;
      const std::uint64_t f = reserve_words(first, words, start, now, c);
      if (words && f > finish) finish = f, critical = c;
      n += words;
    }
  } else {
    const auto [first, words] = words_of(a.first_byte, a.bytes);
    n = words;
    finish = std::max(finish, reserve_words(first, words, start, now, critical));
  }
  check(start, a, now, finish);
  if (n == 0) return start;
  const std::uint64_t ideal =
      start + (lanes_shift_ >= 0 ? (n + lanes_ - 1) >> lanes_shift_ : (n + lanes_ - 1) / lanes_);
  conflict_cycles_ += finish - ideal;
  bank_conflicts_[critical] += finish - ideal;
  count(a.write, n, a.bytes);
  return finish + static_cast<std::uint64_t>(config_.latency_cycles) + stall_.draw();
}

std::uint64_t BankedSram::reserve_words(std::uint64_t first, std::uint64_t words, std::uint64_t cycle,
                                        std::uint64_t now, std::uint32_t& critical) {
  critical = words ? bank_of(first) : 0;
  // Word i is in bank (first + i) mod banks, so bank i's share is every banks-th word.
  if (!ports_bind_ && words <= 4 && words <= num_banks_) {
    // A slot or a record: word by word, most often in the calendar's current row.
    std::uint64_t finish = cycle;
    for (std::uint64_t w = first; w < first + words; ++w) {
      const std::uint32_t bank = bank_of(w);
      ++bank_accesses_[bank];
      const std::uint64_t served = (banks_.try_book(bank, cycle) ? cycle : banks_.reserve(bank, cycle, now)) + 1;
      if (served > finish) finish = served, critical = bank;
    }
    return finish;
  }
  if (!ports_bind_ && words <= num_banks_) {  // one word a bank: two runs of neighbouring banks
    if (words == 0) return cycle;
    const std::uint32_t b = bank_of(first);
    const std::uint64_t head = std::min<std::uint64_t>(words, num_banks_ - b), tail = words - head;
    std::uint64_t* accesses = &bank_accesses_[0];
    for (std::uint64_t i = 0; i < head; ++i) ++accesses[b + i];  // (loops the compiler vectorizes)
    for (std::uint64_t i = 0; i < tail; ++i) ++accesses[i];
    return std::max(cycle, banks_.reserve_span(b, static_cast<std::uint32_t>(words), cycle, now, critical));
  }
  // The first `words mod banks` banks take one word more than the others.
  const std::uint64_t touched = std::min(words, num_banks_);
  const std::uint64_t base_share = words / num_banks_, extra = words % num_banks_;
  for (std::uint64_t i = 0, b = bank_of(first); i < touched; ++i, b = b + 1 == num_banks_ ? 0 : b + 1)
    bank_accesses_[b] += base_share + (i < extra ? 1 : 0);
  std::uint32_t b = bank_of(first);
  std::uint64_t finish = cycle;
  for (std::uint64_t i = 0; i < touched; ++i, b = b + 1 == num_banks_ ? 0 : b + 1) {
    const std::uint64_t share = base_share + (i < extra ? 1 : 0);
    std::uint64_t t = cycle;
    if (!ports_bind_)
      t = (share == 1 ? banks_.reserve(b, t, now) : banks_.reserve_n(b, t, share, now)) + 1;
    else
      for (std::uint64_t w = 0; w < share; ++w) t = reserve(b, t, now) + 1;
    if (t > finish) finish = t, critical = b;
  }
  return finish;
}

std::uint64_t BankedSram::charge_in_order(std::uint64_t start, const tlm_if::AccessProfile& a) {
  const std::uint64_t now = std::min(start, clock_.now());
  std::uint64_t stall = 0, last = start, n = 0;
  // Accesses within one word (a walk's nodes and stack entries) take a short path that books
  // most of them in the calendar's current row.
  for (const tlm_if::PipelineAccess *p = a.pipeline, *end = p + a.pipeline_count; p != end; ++p) {
    // The access's words issue together; the pipeline goes on once the last one is served.
    const std::uint64_t t = start + p->issue_offset + stall;
    const std::uint32_t size = p->bytes;
    if (word_in_row_ && size > 0 && (p->byte & (word_bytes_ - 1)) + size <= word_bytes_) {
      const auto bank = static_cast<std::uint32_t>((p->byte >> word_shift_) & bank_mask_);
      const std::uint64_t served = banks_.try_book(bank, t) ? t : banks_.reserve(bank, t, now);
      ++bank_accesses_[bank];
      bank_conflicts_[bank] += served - t;
      stall += served - t;
      last = served + 1;
      ++n;
      continue;
    }
    const auto [first, words] = words_of(p->byte, size);
    std::uint64_t served = t;
    std::uint32_t critical = words ? bank_of(first) : 0;
    for (std::uint64_t w = first; w < first + words; ++w) {
      const std::uint32_t bank = bank_of(w);
      ++bank_accesses_[bank];
      const std::uint64_t s = reserve(bank, t, now);
      if (s > served) served = s, critical = bank;
    }
    bank_conflicts_[critical] += served - t;
    stall += served - t;
    last = served + 1;
    n += words;
  }
  check(start, a, now, last);
  conflict_cycles_ += stall;
  count(a.write, n, a.bytes);
  return a.pipeline_count ? last + static_cast<std::uint64_t>(config_.latency_cycles) + stall_.draw() : start;
}

std::uint64_t BankedSram::charge_one_profiled(std::uint64_t start, std::uint64_t byte, std::uint32_t bytes,
                                              bool write) {
  const tlm_if::PipelineAccess one{byte, bytes, 0};
  return charge_in_order(start, tlm_if::AccessProfile::single(one, write));
}

void BankedSram::check([[maybe_unused]] std::uint64_t start, [[maybe_unused]] const tlm_if::AccessProfile& a,
                       [[maybe_unused]] std::uint64_t now, [[maybe_unused]] std::uint64_t served) {
#ifdef TIGRIS_CHECK_SRAM
  const std::uint64_t want = reference_.charge(start, a, now);
  if (want == served) return;
  std::fprintf(stderr,
               "TIGRIS_CHECK_SRAM: %s: an access from cycle %llu (%s, %s, %llu bytes) was served by cycle %llu; "
               "one-at-a-time booking serves it by cycle %llu\n",
               name(), static_cast<unsigned long long>(start), a.write ? "write" : "read",
               a.pipeline  ? "pipeline"
               : a.scatter ? "scatter"
                           : "burst",
               static_cast<unsigned long long>(a.bytes), static_cast<unsigned long long>(served),
               static_cast<unsigned long long>(want));
  std::abort();
#endif
}

void BankedSram::b_transport(int, tlm::tlm_generic_payload& trans, sc_core::sc_time& delay) {
  const std::uint64_t now = Clock::time_value(), period = clock_.period.value();
  const std::uint64_t start = (now + delay.value()) / period;
  if (trans.get_command() == tlm::TLM_IGNORE_COMMAND) {
    tlm_if::AccessProfile* a = nullptr;
    trans.get_extension(a);
    if (a) delay = sc_core::sc_time::from_value(charge(start, *a) * period - now);
    trans.set_response_status(tlm::TLM_OK_RESPONSE);
    return;
  }
  const std::uint64_t addr = trans.get_address();
  const std::uint64_t len = trans.get_data_length();
  if (addr > data_.size() || len > data_.size() - addr) {
    trans.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
    return;
  }
  if (trans.get_byte_enable_ptr() != nullptr) {
    trans.set_response_status(tlm::TLM_BYTE_ENABLE_ERROR_RESPONSE);
    return;
  }
  const bool write = trans.get_command() == tlm::TLM_WRITE_COMMAND;
  if (write)
    std::memcpy(data_.data() + addr, trans.get_data_ptr(), len);
  else
    std::memcpy(trans.get_data_ptr(), data_.data() + addr, len);
  tlm_if::AccessProfile burst;
  burst.write = write;
  burst.first_byte = addr;
  burst.bytes = len;
  delay = sc_core::sc_time::from_value(charge(start, burst) * period - now);
  trans.set_dmi_allowed(true);
  trans.set_response_status(tlm::TLM_OK_RESPONSE);
}

bool BankedSram::get_direct_mem_ptr(int, tlm::tlm_generic_payload& trans, tlm::tlm_dmi& dmi) {
  tlm_if::TimingHandle* handle = nullptr;
  trans.get_extension(handle);
  if (handle) handle->target = this;
  dmi.allow_read_write();
  dmi.set_dmi_ptr(data_.data());
  dmi.set_start_address(0);
  dmi.set_end_address(data_.empty() ? 0 : data_.size() - 1);
  dmi.set_read_latency(config_.latency_cycles * clock_.period);
  dmi.set_write_latency(clock_.period);
  return true;
}

unsigned int BankedSram::transport_dbg(int, tlm::tlm_generic_payload& trans) {
  const std::uint64_t addr = trans.get_address();
  if (addr >= data_.size()) return 0;
  const unsigned int len =
      static_cast<unsigned int>(std::min<std::uint64_t>(trans.get_data_length(), data_.size() - addr));
  if (trans.get_command() == tlm::TLM_WRITE_COMMAND)
    std::memcpy(data_.data() + addr, trans.get_data_ptr(), len);
  else if (trans.get_command() == tlm::TLM_READ_COMMAND)
    std::memcpy(trans.get_data_ptr(), data_.data() + addr, len);
  return len;
}

}  // namespace tigris::hw
