#include "pcd_reader.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

#include "lzf.hpp"
#include "reader_util.hpp"

namespace tigris {
namespace {

using io_detail::fail;
using io_detail::fail_line;
using io_detail::kMaxPoints;
using io_detail::Line;
using io_detail::LineReader;
using io_detail::printable;
using io_detail::Scalar;
using io_detail::Value;

constexpr std::uint64_t kMaxCount = 0xFFFFFFFFu;  // COUNT of one field

struct Field {
  std::string name;
  std::uint64_t size = 0;
  char type = 0;
  std::uint64_t count = 1;
  Scalar scalar = Scalar::F32;
  std::uint64_t offset = 0;  // in a binary record
};

enum class Data { Ascii, Binary, Compressed };

struct Header {
  std::vector<Field> fields;
  std::uint64_t points = 0;
  std::uint64_t step = 0;    // bytes of one point
  std::uint64_t values = 0;  // values of one point (ASCII)
  int xyz[3] = {-1, -1, -1};
  Data data = Data::Ascii;
  std::size_t data_start = 0;
  std::size_t data_line = 0;  // line number of DATA
};

Scalar scalar_of(char type, std::uint64_t size) {
  if (type == 'F') return size == 4 ? Scalar::F32 : Scalar::F64;
  const bool u = type == 'U';
  switch (size) {
    case 1: return u ? Scalar::U8 : Scalar::I8;
    case 2: return u ? Scalar::U16 : Scalar::I16;
    case 4: return u ? Scalar::U32 : Scalar::I32;
    default: return u ? Scalar::U64 : Scalar::I64;
  }
}

// The header's keywords, each allowed once; COLUMNS (PCD v0.5) is read as FIELDS.
const char* const kKeys[] = {"VERSION", "FIELDS", "SIZE",      "TYPE",   "COUNT",
                             "WIDTH",   "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
enum { kVersion, kFields, kSize, kType, kCount, kWidth, kHeight, kViewpoint, kPoints, kData };
constexpr int kNumKeys = 10;

// The header while it is read: WIDTH and HEIGHT wait for the checks after DATA, and each key's
// line number names the line that the checks spanning several keys blame.
struct HeaderScan {
  Header h;
  std::size_t seen[kNumKeys] = {};  // line numbers, 0: not seen
  std::uint64_t width = 0, height = 0;
};

// The key a header line starts with (its index in kKeys); a line that is no key fails, as not a
// PCD file at all when no key came before it.
int header_key(const Line& line, bool any_key, const std::string& label) {
  std::string_view key = line.words[0];
  if (key == "COLUMNS") key = "FIELDS";  // PCD v0.5
  int k = 0;
  while (k < kNumKeys && key != kKeys[k]) ++k;
  if (k == kNumKeys) {
    if (any_key) fail_line(label, line.number, "corrupt PCD header: unknown line '" + printable(line.words[0]) + "'");
    fail(label, "not a PCD file (no PCD header found)");
  }
  return k;
}

// SIZE, TYPE or COUNT (key k, on line n): one value per field FIELDS named.
void read_field_values(HeaderScan& s, int k, const std::vector<std::string_view>& args, std::size_t n,
                       const std::string& label) {
  Header& h = s.h;
  if (!s.seen[kFields]) fail_line(label, n, "corrupt PCD header: " + std::string(kKeys[k]) + " before FIELDS");
  if (args.size() != h.fields.size())
    fail_line(label, n,
              "corrupt PCD header: " + std::string(kKeys[k]) + " lists " + std::to_string(args.size()) +
                  " values for " + std::to_string(h.fields.size()) + " fields");
  switch (k) {
    case kSize:
      for (std::size_t i = 0; i < args.size(); ++i) {
        std::uint64_t v = 0;
        if (!io_detail::parse_count(args[i], 8, v) || (v != 1 && v != 2 && v != 4 && v != 8))
          fail_line(label, n,
                    "corrupt PCD header: SIZE '" + printable(args[i]) + "' of field '" + printable(h.fields[i].name) +
                        "' (expected 1, 2, 4 or 8)");
        h.fields[i].size = v;
      }
      break;
    case kType:
      if (!s.seen[kSize]) fail_line(label, n, "corrupt PCD header: TYPE before SIZE");
      for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string_view t = args[i];
        const bool ok = (t == "F" && (h.fields[i].size == 4 || h.fields[i].size == 8)) || t == "I" || t == "U";
        if (!ok)
          fail_line(label, n,
                    "corrupt PCD header: TYPE '" + printable(t) + "' of field '" + printable(h.fields[i].name) +
                        "' with SIZE " + std::to_string(h.fields[i].size) + " (expected F with SIZE 4 or 8, I or U)");
        h.fields[i].type = t[0];
      }
      break;
    case kCount:
      for (std::size_t i = 0; i < args.size(); ++i) {
        std::uint64_t v = 0;
        if (!io_detail::parse_count(args[i], kMaxCount, v) || v == 0)
          fail_line(label, n,
                    "corrupt PCD header: COUNT '" + printable(args[i]) + "' of field '" + printable(h.fields[i].name) +
                        "' (expected 1 or more)");
        h.fields[i].count = v;
      }
      break;
  }
}

// One header line's values (key k, on line n; s.seen already holds it).
void read_header_line(HeaderScan& s, int k, const std::vector<std::string_view>& args, std::size_t n,
                      const std::string& label) {
  Header& h = s.h;
  switch (k) {
    case kVersion: {
      static const char* const kVersions[] = {"0.7", ".7", "0.6", ".6", "0.5", ".5"};
      bool ok = args.size() == 1;
      if (ok) ok = std::find(std::begin(kVersions), std::end(kVersions), args[0]) != std::end(kVersions);
      if (!ok) fail_line(label, n, "unsupported PCD VERSION (expected 0.7, 0.6 or 0.5)");
      break;
    }
    case kFields:
      if (args.empty()) fail_line(label, n, "corrupt PCD header: FIELDS names no field");
      for (std::string_view a : args) {
        Field f;
        f.name = std::string(a);
        h.fields.push_back(f);
      }
      break;
    case kSize:
    case kType:
    case kCount: read_field_values(s, k, args, n, label); break;
    case kWidth:
    case kHeight:
    case kPoints: {
      std::uint64_t v = 0;
      if (args.size() != 1 || !io_detail::parse_count(args[0], std::numeric_limits<std::uint64_t>::max(), v))
        fail_line(label, n, "corrupt PCD header: " + std::string(kKeys[k]) + " is not a whole number");
      (k == kWidth ? s.width : k == kHeight ? s.height : h.points) = v;
      break;
    }
    case kViewpoint: {
      double d = 0;
      bool ok = args.size() == 7;
      for (std::size_t i = 0; ok && i < args.size(); ++i) ok = io_detail::parse_double(args[i], d);
      if (!ok) fail_line(label, n, "corrupt PCD header: VIEWPOINT needs 7 numbers");
      break;
    }
    case kData:
      if (args.size() == 1 && args[0] == "ascii") {
        h.data = Data::Ascii;
      } else if (args.size() == 1 && args[0] == "binary") {
        h.data = Data::Binary;
      } else if (args.size() == 1 && args[0] == "binary_compressed") {
        h.data = Data::Compressed;
      } else {
        fail_line(label, n, "corrupt PCD header: DATA must be ascii, binary or binary_compressed");
      }
      break;
  }
}

// After DATA (on line data_line): the keys every file needs, and h.points from WIDTH x HEIGHT
// and POINTS, which must agree when both are given.
void settle_points(HeaderScan& s, std::size_t data_line, const std::string& label) {
  Header& h = s.h;
  const std::size_t* const seen = s.seen;
  if (!seen[kFields] || !seen[kSize] || !seen[kType])
    fail_line(label, data_line, "corrupt PCD header: FIELDS, SIZE and TYPE are required before DATA");
  if (seen[kHeight] && !seen[kWidth]) fail_line(label, seen[kHeight], "corrupt PCD header: HEIGHT without WIDTH");
  if (!seen[kWidth] && !seen[kPoints])
    fail_line(label, data_line, "corrupt PCD header: neither WIDTH nor POINTS given");
  if (seen[kWidth]) {
    if (!seen[kHeight]) s.height = 1;
    std::uint64_t wh = 0;
    if (io_detail::mul_overflows(s.width, s.height, wh) || (seen[kPoints] && wh != h.points))
      fail_line(label, seen[kPoints] ? seen[kPoints] : seen[kWidth],
                "corrupt PCD header: WIDTH x HEIGHT (" + std::to_string(s.width) + " x " + std::to_string(s.height) +
                    ") differs from POINTS (" + std::to_string(h.points) + ")");
    h.points = wh;
  }
  if (h.points == 0) fail(label, "the point cloud is empty (POINTS 0)");
  if (h.points > kMaxPoints) fail(label, "too many points (" + std::to_string(h.points) + "; at most 2^32 - 2)");
}

// Each field's scalar type and offset in a record, the record's size, and which fields are x, y, z.
void lay_out_fields(HeaderScan& s, const std::string& label) {
  Header& h = s.h;
  static const char* const kAxes[3] = {"x", "y", "z"};
  for (std::size_t i = 0; i < h.fields.size(); ++i) {
    Field& f = h.fields[i];
    f.scalar = scalar_of(f.type, f.size);
    f.offset = h.step;
    std::uint64_t bytes = 0;
    if (io_detail::mul_overflows(f.size, f.count, bytes) || io_detail::add_overflows(h.step, bytes, h.step) ||
        io_detail::add_overflows(h.values, f.count, h.values))
      fail(label, "corrupt PCD header: the point record is too large");
    for (int a = 0; a < 3; ++a) {
      if (f.name != kAxes[a]) continue;
      if (h.xyz[a] >= 0)
        fail_line(label, s.seen[kFields], std::string("corrupt PCD header: field '") + kAxes[a] + "' appears twice");
      if (f.count != 1)
        fail_line(label, s.seen[kCount],
                  std::string("field '") + kAxes[a] + "' has COUNT " + std::to_string(f.count) +
                      "; x, y, z must be single values");
      h.xyz[a] = static_cast<int>(i);
    }
  }
  for (int a = 0; a < 3; ++a)
    if (h.xyz[a] < 0) fail_line(label, s.seen[kFields], std::string("the file has no '") + kAxes[a] + "' field");
}

Header read_header(const char* data, std::size_t size, const std::string& label) {
  HeaderScan s;
  LineReader lines(data, size);
  Line line;
  bool any_key = false;
  while (true) {
    if (!lines.next(line) || !line.terminated) {
      fail(label, any_key ? "truncated or corrupt PCD file: no complete DATA line in the header"
                          : "not a PCD file (no PCD header found)");
    }
    const std::size_t n = line.number;
    if (line.words.empty() || line.words[0][0] == '#') continue;
    if (line.control) fail_line(label, n, "corrupt PCD header: a control character");
    const int k = header_key(line, any_key, label);
    any_key = true;
    if (s.seen[k]) fail_line(label, n, "corrupt PCD header: a second " + std::string(kKeys[k]) + " line");
    s.seen[k] = n;
    const std::vector<std::string_view> args(line.words.begin() + 1, line.words.end());
    read_header_line(s, k, args, n, label);
    if (k == kData) break;
  }
  s.h.data_start = lines.pos();
  s.h.data_line = line.number;
  settle_points(s, line.number, label);
  lay_out_fields(s, label);
  return std::move(s.h);
}

[[noreturn]] void not_float32(const std::string& where, const Value& v) {
  std::ostringstream msg;
  msg.precision(17);
  msg << where << " = " << v.d << " is beyond the float32 range (coordinates are float32)";
  throw InputError(msg.str());
}

// A coordinate as float32; `where` (called only on an error) says where the value lies.
template <class Where>
float coordinate(const Value& v, const std::string& label, const char* axis, std::uint64_t point, Where where) {
  bool fits = true;
  const float f = io_detail::to_coordinate(v, fits);
  if (!fits) not_float32(label + ": point " + std::to_string(point) + " (" + where() + "): '" + axis + "'", v);
  return f;
}

const char* const kAxisNames[3] = {"x", "y", "z"};

PointCloud read_ascii(const Header& h, const char* data, std::size_t size, const std::string& label) {
  LineReader lines(data, size, h.data_start, h.data_line);
  Line line;
  auto next_line = [&]() {
    while (lines.next(line))
      if (!line.words.empty()) return true;
    return false;
  };
  PointCloud cloud;
  cloud.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(h.points, (size - h.data_start) / 2 + 1)));
  for (std::uint64_t i = 0; i < h.points; ++i) {
    if (!next_line())
      fail(label, "truncated PCD file: the data ends after " + std::to_string(i) + " of " + std::to_string(h.points) +
                      " points (line " + std::to_string(lines.line()) + ")");
    const std::size_t n = line.number;
    if (line.control) fail_line(label, n, "corrupt PCD data: a control character");
    if (line.words.size() != h.values)
      fail_line(label, n,
                "corrupt PCD data: point " + std::to_string(i) + " has " + std::to_string(line.words.size()) +
                    " values, the header announces " + std::to_string(h.values));
    std::size_t w = 0;
    float xyz[3] = {0.0f, 0.0f, 0.0f};
    for (std::size_t fi = 0; fi < h.fields.size(); ++fi) {
      const Field& f = h.fields[fi];
      for (std::uint64_t c = 0; c < f.count; ++c, ++w) {
        Value v;
        if (!io_detail::parse_scalar(line.words[w], f.scalar, v))
          fail_line(label, n,
                    "corrupt PCD data: point " + std::to_string(i) + ", field '" + printable(f.name) + "': '" +
                        printable(line.words[w]) + "' is not a valid " + io_detail::scalar_name(f.scalar));
        for (int a = 0; a < 3; ++a)
          if (h.xyz[a] == static_cast<int>(fi))
            xyz[a] = coordinate(v, label, kAxisNames[a], i, [&] { return "line " + std::to_string(n); });
      }
    }
    cloud.push_back(Point3{xyz[0], xyz[1], xyz[2]});
  }
  if (next_line())
    fail_line(label, line.number,
              "corrupt PCD data: a line after the last point; the header announces fewer points "
              "than the file holds");
  return cloud;
}

