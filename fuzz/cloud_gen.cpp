#include "cloud_gen.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <utility>
#include <vector>

namespace tigris_fuzz {
namespace {

// A scalar type as the generator knows it (its own table, not the reader's).
struct Type {
  int size;   // bytes
  char kind;  // 'I', 'U', 'F'
};

const Type kTypes[] = {{1, 'I'}, {1, 'U'}, {2, 'I'}, {2, 'U'}, {4, 'I'},
                       {4, 'U'}, {4, 'F'}, {8, 'F'}, {8, 'I'}, {8, 'U'}};
constexpr int kPlyTypes = 8;  // PLY has no 64-bit integers

// PLY spellings: the classic name and the sized alias of each of the first eight types.
const char* const kPlyNames[kPlyTypes][2] = {{"char", "int8"},     {"uchar", "uint8"},   {"short", "int16"},
                                             {"ushort", "uint16"}, {"int", "int32"},     {"uint", "uint32"},
                                             {"float", "float32"}, {"double", "float64"}};

// One value of a type: its text, its little-endian bytes, and (for coordinates) the float32
// the reader must produce.
struct Val {
  std::string text;
  std::string le;
  float as_float = 0.0f;
};

std::string le_bytes(std::uint64_t bits, int size) {
  std::string out;
  for (int k = 0; k < size; ++k) out.push_back(static_cast<char>((bits >> (8 * k)) & 0xFF));
  return out;
}

std::string fmt(const char* f, double d) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, d);
  return buf;
}

// `coordinate`: the value must convert to a finite float32 (x, y, z); otherwise NaN and
// infinities may appear too (other properties are read past).
Val make_value(ByteSource& s, const Type& t, bool coordinate) {
  Val v;
  const int style = s.byte() % 4;  // 0: small, 1-3: any bits
  if (t.kind == 'F') {
    double d;
    if (style == 0) {
      d = static_cast<double>(static_cast<std::int64_t>(s.range(0, 2000)) - 1000) / 8.0;
    } else if (t.size == 4) {
      const std::uint32_t b = static_cast<std::uint32_t>(s.bits(32));
      float f;
      std::memcpy(&f, &b, 4);
      d = f;
    } else {
      const std::uint64_t b = s.bits(64);
      std::memcpy(&d, &b, 8);
    }
    if (coordinate) {
      if (!std::isfinite(d)) d = 0.5;
      if (t.size == 8 && std::fabs(d) > static_cast<double>(FLT_MAX)) d = std::ldexp(d, -900);
      if (t.size == 8 && std::fabs(d) > static_cast<double>(FLT_MAX)) d = 1.0;
    }
    if (t.size == 4) {
      const float f = static_cast<float>(d);
      std::uint32_t b;
      std::memcpy(&b, &f, 4);
      v.le = le_bytes(b, 4);
      v.as_float = f;
      v.text = std::isnan(f) ? (std::signbit(f) ? "-nan" : "nan") : fmt("%.9g", static_cast<double>(f));
    } else {
      std::uint64_t b;
      std::memcpy(&b, &d, 8);
      v.le = le_bytes(b, 8);
      v.as_float = coordinate ? static_cast<float>(d) : 0.0f;
      v.text = std::isnan(d) ? "NaN" : fmt("%.17g", d);
    }
    if (!std::isnan(d) && !std::signbit(d) && s.chance(10)) v.text = "+" + v.text;
    return v;
  }
  const int bits = 8 * t.size;
  std::uint64_t u = style == 0 ? s.range(0, 300) : s.bits(bits);
  if (bits < 64) u &= (std::uint64_t{1} << bits) - 1;
  if (t.kind == 'U') {
    v.text = std::to_string(u);
    v.as_float = static_cast<float>(u);
  } else {
    std::int64_t i;
    if (bits == 64) {
      std::memcpy(&i, &u, 8);
    } else {
      const std::uint64_t sign = std::uint64_t{1} << (bits - 1);
      i = (u & sign) ? static_cast<std::int64_t>(u) - static_cast<std::int64_t>(sign << 1)
                     : static_cast<std::int64_t>(u);
    }
    v.text = std::to_string(i);
    v.as_float = static_cast<float>(i);
  }
  v.le = le_bytes(u, t.size);
  return v;
}

std::string reversed(std::string s) {
  std::reverse(s.begin(), s.end());
  return s;
}

// A list length of an integer count type (kept small).
Val make_count(std::uint64_t n, const Type& t) {
  Val v;
  v.text = std::to_string(n);
  v.le = le_bytes(n, t.size);
  return v;
}

std::string separator(ByteSource& s) {
  switch (s.byte() % 6) {
    case 0: return "\t";
    case 1: return "  ";
    default: return " ";
  }
}

