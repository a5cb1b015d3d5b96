#include "ply_reader.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <unordered_set>
#include <vector>

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
using io_detail::scalar_name;
using io_detail::scalar_size;
using io_detail::Value;

bool ply_type(std::string_view name, Scalar& t) {
  static const struct {
    const char* name;
    Scalar type;
  } kTypes[] = {{"char", Scalar::I8},   {"uchar", Scalar::U8},   {"short", Scalar::I16},   {"ushort", Scalar::U16},
                {"int", Scalar::I32},   {"uint", Scalar::U32},   {"float", Scalar::F32},   {"double", Scalar::F64},
                {"int8", Scalar::I8},   {"uint8", Scalar::U8},   {"int16", Scalar::I16},   {"uint16", Scalar::U16},
                {"int32", Scalar::I32}, {"uint32", Scalar::U32}, {"float32", Scalar::F32}, {"float64", Scalar::F64}};
  for (const auto& k : kTypes)
    if (name == k.name) {
      t = k.type;
      return true;
    }
  return false;
}

struct Property {
  std::string name;
  bool list = false;
  Scalar type = Scalar::F32;       // scalar: its type; list: the item type
  Scalar count_type = Scalar::U8;  // list only
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> props;
  std::size_t line = 0;  // header line of its "element" line
  bool has_list = false;
  std::uint64_t bytes = 0;  // binary bytes of one element without lists (lists: counts only)
};

enum class Format { Ascii, BinaryLE, BinaryBE };

struct Header {
  Format format = Format::Ascii;
  std::vector<Element> elements;
  std::size_t vertex = 0;     // index of the vertex element
  int xyz[3] = {-1, -1, -1};  // property indices of x, y, z in it
  std::size_t data_start = 0;
  std::size_t data_line = 0;  // the line number of end_header
};

// A 'property' line of element `e`: a scalar or a list, its size added to the element's.
Property read_property(const Line& line, Element& e, const std::string& label) {
  const std::size_t n = line.number, nw = line.words.size();
  Property p;
  if (nw == 3) {
    if (!ply_type(line.words[1], p.type))
      fail_line(label, n, "corrupt PLY header: unknown property type '" + printable(line.words[1]) + "'");
    p.name = std::string(line.words[2]);
    e.bytes += static_cast<std::uint64_t>(scalar_size(p.type));
  } else if (nw == 5 && line.words[1] == "list") {
    p.list = true;
    if (!ply_type(line.words[2], p.count_type))
      fail_line(label, n, "corrupt PLY header: unknown list count type '" + printable(line.words[2]) + "'");
    if (io_detail::scalar_is_float(p.count_type))
      fail_line(label, n,
                "corrupt PLY header: a list count must be of an integer type, not '" + printable(line.words[2]) + "'");
    if (!ply_type(line.words[3], p.type))
      fail_line(label, n, "corrupt PLY header: unknown list item type '" + printable(line.words[3]) + "'");
    p.name = std::string(line.words[4]);
    e.has_list = true;
    e.bytes += static_cast<std::uint64_t>(scalar_size(p.count_type));
  } else {
    fail_line(label, n,
              "corrupt PLY header: expected 'property TYPE NAME' or 'property list "
              "COUNT_TYPE ITEM_TYPE NAME'");
  }
  return p;
}

// The vertex element and its x, y, z properties (scalars), and a point count the model takes.
void find_vertex(Header& h, const std::string& label) {
  bool found = false;
  for (std::size_t i = 0; i < h.elements.size(); ++i)
    if (h.elements[i].name == "vertex") {
      h.vertex = i;
      found = true;
    }
  if (!found) fail(label, "the PLY file has no vertex element (no points)");
  const Element& v = h.elements[h.vertex];
  static const char* const kAxes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    for (std::size_t p = 0; p < v.props.size(); ++p)
      if (v.props[p].name == kAxes[a]) h.xyz[a] = static_cast<int>(p);
    if (h.xyz[a] < 0) fail_line(label, v.line, std::string("the vertex element has no '") + kAxes[a] + "' property");
    if (v.props[static_cast<std::size_t>(h.xyz[a])].list)
      fail_line(label, v.line,
                std::string("the vertex property '") + kAxes[a] + "' is a list; x, y, z must be scalars");
  }
  if (v.count == 0) fail_line(label, v.line, "the point cloud is empty (element vertex 0)");
  if (v.count > kMaxPoints)
    fail_line(label, v.line, "too many points (" + std::to_string(v.count) + "; at most 2^32 - 2)");
}

