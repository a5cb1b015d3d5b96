// Shared by the fuzz targets: the entry point's name, the wrong-read check, the byte source the
// structure-aware generators draw from.
//
// Each target is one file defining TIGRIS_FUZZ_ENTRY (LLVMFuzzerTestOneInput under libFuzzer,
// tigris_fuzz_<target> in the normal build's fuzz_corpus_regression, which replays the corpus
// through every target). A target returns normally on a clean read or a clean error and stops
// the program on anything else: an exception of an unexpected type escapes, a wrong read calls
// fuzz_wrong_read() (__builtin_trap under libFuzzer: reported as a crash with the input saved).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#ifndef TIGRIS_FUZZ_ENTRY
#define TIGRIS_FUZZ_ENTRY LLVMFuzzerTestOneInput
#endif

namespace tigris_fuzz {

// A wrong read: the reader accepted the input but returned something else than the input
// holds. Prints why (stderr), then traps.
[[noreturn]] inline void wrong_read(const char* target, const std::string& why) {
  std::fprintf(stderr, "WRONG READ [%s]: %s\n", target, why.c_str());
  std::fflush(stderr);
  __builtin_trap();
}

// A float's bit pattern: "read back exactly" means bit for bit (NaN, -0 included).
inline std::uint32_t float_bits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

// A clean error names its source first ("label: ..." or "label:LINE: ...").
inline bool names_source(const std::string& message, const std::string& label) {
  return message.compare(0, label.size(), label) == 0 && message.size() > label.size() && message[label.size()] == ':';
}

// Draws values from the fuzzer's bytes; past the end every draw is 0 (so every input is usable
// and the generated file only depends on the bytes read).
class ByteSource {
 public:
  ByteSource(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  std::uint64_t bits(int n) {  // n <= 64 random bits
    std::uint64_t v = 0;
    for (int k = 0; k < n; k += 8) v = (v << 8) | byte();
    return n >= 64 ? v : v & ((std::uint64_t{1} << n) - 1);
  }
  // Uniform-ish in [lo, hi].
  std::uint64_t range(std::uint64_t lo, std::uint64_t hi) {
    if (hi <= lo) return lo;
    const std::uint64_t span = hi - lo;
    const std::uint64_t r = span < 0xFF ? byte() : span < 0xFFFF ? bits(16) : bits(64);
    return span == ~std::uint64_t{0} ? r : lo + r % (span + 1);
  }
  bool flag() { return byte() & 1; }
  bool chance(int percent) { return byte() % 100 < static_cast<unsigned>(percent); }
  std::size_t remaining() const { return size_ - pos_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

}  // namespace tigris_fuzz
