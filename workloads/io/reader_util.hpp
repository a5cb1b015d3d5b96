// Helpers the file readers of workloads/io share (not a public interface): errors, header lines,
// number tokens, scalar types and their byte decoding, overflow-checked arithmetic.
//
// Every reader works on the whole file in memory (a byte range and a label, usually the path),
// so the fuzz targets and tests can feed bytes without touching the file system. Every error is
// an InputError whose message starts with the label.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "sw_ref/cloud.hpp"  // InputError

namespace tigris::io_detail {

constexpr std::uint64_t kMaxPoints = 0xFFFFFFFEu;  // a cloud's points: indices are uint32

[[noreturn]] void fail(const std::string& label, const std::string& what);
// "label:LINE: what" (the compiler's style, as the schedule reader reports).
[[noreturn]] void fail_line(const std::string& label, std::size_t line, const std::string& what);

// Appends each point's x, y, z as little-endian float32 (the writers' binary data).
void append_xyz_le32(std::string& out, const PointCloud& cloud);

// A word from a file, fit for an error message: at most 32 characters, bytes outside printable
// ASCII shown as '?'.
std::string printable(std::string_view word);

// ------------------------------------------------------------------------------------------
// Lines. A line ends at '\n' (a '\r' before it is dropped: LF and CRLF files read the same);
// its words are separated by blanks and tabs.

struct Line {
  std::vector<std::string_view> words;
  std::size_t number = 0;   // 1-based line number in the file
  bool control = false;     // holds a control character other than tab (or a lone '\r')
  bool terminated = false;  // ended with '\n' (false: the file ended inside it)
};

// Walks the lines of [data, data + size) from `pos`, counting line numbers from `line`.
class LineReader {
 public:
  LineReader(const char* data, std::size_t size, std::size_t pos = 0, std::size_t line = 0)
      : data_(data), size_(size), pos_(pos), line_(line) {}
  // False at the end of the data. Otherwise fills `out` (word views point into the data).
  bool next(Line& out);
  std::size_t pos() const { return pos_; }  // offset of the first byte after the last line read
  std::size_t line() const { return line_; }

 private:
  const char* data_;
  std::size_t size_;
  std::size_t pos_;
  std::size_t line_;
};

// ------------------------------------------------------------------------------------------
// Numbers.

// A decimal count: digits only, at most `max`. False on anything else (sign, garbage, overflow).
bool parse_count(std::string_view s, std::uint64_t max, std::uint64_t& value);

// An integer token: optional '-' (or '+'), digits. False on garbage or out of int64/uint64 range.
bool parse_int(std::string_view s, std::int64_t& value);
bool parse_uint(std::string_view s, std::uint64_t& value);

// A floating-point token as the C library reads it: decimal, optional sign (a leading '+' too),
// "nan", "inf", "infinity" in any case. A value beyond the type's range is +-infinity and one
// below its smallest subnormal is +-0, as strtof/strtod give them. False on anything else
// (hexadecimal included).
bool parse_float(std::string_view s, float& value);
bool parse_double(std::string_view s, double& value);

// ------------------------------------------------------------------------------------------
// Scalar types of PLY and PCD.

enum class Scalar : std::uint8_t { I8, U8, I16, U16, I32, U32, I64, U64, F32, F64 };

int scalar_size(Scalar t);
bool scalar_is_float(Scalar t);
const char* scalar_name(Scalar t);  // "int8" ... "float64"

// A value of any scalar type, decoded exactly.
struct Value {
  Scalar type = Scalar::F32;
  std::int64_t i = 0;   // I8..I64
  std::uint64_t u = 0;  // U8..U64
  float f = 0.0f;       // F32
  double d = 0.0;       // F64
};

// Decodes scalar_size(t) bytes at p, little- or big-endian.
Value load_scalar(const unsigned char* p, Scalar t, bool big_endian);

// Reads a text token as type t: integers must be integers within the type's range, floats as
// parse_float/parse_double. False on anything else.
bool parse_scalar(std::string_view s, Scalar t, Value& value);

// A coordinate as float32, rounded to nearest. Integers always fit. float64 values beyond the
// float32 range (finite ones) do not: `fits` is false for them. NaN and infinities pass through
// (validate_cloud rejects them with the point's index).
float to_coordinate(const Value& v, bool& fits);

// As an element count (list lengths): false for negative or non-integer values.
bool to_count(const Value& v, std::uint64_t& count);

// ------------------------------------------------------------------------------------------
// Overflow-checked arithmetic on sizes.

inline bool mul_overflows(std::uint64_t a, std::uint64_t b, std::uint64_t& out) {
  return __builtin_mul_overflow(a, b, &out);
}
inline bool add_overflows(std::uint64_t a, std::uint64_t b, std::uint64_t& out) {
  return __builtin_add_overflow(a, b, &out);
}

}  // namespace tigris::io_detail
