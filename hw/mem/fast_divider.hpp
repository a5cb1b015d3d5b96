// n / d for a divisor fixed at construction, by multiplications instead of a division (a
// buffer's word size and bank count that are not powers of two, e.g. the Query Buffer's
// 12-byte words: a division per access costs more than booking it). Exact for n and d below
// 2^32 (Lemire, Kaser and Kurz, "Faster remainder by direct computation", 2019), with
// M = ceil(2^64 / d) and n / d = the high 64 bits of M * n; a plain division beyond.
#pragma once

#include <cstdint>

namespace tigris::hw {

class FastDivider {
 public:
  explicit FastDivider(std::uint64_t d) : d_(d), m_(d >= 1 && d < kLimit ? ~std::uint64_t{0} / d + 1 : 0) {}
  std::uint64_t operator()(std::uint64_t n) const {
    if (m_ == 0 || n >= kLimit) return n / d_;
    // The high 64 bits of m_ * n, from 32-bit halves (n < 2^32, so no sum overflows).
    const std::uint64_t hi = m_ >> 32, lo = m_ & 0xffffffffu;
    return (hi * n + ((lo * n) >> 32)) >> 32;
  }

 private:
  static constexpr std::uint64_t kLimit = std::uint64_t{1} << 32;
  std::uint64_t d_, m_;
};

}  // namespace tigris::hw