// Points out of field-interleaved (binary) or field-after-field (decompressed) data.
PointCloud read_records(const Header& h, const unsigned char* base, bool by_field, std::size_t base_offset,
                        const std::string& label) {
  PointCloud cloud(static_cast<std::size_t>(h.points));
  std::uint64_t field_start[3] = {0, 0, 0};  // by_field: start of the x, y, z blocks
  for (int a = 0; a < 3; ++a) {
    const Field& f = h.fields[static_cast<std::size_t>(h.xyz[a])];
    field_start[a] = f.offset * h.points;  // fields before it, each for all points
  }
  for (std::uint64_t i = 0; i < h.points; ++i) {
    float xyz[3];
    for (int a = 0; a < 3; ++a) {
      const Field& f = h.fields[static_cast<std::size_t>(h.xyz[a])];
      const std::uint64_t at = by_field ? field_start[a] + i * f.size : i * h.step + f.offset;
      const Value v = io_detail::load_scalar(base + at, f.scalar, false);
      xyz[a] = coordinate(v, label, kAxisNames[a], i, [&] {
        return by_field ? "uncompressed byte " + std::to_string(at) : "byte offset " + std::to_string(base_offset + at);
      });
    }
    cloud[static_cast<std::size_t>(i)] = Point3{xyz[0], xyz[1], xyz[2]};
  }
  return cloud;
}

