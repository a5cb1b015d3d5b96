// PCD point clouds (the Point Cloud Library's format), read by the project's own parser.
//
// What is read:
// - VERSION 0.7, 0.6 or 0.5 (also written .7 .6 .5), or no VERSION line; COLUMNS is read as
//   FIELDS (v0.5).
// - Header keywords FIELDS, SIZE, TYPE, COUNT, WIDTH, HEIGHT, VIEWPOINT, POINTS, then DATA
//   last. Each at most once; SIZE, TYPE and COUNT after FIELDS with one value per field; COUNT
//   defaults to 1. SIZE 1, 2, 4 or 8; TYPE F (SIZE 4 or 8), I or U. VIEWPOINT must hold 7
//   numbers and is otherwise ignored. Lines starting with '#' are comments; empty lines are
//   skipped; unknown keywords are errors.
// - WIDTH x HEIGHT and POINTS must agree when both are given; either one alone sets the other
//   (HEIGHT 1). The cloud must not be empty.
// - DATA ascii (one point per line, exactly its values; empty lines skipped), binary
//   (little-endian records of the fields in order) or binary_compressed (uint32 compressed size,
//   uint32 uncompressed size, then LZF data that decompresses to the fields one after another,
//   each for all points). The data must end where the points end: a shorter file, or bytes or
//   lines after the last point, are errors.
// - x, y, z: fields of COUNT 1 of any type, converted to float32 by rounding to nearest. A value
//   that is not a finite float32 is an error (float64 beyond the float32 range here; NaN/Inf,
//   and |value| > kMaxCoordinate, in validate_cloud). Other fields, repeated names among them
//   (PCL's "_" padding fields), are read past; x, y and z may not repeat.
// - Header lines and ASCII data lines end in LF or CRLF; binary data starts after the LF that
//   ends the DATA line.
// Errors are InputError naming the file and the line (header, ASCII data) or the point index and
// byte offset (binary data).
#pragma once

#include <cstddef>
#include <string>

#include "sw_ref/cloud.hpp"

namespace tigris {

// Parses a whole PCD file held in memory. Does not validate the points (load_cloud does).
PointCloud parse_pcd(const char* data, std::size_t size, const std::string& label);

// A binary PCD v0.7 file of `cloud`: fields x y z, float32.
std::string pcd_bytes(const PointCloud& cloud);

}  // namespace tigris
