// An SRAM's storage: zeros that cost nothing until touched. A vector would write every byte
// at construction (8 MB for the paper's buffers, most of a small job's set-up time); an
// anonymous mapping leaves the zeroing to the kernel, page by page, as the job first writes.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <new>

namespace tigris::hw {

class ZeroedBytes {
 public:
  explicit ZeroedBytes(std::size_t bytes) : size_(bytes) {
    if (bytes == 0) return;
    void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    data_ = static_cast<std::uint8_t*>(p);
    // Huge pages where the kernel allows them: fewer faults and TLB misses in a large job (as
    // glibc's malloc does for the rest of `tigris`, docs/performance.md "Huge pages").
    madvise(p, bytes, MADV_HUGEPAGE);
  }
  ~ZeroedBytes() {
    if (data_) munmap(data_, size_);
  }
  ZeroedBytes(const ZeroedBytes&) = delete;
  ZeroedBytes& operator=(const ZeroedBytes&) = delete;

  std::uint8_t* data() { return data_; }
  const std::uint8_t* data() const { return data_; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }

 private:
  std::uint8_t* data_ = nullptr;
  std::size_t size_;
};

}  // namespace tigris::hw