Header read_header(const char* data, std::size_t size, const std::string& label) {
  Header h;
  LineReader lines(data, size);
  Line line;
  if (!lines.next(line) || line.words.size() != 1 || line.words[0] != "ply" || line.control || !line.terminated)
    fail(label, "not a PLY file (it does not start with a 'ply' line)");
  bool have_format = false, have_end = false;
  // Names seen (hash sets: a header of a million elements or properties stays linear).
  std::unordered_set<std::string> element_names, property_names;
  while (lines.next(line)) {
    const std::size_t n = line.number;
    if (!line.terminated) break;  // the file ends inside the header
    if (line.words.empty()) fail_line(label, n, "corrupt PLY header: an empty line");
    const std::string_view key = line.words[0];
    if (key == "comment" || key == "obj_info") continue;
    if (line.control) fail_line(label, n, "corrupt PLY header: a control character");
    const std::size_t nw = line.words.size();
    if (key == "format") {
      if (have_format) fail_line(label, n, "corrupt PLY header: a second format line");
      if (!h.elements.empty()) fail_line(label, n, "corrupt PLY header: format after an element");
      if (nw != 3 || line.words[2] != "1.0")
        fail_line(label, n,
                  "corrupt PLY header: expected 'format ascii|binary_little_endian|"
                  "binary_big_endian 1.0'");
      const std::string_view f = line.words[1];
      if (f == "ascii") {
        h.format = Format::Ascii;
      } else if (f == "binary_little_endian") {
        h.format = Format::BinaryLE;
      } else if (f == "binary_big_endian") {
        h.format = Format::BinaryBE;
      } else {
        fail_line(label, n,
                  "corrupt PLY header: unknown format '" + printable(f) +
                      "' (expected ascii, binary_little_endian or binary_big_endian)");
      }
      have_format = true;
    } else if (key == "element") {
      if (!have_format) fail_line(label, n, "corrupt PLY header: an element before the format line");
      Element e;
      if (nw != 3 || !io_detail::parse_count(line.words[2], std::numeric_limits<std::uint64_t>::max(), e.count))
        fail_line(label, n, "corrupt PLY header: expected 'element NAME COUNT' (COUNT a whole number)");
      e.name = std::string(line.words[1]);
      e.line = n;
      if (!element_names.insert(e.name).second)
        fail_line(label, n, "corrupt PLY header: a second element '" + printable(e.name) + "'");
      property_names.clear();
      h.elements.push_back(std::move(e));
    } else if (key == "property") {
      if (h.elements.empty()) fail_line(label, n, "corrupt PLY header: a property before any element");
      Element& e = h.elements.back();
      Property p = read_property(line, e, label);
      if (!property_names.insert(p.name).second)
        fail_line(label, n,
                  "corrupt PLY header: property '" + printable(p.name) + "' appears twice in element '" +
                      printable(e.name) + "'");
      e.props.push_back(std::move(p));
    } else if (key == "end_header") {
      if (nw != 1) fail_line(label, n, "corrupt PLY header: words after end_header");
      have_end = true;
      h.data_line = n;
      break;
    } else {
      fail_line(label, n, "corrupt PLY header: unknown line '" + printable(key) + "'");
    }
  }
  if (!have_end) fail(label, "truncated or corrupt PLY file: no end_header line");
  if (!have_format) fail(label, "corrupt PLY header: no format line");
  h.data_start = lines.pos();

  find_vertex(h, label);
  return h;
}

// Which of x, y, z property p of the vertex element is (-1: none).
int axis_of(const Header& h, std::size_t p) {
  for (int a = 0; a < 3; ++a)
    if (h.xyz[a] == static_cast<int>(p)) return a;
  return -1;
}

[[noreturn]] void not_float32(const std::string& where, const Value& v) {
  std::ostringstream msg;
  msg.precision(17);
  msg << where << " = " << v.d << " is beyond the float32 range (coordinates are float32)";
  throw InputError(msg.str());
}

// ------------------------------------------------------------------------------------------
// Binary data.

class BinaryBody {
 public:
  BinaryBody(const unsigned char* data, std::size_t size, std::size_t pos, bool big_endian, const std::string& label)
      : data_(data), size_(size), pos_(pos), big_(big_endian), label_(label) {}

