// The accelerator's host-visible memory map and CSRs (docs/model.md, the host side). The host
// driver writes the tree image and queries into the buffer windows, programs the CSRs, writes
// CTRL.START, waits for the done interrupt and reads the result stream from the DRAM window.
#pragma once

#include <cstdint>

namespace tigris::tlm_if {

// Windows on the host target socket.
constexpr std::uint64_t kCsrBase = 0x0000'0000;
constexpr std::uint64_t kCsrSize = 0x1000;
constexpr std::uint64_t kPointBufferBase = 0x1000'0000;   // tree image (tree_image.hpp)
constexpr std::uint64_t kQueryBufferBase = 0x2000'0000;   // queries (QueryRecord)
constexpr std::uint64_t kWindowSize = 0x1000'0000;        // buffer windows: 256 MiB each
constexpr std::uint64_t kResultDramBase = 0x1'0000'0000;  // result stream written back to DRAM
constexpr std::uint64_t kResultDramSize = 0xF'0000'0000;  // up to 60 GiB of records

// CSRs: 32-bit registers at these byte offsets in the CSR window.
enum Csr : std::uint32_t {
  kCtrl = 0x00,         // write 1: start the job
  kStatus = 0x04,       // bit 0 busy, bit 1 done, bit 2 error (read); write 0 clears done
  kMode = 0x08,         // SearchMode
  kK = 0x0C,            // neighbours kept per query (NN: 1)
  kRadius2Bits = 0x10,  // r*r as float32 bits (radius mode)
  kNumPoints = 0x14,
  kNumQueries = 0x18,
  kTopHeight = 0x1C,
  kNumTopNodes = 0x20,    // 2^h - 1 entries at the start of the Point Buffer
  kNumLeaves = 0x24,      // 2^h; 0 when the image has no leaf directory (canonical tree)
  kLeafDirOffset = 0x28,  // byte offset of the leaf directory in the Point Buffer
  kResultBytesLo = 0x2C,  // bytes of result stream written to DRAM (read after done)
  kResultBytesHi = 0x30,
  kCyclesLo = 0x34,  // cycles from START to done
  kCyclesHi = 0x38,
  kErrorCode = 0x3C,
  kApprox = 0x40,          // approximate search: 0 off, 1 every leaf, 2 first leaf (wait), 3 first leaf (finished only)
  kApproxThd2Bits = 0x44,  // thd*thd as float32 bits: a query this close to a leader follows it
  kLeaderWidth = 0x48,     // R: entries in a NN/kNN leader's local result list
  kCsrCount = 0x4C / 4,
};

enum class SearchMode : std::uint32_t { NN = 0, KNN = 1, Radius = 2 };

enum StatusBits : std::uint32_t { kBusy = 1, kDone = 2, kError = 4 };

// One query in the Query Buffer: 12 bytes (x, y, z as float32).
struct QueryRecord {
  float x, y, z;
};
static_assert(sizeof(QueryRecord) == 12, "query records are packed");

// One record of the result stream: 12 bytes, little-endian.
struct ResultRecord {
  std::uint32_t query;
  std::uint32_t index;
  float dist2;
};
static_assert(sizeof(ResultRecord) == 12, "result records are packed");

}  // namespace tigris::tlm_if
