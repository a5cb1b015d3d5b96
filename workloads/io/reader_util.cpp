#include "reader_util.hpp"

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/visible_text.hpp"

namespace tigris::io_detail {

void fail(const std::string& label, const std::string& what) { throw InputError(label + ": " + what); }

void fail_line(const std::string& label, std::size_t line, const std::string& what) {
  throw InputError(label + ":" + std::to_string(line) + ": " + what);
}

void append_xyz_le32(std::string& out, const PointCloud& cloud) {
  out.reserve(out.size() + 12 * cloud.size());
  for (const Point3& p : cloud)
    for (const float f : {p.x, p.y, p.z}) {
      std::uint32_t u;
      std::memcpy(&u, &f, 4);
      for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((u >> (8 * i)) & 0xFFu));
    }
}

std::string printable(std::string_view word) { return visible_word(word); }

bool LineReader::next(Line& out) {
  if (pos_ >= size_) return false;
  out.words.clear();
  out.control = false;
  out.number = ++line_;
  const void* nl_ptr = std::memchr(data_ + pos_, '\n', size_ - pos_);
  const std::size_t nl = nl_ptr ? static_cast<std::size_t>(static_cast<const char*>(nl_ptr) - data_) : size_;
  out.terminated = nl_ptr != nullptr;
  std::size_t end = nl;
  if (out.terminated && end > pos_ && data_[end - 1] == '\r') --end;  // CRLF
  std::size_t i = pos_;
  while (i < end) {
    while (i < end && (data_[i] == ' ' || data_[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < end && data_[i] != ' ' && data_[i] != '\t') {
      const unsigned char c = static_cast<unsigned char>(data_[i]);
      if (c < 0x20 || c == 0x7F) out.control = true;
      ++i;
    }
    if (i > start) out.words.emplace_back(data_ + start, i - start);
  }
  pos_ = out.terminated ? nl + 1 : size_;
  return true;
}

bool parse_count(std::string_view s, std::uint64_t max, std::uint64_t& value) {
  if (s.empty() || s.size() > 20) return false;
  for (char c : s)
    if (c < '0' || c > '9') return false;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), value);
  return r.ec == std::errc() && r.ptr == s.data() + s.size() && value <= max;
}

bool parse_int(std::string_view s, std::int64_t& value) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  if (s.empty() || s[0] == '+') return false;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), value);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

bool parse_uint(std::string_view s, std::uint64_t& value) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), value);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

namespace {

// from_chars reports values beyond the range (both ways) as result_out_of_range and leaves the
// value alone. Which way: the decimal exponent of the leading significant digit (out of range
// only happens far above 1 or far below it, so its sign decides).
template <class T>
bool parse_real(std::string_view s, T& value) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  if (s.empty() || s[0] == '+') return false;
  const char* first = s.data();
  const char* last = first + s.size();
  const auto r = std::from_chars(first, last, value, std::chars_format::general);
  if (r.ptr != last) return false;
  if (r.ec == std::errc()) return true;
  if (r.ec != std::errc::result_out_of_range) return false;
  const bool negative = *first == '-';
  const char* p = first + (negative ? 1 : 0);
  long long exp10 = 0;  // decimal exponent of the first non-zero digit, before the 'e' part
  bool seen_point = false, seen_digit = false;
  long long int_digits = 0, leading_frac_zeros = 0;
  for (; p < last && *p != 'e' && *p != 'E'; ++p) {
    if (*p == '.') {
      seen_point = true;
    } else if (!seen_digit && *p == '0') {
      if (seen_point) ++leading_frac_zeros;
    } else {
      if (!seen_point) ++int_digits;
      seen_digit = true;
    }
  }
  if (!seen_digit) return false;  // zero is never out of range
  exp10 = int_digits > 0 ? int_digits - 1 : -(leading_frac_zeros + 1);
  if (p < last) {  // exponent: [+-]digits, at most a sane number of them
    ++p;
    const bool eneg = p < last && *p == '-';
    if (p < last && (*p == '-' || *p == '+')) ++p;
    long long e = 0;
    for (; p < last; ++p) {
      if (*p < '0' || *p > '9') return false;
      if (e < 1000000000LL) e = e * 10 + (*p - '0');
    }
    exp10 += eneg ? -e : e;
  }
  const T magnitude = exp10 >= 0 ? std::numeric_limits<T>::infinity() : T(0);
  value = negative ? -magnitude : magnitude;
  return true;
}

}  // namespace