  // The bytes of one value of type t; the error names what was being read.
  const unsigned char* take(std::uint64_t bytes, const Element& e, std::uint64_t index, const Property& p) {
    if (bytes > size_ - pos_) {
      std::ostringstream msg;
      msg << "truncated PLY file: element '" << printable(e.name) << "' " << index << " of " << e.count
          << ", property '" << printable(p.name) << "' needs " << bytes << " bytes at byte offset " << pos_
          << " but the file ends at " << size_;
      fail(label_, msg.str());
    }
    const unsigned char* p_ = data_ + pos_;
    pos_ += static_cast<std::size_t>(bytes);
    return p_;
  }
  Value value(Scalar t, const Element& e, std::uint64_t index, const Property& p) {
    return io_detail::load_scalar(take(static_cast<std::uint64_t>(scalar_size(t)), e, index, p), t, big_);
  }
  std::uint64_t list_count(const Element& e, std::uint64_t index, const Property& p) {
    const std::size_t at = pos_;
    const Value c = value(p.count_type, e, index, p);
    std::uint64_t n = 0;
    if (!io_detail::to_count(c, n)) {
      std::ostringstream msg;
      msg << "corrupt PLY file: element '" << printable(e.name) << "' " << index << ", list '" << printable(p.name)
          << "' has a negative count (" << c.i << ") at byte offset " << at;
      fail(label_, msg.str());
    }
    return n;
  }
  // Skips `count` elements of a list-free element at once.
  void skip_fixed(const Element& e) {
    std::uint64_t bytes = 0;
    if (io_detail::mul_overflows(e.count, e.bytes, bytes) || bytes > size_ - pos_) {
      std::ostringstream msg;
      msg << "truncated PLY file: element '" << printable(e.name) << "' announces " << e.count << " entries of "
          << e.bytes << " bytes from byte offset " << pos_ << " but the file ends at " << size_ << " (holds "
          << (size_ - pos_) / e.bytes << " entries)";
      fail(label_, msg.str());
    }
    pos_ += static_cast<std::size_t>(bytes);
  }
  std::size_t pos() const { return pos_; }
  std::size_t remaining() const { return size_ - pos_; }

 private:
  const unsigned char* data_;
  std::size_t size_;
  std::size_t pos_;
  bool big_;
  const std::string& label_;
};

PointCloud read_binary(const Header& h, const char* data, std::size_t size, const std::string& label) {
  BinaryBody body(reinterpret_cast<const unsigned char*>(data), size, h.data_start, h.format == Format::BinaryBE,
                  label);
  PointCloud cloud;
  for (std::size_t ei = 0; ei < h.elements.size(); ++ei) {
    const Element& e = h.elements[ei];
    const bool vertex = ei == h.vertex;
    if (!vertex && (!e.has_list || e.props.empty())) {
      if (e.bytes > 0) body.skip_fixed(e);
      continue;
    }
    if (vertex)
      cloud.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(e.count, body.remaining() / e.bytes + 1)));
    for (std::uint64_t i = 0; i < e.count; ++i) {
      float xyz[3] = {0.0f, 0.0f, 0.0f};
      for (std::size_t pi = 0; pi < e.props.size(); ++pi) {
        const Property& p = e.props[pi];
        if (p.list) {
          const std::uint64_t n = body.list_count(e, i, p);
          std::uint64_t bytes = 0;
          if (io_detail::mul_overflows(n, static_cast<std::uint64_t>(scalar_size(p.type)), bytes))
            bytes = std::numeric_limits<std::uint64_t>::max();
          body.take(bytes, e, i, p);
          continue;
        }
        const int a = vertex ? axis_of(h, pi) : -1;
        if (a < 0) {
          body.take(static_cast<std::uint64_t>(scalar_size(p.type)), e, i, p);
          continue;
        }
        const std::size_t at = body.pos();
        const Value v = body.value(p.type, e, i, p);
        bool fits = true;
        xyz[a] = io_detail::to_coordinate(v, fits);
        if (!fits)
          not_float32(
              label + ": vertex " + std::to_string(i) + " (byte offset " + std::to_string(at) + "): '" + p.name + "'",
              v);
      }
      if (vertex) cloud.push_back(Point3{xyz[0], xyz[1], xyz[2]});
    }
  }
  if (body.remaining() != 0) {
    std::ostringstream msg;
    msg << "corrupt PLY file: " << body.remaining() << " bytes after the last element (from byte "
        << "offset " << body.pos() << "); the header announces fewer elements than the file holds";
    fail(label, msg.str());
  }
  return cloud;
}

