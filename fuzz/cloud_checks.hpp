// Shared by the PCD and PLY targets: what a read of a cloud file must satisfy.
//   check_file:      any input: a clean error naming the file, or as many points as the header
//                    announces (an independent scan) that survive a write and re-read;
//   check_generated: a valid file the generator made must read back its points bit for bit.
#pragma once

#include <sstream>
#include <string>

#include "cloud_gen.hpp"
#include "fuzz_common.hpp"
#include "sw_ref/cloud.hpp"

namespace tigris_fuzz {

using ParseCloud = tigris::PointCloud (*)(const char*, std::size_t, const std::string&);

// "" when equal bit for bit, else the first difference.
inline std::string difference(const tigris::PointCloud& got, const tigris::PointCloud& want) {
  if (got.size() != want.size())
    return std::to_string(got.size()) + " points read, " + std::to_string(want.size()) + " expected";
  for (std::size_t i = 0; i < got.size(); ++i)
    if (float_bits(got[i].x) != float_bits(want[i].x) || float_bits(got[i].y) != float_bits(want[i].y) ||
        float_bits(got[i].z) != float_bits(want[i].z)) {
      std::ostringstream m;
      m.precision(9);
      m << "point " << i << " read as (" << got[i].x << ", " << got[i].y << ", " << got[i].z << "), expected ("
        << want[i].x << ", " << want[i].y << ", " << want[i].z << ")";
      return m.str();
    }
  return "";
}

// `announced`: the header's point count by a scan sharing nothing with the reader (-1: none).
inline void check_file(const std::uint8_t* data, std::size_t size, const char* target, const std::string& label,
                       ParseCloud parse, std::string (*write)(const tigris::PointCloud&),
                       long long (*announced)(const std::string&)) {
  tigris::PointCloud cloud;
  try {
    cloud = parse(reinterpret_cast<const char*>(data), size, label);
  } catch (const tigris::InputError& e) {
    if (!names_source(e.what(), label)) wrong_read(target, std::string("error without the file name: ") + e.what());
    return;
  }
  const long long n = announced(std::string(reinterpret_cast<const char*>(data), size));
  if (n < 0 || static_cast<unsigned long long>(n) != cloud.size())
    wrong_read(target, std::to_string(cloud.size()) + " points read, the header announces " + std::to_string(n));
  const std::string again = write(cloud);
  const std::string diff = difference(parse(again.data(), again.size(), label), cloud);
  if (!diff.empty()) wrong_read(target, "write and re-read: " + diff);
  try {
    tigris::validate_cloud(cloud, label);
  } catch (const tigris::InputError& e) {
    if (!names_source(e.what(), label)) wrong_read(target, std::string("error without the file name: ") + e.what());
  }
}

inline void check_generated(const Generated& g, const char* target, const std::string& label, ParseCloud parse) {
  tigris::PointCloud cloud;
  try {
    cloud = parse(g.bytes.data(), g.bytes.size(), label);
  } catch (const tigris::InputError& e) {
    wrong_read(target, "a valid file (" + g.variant + ") rejected: " + e.what() + "\n" + g.bytes.substr(0, 600));
  }
  const std::string diff = difference(cloud, g.points);
  if (!diff.empty()) wrong_read(target, g.variant + ": " + diff + "\n" + g.bytes.substr(0, 600));
}

}  // namespace tigris_fuzz
