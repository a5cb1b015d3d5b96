// The buffers' bookkeeping against naive models: the bank calendar (its rows, runs, row cache,
// fast path and many-word bookings are for speed only, so they must book exactly what one-at-a-time
// reservation on a plain set of busy cycles books), the Result Buffer's heap-ordered slots and the
// FE Query Queue's ring.
#include <catch2/catch.hpp>

#include <algorithm>
#include <deque>
#include <random>
#include <set>
#include <vector>

#include "hw/host/fifo_ring.hpp"
#include "hw/mem/bank_calendar.hpp"
#include "hw/mem/fast_divider.hpp"
#include "hw/mem/result_slots.hpp"

using namespace tigris;

namespace {

struct NaiveCalendar {
  std::vector<std::set<std::uint64_t>> busy;
  std::uint64_t next_free(std::uint32_t bank, std::uint64_t c) const {
    while (busy[bank].count(c)) ++c;
    return c;
  }
  std::uint64_t reserve(std::uint32_t bank, std::uint64_t c) {
    c = next_free(bank, c);
    busy[bank].insert(c);
    return c;
  }
};

}  // namespace

TEST_CASE("bank calendar books what one-at-a-time reservation on a set of busy cycles books", "[hw][memory]") {
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    std::mt19937_64 rng(seed);
    const std::uint32_t banks = 1 + seed % 5;
    hw::BankCalendar cal(banks);
    NaiveCalendar ref{std::vector<std::set<std::uint64_t>>(banks)};
    std::uint64_t now = 0;
    for (int op = 0; op < 4000; ++op) {
      now += rng() % 8;  // time moves on; bookings reach far ahead, so rows recycle and grow
      const std::uint32_t bank = static_cast<std::uint32_t>(rng() % banks);
      const std::uint64_t at = now + rng() % (seed % 2 ? 300 : 9000);
      INFO("seed " << seed << " op " << op << " bank " << bank << " at " << at);
      switch (rng() % 6) {
        case 0: REQUIRE(cal.reserve(bank, at, now) == ref.reserve(bank, at)); break;
        case 4: {  // one word in each of `count` banks from `bank` on, wrapping
          const auto count = static_cast<std::uint32_t>(1 + rng() % banks);
          std::uint64_t finish = at + 1;
          std::uint32_t last = bank;  // the bank served last (the first of equals)
          for (std::uint32_t i = 0; i < count; ++i) {
            const std::uint64_t served = ref.reserve((bank + i) % banks, at) + 1;
            if (served > finish) finish = served, last = (bank + i) % banks;
          }
          std::uint32_t critical = banks;
          REQUIRE(cal.reserve_span(bank, count, at, now, critical) == finish);
          REQUIRE(critical == last);
          break;
        }
        case 5:  // the fast path books exactly when the bank is free at `at` (if it can tell)
          if (cal.try_book(bank, at)) {
            REQUIRE(ref.next_free(bank, at) == at);
            ref.busy[bank].insert(at);
          }
          break;
        case 1: {
          const std::uint64_t m = 1 + rng() % 150;
          std::uint64_t t = at, last = 0;
          for (std::uint64_t i = 0; i < m; ++i) t = (last = ref.reserve(bank, t)) + 1;
          REQUIRE(cal.reserve_n(bank, at, m, now) == last);
          break;
        }
        case 2: REQUIRE(cal.next_free(bank, at, now) == ref.next_free(bank, at)); break;
        default: {
          const std::uint64_t c = ref.next_free(bank, at);
          cal.book(bank, cal.next_free(bank, at, now), now);
          ref.busy[bank].insert(c);
        }
      }
    }
  }
}

TEST_CASE("Result Buffer slots: the k best in canonical order, bound = k-th best, for small and large k",
          "[hw][memory]") {
  for (std::uint32_t k : {1u, 2u, 5u, 64u, 1000u}) {
    std::mt19937 rng(k);
    const std::uint32_t slots = 3;
    std::vector<std::uint8_t> memory(hw::ResultSlots::slot_bytes(k) * slots);
    hw::ResultSlots view(memory.data(), k);
    std::vector<std::vector<Neighbor>> seen(slots);
    for (std::uint32_t s = 0; s < slots; ++s) view.clear(s);
    for (int i = 0; i < 5000; ++i) {
      const std::uint32_t s = rng() % slots;
      // Few distinct distances, so ties are broken by index.
      const Neighbor n{static_cast<std::uint32_t>(i), static_cast<float>(rng() % 97)};
      view.insert(s, n);
      seen[s].push_back(n);
      if (i % 37 != 0) continue;
      std::vector<Neighbor> best = seen[s];
      std::sort(best.begin(), best.end(), closer);
      const float bound = best.size() < k ? kInfinity : best[k - 1].dist2;
      REQUIRE(view.bound(s) == bound);
    }
    for (std::uint32_t s = 0; s < slots; ++s) {
      std::vector<Neighbor> best = seen[s];
      std::sort(best.begin(), best.end(), closer);
      best.resize(std::min<std::size_t>(best.size(), k));
      view.finish(s);
      REQUIRE(view.count(s) == best.size());
      for (std::uint32_t i = 0; i < best.size(); ++i) {
        CHECK(view.entries(s)[i].index == best[i].index);
        CHECK(view.entries(s)[i].dist2 == best[i].dist2);
      }
    }
  }
}

TEST_CASE("FifoRing: first in, first out across wrap-arounds and growth, as a std::deque", "[hw][memory]") {
  hw::FifoRing<std::uint32_t> ring;
  std::deque<std::uint32_t> model;
  std::mt19937 rng(7);
  ring.reserve(5);  // rounded up; pushes beyond it grow the ring
  std::uint32_t next = 0;
  for (int step = 0; step < 20000; ++step) {
    // Phases that fill (growing past every capacity) and drain (wrapping the head around).
    const bool fill = (step / 2500) % 2 == 0;
    if (model.empty() || rng() % 4 < (fill ? 3u : 1u)) {
      ring.push_back(next);
      model.push_back(next++);
    } else {
      REQUIRE(ring.front() == model.front());
      ring.pop_front();
      model.pop_front();
    }
    REQUIRE(ring.size() == model.size());
    REQUIRE(ring.empty() == model.empty());
    if (!model.empty()) {
      const std::size_t i = rng() % model.size();
      REQUIRE(ring[i] == model[i]);
    }
  }
  ring.clear();
  CHECK(ring.empty());
  ring.push_back(42);
  CHECK(ring.front() == 42);
}

TEST_CASE("FastDivider: n / d exactly, by multiplications below 2^32 and a division beyond", "[hw][memory]") {
  std::mt19937_64 rng(11);
  std::vector<std::uint64_t> divisors = {1, 2, 3, 7, 12, 24, 96, 1000, 65535, 65536, 4294967295ULL, 4294967296ULL};
  for (int i = 0; i < 200; ++i) divisors.push_back(1 + rng() % 4294967295ULL);
  for (int i = 0; i < 50; ++i) divisors.push_back(1 + rng() % 5000);
  for (std::uint64_t d : divisors) {
    const hw::FastDivider div(d);
    std::vector<std::uint64_t> ns = {0, 1, d - 1, d, d + 1, 2 * d - 1, 4294967295ULL, 4294967296ULL, ~std::uint64_t{0}};
    for (int i = 0; i < 2000; ++i) ns.push_back(rng() % 4294967296ULL);
    for (int i = 0; i < 200; ++i) ns.push_back(rng());
    for (std::uint64_t n : ns) {
      INFO(n << " / " << d);
      REQUIRE(div(n) == n / d);
    }
  }
}
