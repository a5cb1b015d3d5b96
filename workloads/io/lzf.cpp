#include "lzf.hpp"

namespace tigris {

// The format: a control byte c. c < 32: a literal run of c + 1 bytes follows. Otherwise a back
// reference: length (c >> 5) + 2, or when c >> 5 == 7, 7 + next byte + 2; offset
// ((c & 31) << 8) + next byte + 1 bytes back from the current output position. A reference may
// overlap the bytes it produces (copied byte by byte).
long lzf_decompress(const unsigned char* in, std::size_t in_size, unsigned char* out, std::size_t out_capacity) {
  std::size_t ip = 0, op = 0;
  while (ip < in_size) {
    const unsigned int ctrl = in[ip++];
    if (ctrl < 32) {
      const std::size_t len = ctrl + 1u;
      if (len > in_size - ip || len > out_capacity - op) return -1;
      for (std::size_t k = 0; k < len; ++k) out[op + k] = in[ip + k];
      ip += len;
      op += len;
    } else {
      std::size_t len = ctrl >> 5;
      if (ip >= in_size) return -1;
      if (len == 7) {
        len += in[ip++];
        if (ip >= in_size) return -1;
      }
      len += 2;
      const std::size_t back = ((static_cast<std::size_t>(ctrl & 0x1Fu)) << 8) + in[ip++] + 1;
      if (back > op || len > out_capacity - op) return -1;
      for (std::size_t k = 0; k < len; ++k, ++op) out[op] = out[op - back];
    }
  }
  return static_cast<long>(op);
}

}  // namespace tigris
