// PLY point clouds (Greg Turk's format, version 1.0), read by the project's own parser.
//
// What is read:
// - format ascii, binary_little_endian and binary_big_endian, version 1.0.
// - Elements in any order and number; the one named "vertex" holds the points (exactly one such
//   element). Every other element is read past, its list properties included.
// - Property types char uchar short ushort int uint float double and their aliases int8 uint8
//   int16 uint16 int32 uint32 float32 float64. List properties ("property list COUNT ITEM
//   name") anywhere, also in the vertex element: the count of any integer type (a negative
//   count is an error), items of any type.
// - x, y, z: scalar properties of the vertex element, of any type, converted to float32 by
//   rounding to nearest. A value that is not a finite float32 is an error: a float64 beyond the
//   float32 range here, NaN/Inf (and |value| > kMaxCoordinate) in validate_cloud, which
//   load_cloud runs.
// - Header: "comment" and "obj_info" lines are ignored anywhere in it. Lines end in LF or CRLF
//   (the header of a binary file too: its data starts after the LF that ends "end_header"). A
//   lone CR is not a line end. Empty header lines, unknown keywords, repeated property names
//   in an element and extra words on a line are errors.
// - ASCII data: one element per line (empty lines are skipped), values separated by blanks or
//   tabs; a line must hold exactly its element's values (a list: its count, then that many
//   items). Integers must be integers in their type's range; floats are decimal, "nan" or
//   "inf" (any case, optional sign).
// - The data must end where the last element ends: missing data, and data (or text lines)
//   after the last element, are errors (a header that announces fewer elements than the file
//   holds is caught this way).
// Errors are InputError naming the file and the header line, the data line (ASCII), or the
// element, its index, the property and the byte offset (binary).
#pragma once

#include <cstddef>
#include <string>

#include "sw_ref/cloud.hpp"

namespace tigris {

// Parses a whole PLY file held in memory. Does not validate the points (load_cloud does).
PointCloud parse_ply(const char* data, std::size_t size, const std::string& label);

// A binary little-endian PLY file of `cloud`: one vertex element of float x, y, z.
std::string ply_bytes(const PointCloud& cloud);

}  // namespace tigris