// ------------------------------------------------------------------------------------------
// ASCII data: one element per line.

PointCloud read_ascii(const Header& h, const char* data, std::size_t size, const std::string& label) {
  LineReader lines(data, size, h.data_start, h.data_line);
  Line line;
  auto next_line = [&]() {
    while (lines.next(line))
      if (!line.words.empty()) return true;
    return false;
  };
  PointCloud cloud;
  for (std::size_t ei = 0; ei < h.elements.size(); ++ei) {
    const Element& e = h.elements[ei];
    if (e.props.empty()) continue;  // nothing to read, however many
    const bool vertex = ei == h.vertex;
    if (vertex)
      cloud.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(e.count, (size - h.data_start) / 2 + 1)));
    for (std::uint64_t i = 0; i < e.count; ++i) {
      if (!next_line()) {
        std::ostringstream msg;
        msg << "truncated PLY file: the data ends after " << i << " of " << e.count << " entries of element '"
            << printable(e.name) << "' (line " << lines.line() << ")";
        fail(label, msg.str());
      }
      const std::size_t n = line.number;
      const auto where = [&](const Property& p) {
        return "element '" + printable(e.name) + "' " + std::to_string(i) + ", property '" + printable(p.name) + "'";
      };
      if (line.control) fail_line(label, n, "corrupt PLY data: a control character");
      std::size_t w = 0;
      float xyz[3] = {0.0f, 0.0f, 0.0f};
      for (std::size_t pi = 0; pi < e.props.size(); ++pi) {
        const Property& p = e.props[pi];
        const auto word = [&]() -> std::string_view {
          if (w >= line.words.size())
            fail_line(label, n,
                      "corrupt PLY data: the line ends before " + where(p) + " (" + std::to_string(line.words.size()) +
                          " values on the line)");
          return line.words[w++];
        };
        Value v;
        if (p.list) {
          const std::string_view cw = word();
          std::uint64_t count = 0;
          if (!io_detail::parse_scalar(cw, p.count_type, v) || !io_detail::to_count(v, count))
            fail_line(label, n,
                      "corrupt PLY data: " + where(p) + ": list count '" + printable(cw) + "' is not a " +
                          scalar_name(p.count_type) + " count");
          if (count > line.words.size() - w)
            fail_line(label, n,
                      "corrupt PLY data: " + where(p) + ": a list of " + std::to_string(count) +
                          " items but the line holds " + std::to_string(line.words.size() - w) + " more values");
          for (std::uint64_t k = 0; k < count; ++k) {
            const std::string_view iw = word();
            if (!io_detail::parse_scalar(iw, p.type, v))
              fail_line(label, n,
                        "corrupt PLY data: " + where(p) + ": item '" + printable(iw) + "' is not a valid " +
                            scalar_name(p.type));
          }
          continue;
        }
        const std::string_view sw = word();
        if (!io_detail::parse_scalar(sw, p.type, v))
          fail_line(
              label, n,
              "corrupt PLY data: " + where(p) + ": '" + printable(sw) + "' is not a valid " + scalar_name(p.type));
        const int a = vertex ? axis_of(h, pi) : -1;
        if (a >= 0) {
          bool fits = true;
          xyz[a] = io_detail::to_coordinate(v, fits);
          if (!fits)
            not_float32(label + ":" + std::to_string(n) + ": vertex " + std::to_string(i) + " '" + p.name + "'", v);
        }
      }
      if (w != line.words.size())
        fail_line(label, n,
                  "corrupt PLY data: element '" + printable(e.name) + "' " + std::to_string(i) + " has " +
                      std::to_string(line.words.size()) + " values on its line, " + std::to_string(w) + " expected");
      if (vertex) cloud.push_back(Point3{xyz[0], xyz[1], xyz[2]});
    }
  }
  if (next_line())
    fail_line(label, line.number,
              "corrupt PLY data: a line after the last element; the header announces fewer "
              "elements than the file holds");
  return cloud;
}

}  // namespace

PointCloud parse_ply(const char* data, std::size_t size, const std::string& label) {
  const Header h = read_header(data, size, label);
  return h.format == Format::Ascii ? read_ascii(h, data, size, label) : read_binary(h, data, size, label);
}

std::string ply_bytes(const PointCloud& cloud) {
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by tigris\nelement vertex " +
                    std::to_string(cloud.size()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  io_detail::append_xyz_le32(out, cloud);
  return out;
}

}  // namespace tigris
