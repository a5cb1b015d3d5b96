// Structure-aware generators of valid PLY and PCD files for the fuzz targets: the fuzzer's bytes
// choose the format variant, element/field order, every property type and list, the line ends,
// comments and the values; the generator returns the file and the points it put in, so the
// target can check the reader's result bit for bit (an independent decode: the generator never
// calls the reader's code).
//
// The files are valid by the grammar of workloads/io/ply_reader.hpp and pcd_reader.hpp, and
// unusual on purpose: lists before x/y/z and in other elements, int/uint list counts, every
// scalar type for x/y/z, elements with no properties or no entries, big-endian data, CRLF
// headers, PCD fields of COUNT > 1, organized clouds, binary_compressed data.
#pragma once

#include <string>

#include "fuzz_common.hpp"
#include "sw_ref/cloud.hpp"

namespace tigris_fuzz {

struct Generated {
  std::string bytes;
  tigris::PointCloud points;  // what the reader must return (before validate_cloud)
  std::string variant;        // a short description for failure messages
};

Generated generate_ply(ByteSource& src);
Generated generate_pcd(ByteSource& src);

// LZF compression (valid liblzf output: literal runs and back references), for
// binary_compressed files. Independent of the reader's decompressor.
std::string lzf_compress(const std::string& in);

}  // namespace tigris_fuzz