std::uint32_t u32_le(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

PointCloud read_binary(const Header& h, const char* data, std::size_t size, const std::string& label) {
  const std::uint64_t body = size - h.data_start;
  std::uint64_t needed = 0;
  if (io_detail::mul_overflows(h.points, h.step, needed)) needed = std::numeric_limits<std::uint64_t>::max();
  if (needed > body) {
    std::ostringstream msg;
    msg << "truncated PCD file: " << h.points << " points of " << h.step << " bytes need " << needed
        << " bytes of binary data from byte offset " << h.data_start << " but the file holds " << body << " ("
        << body / h.step << " points)";
    fail(label, msg.str());
  }
  if (needed < body) {
    std::ostringstream msg;
    msg << "corrupt PCD file: " << body - needed << " bytes after the last point (from byte offset "
        << h.data_start + needed << "); the header announces fewer points than the file holds";
    fail(label, msg.str());
  }
  return read_records(h, reinterpret_cast<const unsigned char*>(data) + h.data_start, false, h.data_start, label);
}

PointCloud read_compressed(const Header& h, const char* data, std::size_t size, const std::string& label) {
  const unsigned char* p = reinterpret_cast<const unsigned char*>(data) + h.data_start;
  const std::uint64_t body = size - h.data_start;
  if (body < 8)
    fail(label, "truncated PCD file: binary_compressed data needs 8 bytes of sizes at byte offset " +
                    std::to_string(h.data_start) + ", the file holds " + std::to_string(body));
  const std::uint64_t compressed = u32_le(p), uncompressed = u32_le(p + 4);
  std::uint64_t needed = 0;
  if (io_detail::mul_overflows(h.points, h.step, needed) || uncompressed != needed)
    fail(label, "corrupt PCD file: the compressed block decompresses to " + std::to_string(uncompressed) +
                    " bytes, but " + std::to_string(h.points) + " points of " + std::to_string(h.step) +
                    " bytes take " + (needed == 0 && h.step != 0 ? std::string("more") : std::to_string(needed)));
  if (compressed > body - 8)
    fail(label, "truncated PCD file: the compressed block of " + std::to_string(compressed) + " bytes at byte offset " +
                    std::to_string(h.data_start + 8) + " passes the end of the file (" + std::to_string(body - 8) +
                    " bytes left)");
  if (compressed < body - 8)
    fail(label, "corrupt PCD file: " + std::to_string(body - 8 - compressed) +
                    " bytes after the compressed block (from byte offset " +
                    std::to_string(h.data_start + 8 + compressed) + ")");
  // LZF yields at most 88 output bytes an input byte (a 3-byte reference of 264): a size the
  // block cannot reach is caught before anything is allocated.
  if (uncompressed > 88 * compressed)
    fail(label, "corrupt PCD file: " + std::to_string(compressed) + " compressed bytes cannot hold " +
                    std::to_string(uncompressed) + " bytes");
  std::vector<unsigned char> out(static_cast<std::size_t>(uncompressed));
  const long got = lzf_decompress(p + 8, static_cast<std::size_t>(compressed), out.data(), out.size());
  if (got < 0 || static_cast<std::uint64_t>(got) != uncompressed)
    fail(label,
         "corrupt PCD file: the LZF data at byte offset " + std::to_string(h.data_start + 8) +
             (got < 0 ? " is corrupt"
                      : " decompresses to " + std::to_string(got) + " bytes, not " + std::to_string(uncompressed)));
  return read_records(h, out.data(), true, 0, label);
}

}  // namespace

PointCloud parse_pcd(const char* data, std::size_t size, const std::string& label) {
  const Header h = read_header(data, size, label);
  switch (h.data) {
    case Data::Ascii: return read_ascii(h, data, size, label);
    case Data::Binary: return read_binary(h, data, size, label);
    case Data::Compressed: return read_compressed(h, data, size, label);
  }
  return {};
}

std::string pcd_bytes(const PointCloud& cloud) {
  const std::string n = std::to_string(cloud.size());
  std::string out =
      "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
      "TYPE F F F\nCOUNT 1 1 1\nWIDTH " +
      n + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + n + "\nDATA binary\n";
  io_detail::append_xyz_le32(out, cloud);
  return out;
}

}  // namespace tigris
