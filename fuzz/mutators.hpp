// libFuzzer custom mutators of the PLY and PCD targets (only under libFuzzer): besides the
// ordinary byte mutations (guided by the dictionaries ply.dict, pcd.dict) they
// - turn a generator input (first byte 0) into the file it generates, so the byte mutations
//   then start from a valid, unusual file (every type, lists before x/y/z, big-endian, ...);
// - edit a file's header line by line: swap, repeat or drop a line, put a header keyword or
//   type name in place of a word, insert a line of the format's grammar.
#pragma once

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "cloud_gen.hpp"

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

namespace tigris_fuzz {

inline std::size_t put(const std::string& bytes, std::uint8_t* data, std::size_t max_size, std::size_t fallback) {
  if (bytes.empty() || bytes.size() > max_size) return fallback;
  std::memcpy(data, bytes.data(), bytes.size());
  return bytes.size();
}

inline std::size_t structured_mutate(std::uint8_t* data, std::size_t size, std::size_t max_size, unsigned int seed,
                                     Generated (*generate)(ByteSource&), const char* header_end,
                                     const std::vector<std::string>& words, const std::vector<std::string>& lines) {
  std::mt19937 rng(seed);
  const unsigned r = rng() % 16;
  if (size > 0 && data[0] == 0 && r < 3) {
    ByteSource src(data + 1, size - 1);
    const std::size_t n = put(generate(src).bytes, data, max_size, 0);
    if (n > 0) return n;
  } else if (size > 0 && data[0] != 0 && r < 7) {
    const std::string file(reinterpret_cast<const char*>(data), size);
    std::size_t end = file.find(header_end);
    end = end == std::string::npos ? std::min<std::size_t>(file.size(), 2048) : end;
    std::vector<std::string> hl;
    std::size_t pos = 0;
    while (pos < end) {
      const std::size_t nl = file.find('\n', pos);
      const std::size_t stop = nl == std::string::npos || nl >= end ? end : nl + 1;
      hl.push_back(file.substr(pos, stop - pos));
      pos = stop;
    }
    if (!hl.empty()) {
      const std::size_t a = rng() % hl.size(), b = rng() % hl.size();
      switch (rng() % 5) {
        case 0: std::swap(hl[a], hl[b]); break;
        case 1: hl.insert(hl.begin() + static_cast<std::ptrdiff_t>(a), hl[b]); break;
        case 2: hl.erase(hl.begin() + static_cast<std::ptrdiff_t>(a)); break;
        case 3: {  // a word of line a becomes a grammar word
          std::string& l = hl[a];
          std::vector<std::size_t> starts;
          for (std::size_t k = 0; k < l.size(); ++k)
            if (l[k] != ' ' && l[k] != '\n' && l[k] != '\r' && (k == 0 || l[k - 1] == ' ')) starts.push_back(k);
          if (!starts.empty()) {
            const std::size_t s0 = starts[rng() % starts.size()];
            std::size_t s1 = s0;
            while (s1 < l.size() && l[s1] != ' ' && l[s1] != '\n' && l[s1] != '\r') ++s1;
            l.replace(s0, s1 - s0, words[rng() % words.size()]);
          }
          break;
        }
        default: hl.insert(hl.begin() + static_cast<std::ptrdiff_t>(a), lines[rng() % lines.size()] + "\n"); break;
      }
      std::string out;
      for (const std::string& l : hl) out += l;
      out += file.substr(end);
      const std::size_t n = put(out, data, max_size, 0);
      if (n > 0) return n;
    }
  }
  return LLVMFuzzerMutate(data, size, max_size);
}

}  // namespace tigris_fuzz