struct PlyProp {
  std::string name;
  bool list = false;
  int type = 0;        // index into kTypes (item type for a list)
  int count_type = 1;  // lists: an integer type
  int axis = -1;       // 0, 1, 2 for x, y, z of the vertex element
};

struct PlyElem {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProp> props;
  bool vertex = false;
};

PlyProp random_ply_prop(ByteSource& s, const std::string& name) {
  PlyProp p;
  p.name = name;
  p.list = s.chance(40);
  p.type = static_cast<int>(s.range(0, kPlyTypes - 1));
  p.count_type = static_cast<int>(s.range(0, 5));  // char .. uint
  return p;
}

const char* const kPlyFormats[] = {"ascii", "binary_little_endian", "binary_big_endian"};
const char* const kPcdData[] = {"ascii", "binary", "binary_compressed"};

// The elements: the vertex element somewhere among up to three others.
std::vector<PlyElem> random_ply_elements(ByteSource& s) {
  static const char* const kOther[] = {"face", "edge", "material", "camera", "range_grid"};
  const int n_other = static_cast<int>(s.range(0, 3));
  const int vertex_at = static_cast<int>(s.range(0, static_cast<std::uint64_t>(n_other)));
  std::vector<PlyElem> elems;
  for (int e = 0, o = 0; e <= n_other; ++e) {
    PlyElem el;
    if (e == vertex_at) {
      el.name = "vertex";
      el.vertex = true;
      el.count = s.range(1, 24);
      const int extras = static_cast<int>(s.range(0, 4));
      static const char* const kExtra[] = {"e", "nx", "red", "intensity", "vertex_indices", "w"};
      std::vector<PlyProp> props;
      for (int k = 0; k < extras; ++k)
        props.push_back(random_ply_prop(s, std::string(kExtra[k % 6]) + (k >= 6 ? std::to_string(k) : "")));
      static const char* const kAxes[] = {"x", "y", "z"};
      for (int a = 0; a < 3; ++a) {
        PlyProp p;
        p.name = kAxes[a];
        p.type = static_cast<int>(s.range(0, kPlyTypes - 1));
        p.axis = a;
        const std::size_t at = static_cast<std::size_t>(s.range(0, props.size()));
        props.insert(props.begin() + static_cast<std::ptrdiff_t>(at), p);
      }
      el.props = props;
    } else {
      el.name = kOther[(o++ + s.range(0, 1)) % 5];
      for (bool again = true; again;) {
        again = false;
        for (const PlyElem& other : elems)
          if (other.name == el.name) {
            el.name += "2";
            again = true;
          }
      }
      el.count = s.range(0, 5);
      const int n_props = static_cast<int>(s.range(0, 3));
      for (int k = 0; k < n_props; ++k) el.props.push_back(random_ply_prop(s, "p" + std::to_string(k)));
    }
    elems.push_back(el);
  }
  return elems;
}

// The header, comments anywhere between its lines.
void write_ply_header(ByteSource& s, const std::vector<PlyElem>& elems, int format, const std::string& eol,
                      std::string& bytes) {
  auto comment = [&]() {
    if (s.chance(15)) bytes += (s.flag() ? "comment made by the fuzzer" : "obj_info generated") + eol;
  };
  auto tname = [&](int t) { return std::string(kPlyNames[t][s.byte() & 1]); };
  bytes = "ply" + eol;
  comment();
  bytes += std::string("format ") + kPlyFormats[format] + " 1.0" + eol;
  for (const PlyElem& e : elems) {
    comment();
    bytes += "element " + e.name + " " + std::to_string(e.count) + eol;
    for (const PlyProp& p : e.props) {
      comment();
      bytes += p.list ? "property list " + tname(p.count_type) + " " + tname(p.type) + " " + p.name + eol
                      : "property " + tname(p.type) + " " + p.name + eol;
    }
  }
  comment();
  bytes += "end_header" + eol;
}

// The elements' values (every element's, in order); the vertices' coordinates into g.points.
void write_ply_data(ByteSource& s, const std::vector<PlyElem>& elems, int format, const std::string& eol,
                    Generated& g) {
  for (const PlyElem& e : elems) {
    for (std::uint64_t i = 0; i < e.count; ++i) {
      float xyz[3] = {0, 0, 0};
      std::string line;
      auto put = [&](const Val& v) {
        if (format == 0) {
          if (!line.empty()) line += separator(s);
          line += v.text;
        } else {
          g.bytes += format == 1 ? v.le : reversed(v.le);
        }
      };
      for (const PlyProp& p : e.props) {
        if (p.list) {
          const std::uint64_t n = s.range(0, 3);
          put(make_count(n, kTypes[p.count_type]));
          for (std::uint64_t k = 0; k < n; ++k) put(make_value(s, kTypes[p.type], false));
        } else {
          const Val v = make_value(s, kTypes[p.type], p.axis >= 0);
          if (p.axis >= 0) xyz[p.axis] = v.as_float;
          put(v);
        }
      }
      if (format == 0 && !e.props.empty()) {
        if (s.chance(5)) g.bytes += eol;  // empty lines are skipped
        g.bytes += (s.chance(5) ? " " : "") + line + (s.chance(5) ? "\t" : "") + eol;
      }
      if (e.vertex) g.points.push_back(tigris::Point3{xyz[0], xyz[1], xyz[2]});
    }
  }
}

}  // namespace