bool parse_float(std::string_view s, float& value) { return parse_real(s, value); }
bool parse_double(std::string_view s, double& value) { return parse_real(s, value); }

int scalar_size(Scalar t) {
  switch (t) {
    case Scalar::I8:
    case Scalar::U8: return 1;
    case Scalar::I16:
    case Scalar::U16: return 2;
    case Scalar::I32:
    case Scalar::U32:
    case Scalar::F32: return 4;
    case Scalar::I64:
    case Scalar::U64:
    case Scalar::F64: return 8;
  }
  return 0;
}

bool scalar_is_float(Scalar t) { return t == Scalar::F32 || t == Scalar::F64; }

const char* scalar_name(Scalar t) {
  static const char* const kNames[] = {"int8",   "uint8", "int16",  "uint16",  "int32",
                                       "uint32", "int64", "uint64", "float32", "float64"};
  return kNames[static_cast<int>(t)];
}

Value load_scalar(const unsigned char* p, Scalar t, bool big_endian) {
  const int n = scalar_size(t);
  std::uint64_t bits = 0;
  for (int k = 0; k < n; ++k) {
    const unsigned char b = big_endian ? p[k] : p[n - 1 - k];
    bits = (bits << 8) | b;
  }
  Value v;
  v.type = t;
  switch (t) {
    case Scalar::I8: v.i = static_cast<std::int8_t>(static_cast<std::uint8_t>(bits)); break;
    case Scalar::I16: v.i = static_cast<std::int16_t>(static_cast<std::uint16_t>(bits)); break;
    case Scalar::I32: v.i = static_cast<std::int32_t>(static_cast<std::uint32_t>(bits)); break;
    case Scalar::I64: v.i = static_cast<std::int64_t>(bits); break;
    case Scalar::U8:
    case Scalar::U16:
    case Scalar::U32:
    case Scalar::U64: v.u = bits; break;
    case Scalar::F32: {
      const std::uint32_t b32 = static_cast<std::uint32_t>(bits);
      std::memcpy(&v.f, &b32, 4);
      break;
    }
    case Scalar::F64: std::memcpy(&v.d, &bits, 8); break;
  }
  return v;
}

bool parse_scalar(std::string_view s, Scalar t, Value& value) {
  value = Value{};
  value.type = t;
  switch (t) {
    case Scalar::F32: return parse_float(s, value.f);
    case Scalar::F64: return parse_double(s, value.d);
    case Scalar::U8:
    case Scalar::U16:
    case Scalar::U32:
    case Scalar::U64: {
      if (!parse_uint(s, value.u)) return false;
      const int bits = 8 * scalar_size(t);
      return bits == 64 || value.u < (std::uint64_t{1} << bits);
    }
    case Scalar::I8:
    case Scalar::I16:
    case Scalar::I32:
    case Scalar::I64: {
      if (!parse_int(s, value.i)) return false;
      const int bits = 8 * scalar_size(t);
      if (bits == 64) return true;
      const std::int64_t lim = std::int64_t{1} << (bits - 1);
      return value.i >= -lim && value.i < lim;
    }
  }
  return false;
}

float to_coordinate(const Value& v, bool& fits) {
  fits = true;
  switch (v.type) {
    case Scalar::F32: return v.f;
    case Scalar::F64: {
      const double d = v.d;
      if (std::isnan(d)) return std::numeric_limits<float>::quiet_NaN();
      if (std::isinf(d))
        return d > 0 ? std::numeric_limits<float>::infinity() : -std::numeric_limits<float>::infinity();
      // Beyond the largest float32 (and the half ulp that still rounds down to it).
      if (std::fabs(d) >= 0x1.ffffffp127) {
        fits = false;
        return 0.0f;
      }
      return static_cast<float>(d);
    }
    case Scalar::I8:
    case Scalar::I16:
    case Scalar::I32:
    case Scalar::I64: return static_cast<float>(v.i);
    case Scalar::U8:
    case Scalar::U16:
    case Scalar::U32:
    case Scalar::U64: return static_cast<float>(v.u);
  }
  return 0.0f;
}

bool to_count(const Value& v, std::uint64_t& count) {
  switch (v.type) {
    case Scalar::I8:
    case Scalar::I16:
    case Scalar::I32:
    case Scalar::I64:
      if (v.i < 0) return false;
      count = static_cast<std::uint64_t>(v.i);
      return true;
    case Scalar::U8:
    case Scalar::U16:
    case Scalar::U32:
    case Scalar::U64: count = v.u; return true;
    default: return false;
  }
}

}  // namespace tigris::io_detail
