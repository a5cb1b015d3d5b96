// LZF decompression (Marc Lehmann's liblzf format), as PCD's binary_compressed data uses it.
#pragma once

#include <cstddef>

namespace tigris {

// Decompresses [in, in + in_size) into [out, out + out_capacity). Returns the number of bytes
// written, or -1 on corrupt input: a back reference before the start of the output, a run that
// passes the end of the input, or output that would not fit. Never reads or writes out of
// bounds.
long lzf_decompress(const unsigned char* in, std::size_t in_size, unsigned char* out, std::size_t out_capacity);

}  // namespace tigris