Generated generate_ply(ByteSource& s) {
  Generated g;
  const int format = static_cast<int>(s.range(0, 2));  // ascii, little, big
  const bool crlf = s.chance(25);
  const std::string eol = crlf ? "\r\n" : "\n";
  g.variant = std::string("ply ") + kPlyFormats[format] + (crlf ? " crlf" : "");
  const std::vector<PlyElem> elems = random_ply_elements(s);
  write_ply_header(s, elems, format, eol, g.bytes);
  write_ply_data(s, elems, format, eol, g);
  return g;
}

namespace {

struct PcdField {
  std::string name;
  int type;
  std::uint64_t count;
  int axis;  // 0..2 for x, y, z; -1: another field
};

// The fields: x, y and z among up to four others of random types and counts.
std::vector<PcdField> random_pcd_fields(ByteSource& s) {
  std::vector<PcdField> fields;
  static const char* const kExtra[] = {"intensity", "_", "rgb", "normal_x", "_", "label", "curvature"};
  const int extras = static_cast<int>(s.range(0, 4));
  for (int k = 0; k < extras; ++k)
    fields.push_back({kExtra[s.range(0, 6)], static_cast<int>(s.range(0, 9)), s.range(1, 3), -1});
  static const char* const kAxes[] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    const std::size_t at = static_cast<std::size_t>(s.range(0, fields.size()));
    fields.insert(fields.begin() + static_cast<std::ptrdiff_t>(at),
                  PcdField{kAxes[a], static_cast<int>(s.range(0, 9)), 1, a});
  }
  // Extra fields named like an axis would repeat it: rename.
  for (PcdField& f : fields)
    if (f.axis < 0 && (f.name == "x" || f.name == "y" || f.name == "z")) f.name = "_";
  return fields;
}

// The header's lines: FIELDS, SIZE, TYPE, COUNT, then WIDTH, HEIGHT, VIEWPOINT and POINTS (some
// left out, in any order), comments and an empty line anywhere, DATA last.
std::vector<std::string> pcd_header(ByteSource& s, const std::vector<PcdField>& fields, std::uint64_t points,
                                    int data) {
  std::uint64_t width = points, height = 1;
  if (s.chance(30))
    for (std::uint64_t h = s.range(1, points); h >= 1; --h)
      if (points % h == 0) {
        height = h;
        width = points / h;
        break;
      }
  const int dims =
      static_cast<int>(s.range(0, 3));  // 0: all, 1: no POINTS, 2: no WIDTH/HEIGHT, 3: WIDTH without HEIGHT
  const bool with_width = dims != 2, with_height = dims == 0 || dims == 1, with_points = dims != 1;
  if (dims == 3) {  // WIDTH alone means HEIGHT 1
    width = points;
    height = 1;
  }
  bool all_count_one = true;
  for (const PcdField& f : fields) all_count_one = all_count_one && f.count == 1;

  // Header lines; WIDTH, HEIGHT, VIEWPOINT and POINTS may come in any order.
  auto join = [&](auto get) {
    std::string out;
    for (const PcdField& f : fields) out += " " + get(f);
    return out;
  };
  std::vector<std::string> header;
  if (s.chance(60)) header.push_back("# .PCD v0.7 - Point Cloud Data file format");
  if (s.chance(80)) {
    static const char* const kVersions[] = {"0.7", ".7", "0.6", "0.5"};
    header.push_back(std::string("VERSION ") + kVersions[s.range(0, 3)]);
  }
  header.push_back(std::string(s.chance(10) ? "COLUMNS" : "FIELDS") + join([](const PcdField& f) { return f.name; }));
  header.push_back("SIZE" + join([](const PcdField& f) { return std::to_string(kTypes[f.type].size); }));
  header.push_back("TYPE" + join([](const PcdField& f) { return std::string(1, kTypes[f.type].kind); }));
  if (!all_count_one || s.chance(70))
    header.push_back("COUNT" + join([](const PcdField& f) { return std::to_string(f.count); }));
  std::vector<std::string> dims_lines;
  if (with_width) dims_lines.push_back("WIDTH " + std::to_string(width));
  if (with_height) dims_lines.push_back("HEIGHT " + std::to_string(height));
  if (s.chance(70)) dims_lines.push_back("VIEWPOINT 0 0 0 1 0 0 0");
  if (with_points) dims_lines.push_back("POINTS " + std::to_string(points));
  if (s.chance(20) && dims_lines.size() > 1) {
    const std::size_t a = s.range(0, dims_lines.size() - 1), b = s.range(0, dims_lines.size() - 1);
    std::swap(dims_lines[a], dims_lines[b]);
  }
  for (std::string& l : dims_lines) header.push_back(l);
  if (s.chance(10))
    header.insert(header.begin() + static_cast<std::ptrdiff_t>(s.range(0, header.size())), "# a comment");
  if (s.chance(5)) header.insert(header.begin() + static_cast<std::ptrdiff_t>(s.range(1, header.size())), "");
  header.push_back(std::string("DATA ") + kPcdData[data]);
  return header;
}

// The values, point by point (binary_compressed: field after field, LZF); the points into g.points.
void write_pcd_values(ByteSource& s, const std::vector<PcdField>& fields, std::uint64_t points, int data,
                      const std::string& eol, Generated& g) {
  std::vector<std::vector<Val>> vals(fields.size());
  for (std::uint64_t i = 0; i < points; ++i) {
    float xyz[3] = {0, 0, 0};
    std::string line;
    for (std::size_t fi = 0; fi < fields.size(); ++fi) {
      const PcdField& f = fields[fi];
      for (std::uint64_t c = 0; c < f.count; ++c) {
        Val v = make_value(s, kTypes[f.type], f.axis >= 0);
        if (f.axis >= 0) xyz[f.axis] = v.as_float;
        if (data == 0) line += (line.empty() ? "" : separator(s)) + v.text;
        if (data == 1) g.bytes += v.le;
        if (data == 2) vals[fi].push_back(std::move(v));
      }
    }
    if (data == 0) g.bytes += line + eol;
    g.points.push_back(tigris::Point3{xyz[0], xyz[1], xyz[2]});
  }
  if (data == 2) {
    std::string raw;  // field after field, each for all points
    for (const auto& column : vals)
      for (const Val& v : column) raw += v.le;
    const std::string packed = lzf_compress(raw);
    g.bytes += le_bytes(packed.size(), 4) + le_bytes(raw.size(), 4) + packed;
  }
}

}  // namespace

Generated generate_pcd(ByteSource& s) {
  Generated g;
  const int data = static_cast<int>(s.range(0, 2));  // ascii, binary, binary_compressed
  const bool crlf = s.chance(20);
  const std::string eol = crlf ? "\r\n" : "\n";
  g.variant = std::string("pcd ") + kPcdData[data] + (crlf ? " crlf" : "");
  const std::vector<PcdField> fields = random_pcd_fields(s);
  const std::uint64_t points = s.range(1, 24);
  for (const std::string& l : pcd_header(s, fields, points, data)) g.bytes += l + eol;
  write_pcd_values(s, fields, points, data, eol, g);
  return g;
}

std::string lzf_compress(const std::string& in) {
  std::string out;
  const std::size_t n = in.size();
  std::vector<long> last(1 << 12, -1);  // hash of 3 bytes -> last position
  std::string literal;
  auto flush = [&]() {
    for (std::size_t k = 0; k < literal.size(); k += 32) {
      const std::size_t len = std::min<std::size_t>(32, literal.size() - k);
      out.push_back(static_cast<char>(len - 1));
      out.append(literal, k, len);
    }
    literal.clear();
  };
  std::size_t i = 0;
  while (i < n) {
    std::size_t best = 0, dist = 0;
    if (i + 3 <= n) {
      const unsigned h = ((static_cast<unsigned char>(in[i]) << 8) ^ (static_cast<unsigned char>(in[i + 1]) << 4) ^
                          static_cast<unsigned char>(in[i + 2])) &
                         0xFFF;
      const long cand = last[h];
      last[h] = static_cast<long>(i);
      if (cand >= 0 && i - static_cast<std::size_t>(cand) <= 8192) {
        std::size_t len = 0;
        while (i + len < n && len < 264 && in[static_cast<std::size_t>(cand) + len] == in[i + len]) ++len;
        if (len >= 3) {
          best = len;
          dist = i - static_cast<std::size_t>(cand);
        }
      }
    }
    if (best == 0) {
      literal.push_back(in[i++]);
      continue;
    }
    flush();
    const std::size_t len = best - 2, off = dist - 1;
    if (len < 7) {
      out.push_back(static_cast<char>((len << 5) | (off >> 8)));
    } else {
      out.push_back(static_cast<char>((7 << 5) | (off >> 8)));
      out.push_back(static_cast<char>(len - 7));
    }
    out.push_back(static_cast<char>(off & 0xFF));
    i += best;
  }
  flush();
  return out;
}

}  // namespace tigris_fuzz
