// Point-cloud files (see cloud_io.hpp). KITTI .bin is read and written here directly; .pcd and
// .ply go through PCL 1.13, whose own console messages are silenced while it works, so the
// InputError raised here is the one message the user sees.
//
// Robustness: PCL is handed a .pcd/.ply file only after its header has passed a strict check
// here (the grammar of PCD v0.7 / PLY 1.0, and counts that the file size can hold). PCL 1.13
// crashes on some malformed headers, and it sizes its buffers from the header before reading
// the body, so a corrupt count would make it allocate (and touch) gigabytes. Whatever PCL then
// returns is checked again (x, y, z fields present, float32 or float64, buffer large enough)
// before a byte of it is read.
#include "cloud_io.hpp"

#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <vector>

namespace tigris {
namespace {

namespace fs = std::filesystem;

// Silences PCL's console output for the lifetime of the object, then restores the old level.
class QuietPcl {
 public:
  QuietPcl() : saved_(pcl::console::getVerbosityLevel()) {
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  }
  ~QuietPcl() { pcl::console::setVerbosityLevel(saved_); }
  QuietPcl(const QuietPcl&) = delete;
  QuietPcl& operator=(const QuietPcl&) = delete;

 private:
  pcl::console::VERBOSITY_LEVEL saved_;
};

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw InputError(path + ": " + what);
}

// A word from a file, fit for an error message: at most 32 characters, non-printable bytes
// shown as '?'.
std::string printable(const std::string& word) {
  std::string out = word.substr(0, 32);
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7E) c = '?';
  return word.size() > 32 ? out + "..." : out;
}

std::uintmax_t file_size_or_fail(const std::string& path) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) fail(path, "cannot determine the file size (" + ec.message() + ")");
  return size;
}

// ---------------------------------------------------------------------------------------------
// KITTI .bin: float32 x, y, z, reflectance, little-endian, 16 bytes a point, no header. The bytes
// are assembled explicitly, so the code is independent of the host's byte order.

std::uint32_t u32_from_le(const unsigned char* b) {
  return static_cast<std::uint32_t>(b[0]) | (static_cast<std::uint32_t>(b[1]) << 8) |
         (static_cast<std::uint32_t>(b[2]) << 16) | (static_cast<std::uint32_t>(b[3]) << 24);
}

float float_from_le(const unsigned char* b) {
  const std::uint32_t u = u32_from_le(b);
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

void float_to_le(float f, unsigned char* b) {
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  for (int i = 0; i < 4; ++i) b[i] = static_cast<unsigned char>((u >> (8 * i)) & 0xFFu);
}

PointCloud load_bin(const std::string& path) {
  const std::uintmax_t size = file_size_or_fail(path);
  if (size % 16 != 0) {
    std::ostringstream msg;
    msg << "file size " << size
        << " bytes is not a multiple of 16 (a KITTI .bin holds float32 x, y, z, reflectance per"
           " point); the file is truncated or not a KITTI scan";
    fail(path, msg.str());
  }
  if (size > static_cast<std::uintmax_t>(std::numeric_limits<std::streamsize>::max()) ||
      size / 16 > std::numeric_limits<std::uint32_t>::max())
    fail(path, "file too large");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the file for reading");
  std::vector<unsigned char> bytes(static_cast<std::size_t>(size));
  if (size > 0 &&
      !in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size)))
    fail(path, "read error");
  PointCloud cloud(static_cast<std::size_t>(size / 16));
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const unsigned char* p = bytes.data() + 16 * i;
    cloud[i] = Point3{float_from_le(p), float_from_le(p + 4), float_from_le(p + 8)};
  }
  return cloud;
}

void save_bin(const std::string& path, const PointCloud& cloud) {
  std::vector<unsigned char> bytes(16 * cloud.size(), 0);  // reflectance 0
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    float_to_le(cloud[i].x, &bytes[16 * i]);
    float_to_le(cloud[i].y, &bytes[16 * i + 4]);
    float_to_le(cloud[i].z, &bytes[16 * i + 8]);
  }
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) fail(path, "cannot open the file for writing");
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) fail(path, "write error");
}

// ---------------------------------------------------------------------------------------------
// Header pre-checks for .pcd and .ply (see the comment at the top of the file). They accept the
// well-formed headers of the PCD v0.7 and PLY 1.0 specifications and reject everything else:
// PCL 1.13 itself crashes on some malformed headers (an unknown PCD keyword, for one).

constexpr std::size_t kMaxHeader = 64 * 1024;    // generous: real headers are a few hundred bytes
constexpr std::uint64_t kMaxCount = 0x7FFFFFFF;  // PCL keeps point counts in int

struct HeaderLine {
  std::vector<std::string> words;  // split at blanks and tabs
  bool blank = false;              // the line holds nothing but white space
  bool control = false;            // the line holds a control character (other than a tab)
};

// Splits the beginning of a file into complete ('\n'-terminated) lines, up to and including the
// line that `is_last` accepts. Returns false when no such line is found in the first kMaxHeader
// bytes. `header_end` receives the offset of the first byte after that line.
template <class IsLast>
bool read_header_lines(const std::string& path, IsLast is_last, std::vector<HeaderLine>& lines,
                       std::uint64_t& header_end) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the file for reading");
  std::string head(kMaxHeader, '\0');
  in.read(&head[0], static_cast<std::streamsize>(kMaxHeader));
  head.resize(static_cast<std::size_t>(in.gcount()));
  std::size_t pos = 0;
  while (pos < head.size()) {
    const std::size_t nl = head.find('\n', pos);
    if (nl == std::string::npos) return false;
    std::string text = head.substr(pos, nl - pos);
    pos = nl + 1;
    const bool empty = text.empty();  // PCL skips only truly empty lines
    if (!text.empty() && text.back() == '\r') text.pop_back();
    HeaderLine line;
    std::string word;
    for (char c : text) {
      if (c == ' ' || c == '\t') {
        if (!word.empty()) line.words.push_back(word);
        word.clear();
      } else {
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) line.control = true;
        word.push_back(c);
      }
    }
    if (!word.empty()) line.words.push_back(word);
    line.blank = line.words.empty() && !empty;
    lines.push_back(line);
    if (is_last(line)) {
      header_end = pos;
      return true;
    }
  }
  return false;
}

// A decimal count in [0, max]; false on anything else (sign, garbage, overflow).
bool parse_count(const std::string& s, std::uint64_t max, std::uint64_t& value) {
  if (s.empty() || s.size() > 19) return false;
  value = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
    value = value * 10 + static_cast<std::uint64_t>(c - '0');
  }
  return value <= max;
}

bool parse_number(const std::string& s) {
  std::istringstream in(s);
  in.imbue(std::locale::classic());
  double d = 0.0;
  in >> d;
  return !in.fail() && in.peek() == std::char_traits<char>::eof();
}

// ASCII bodies: PCL silently reads a word that is not a number as 0 (PCD) or NaN (PLY), so every
// word is checked here: a decimal number, "nan" or "inf" (signed or not; PCL reads those right,
// and validate_cloud rejects them in x, y, z). Returns the number of words.
std::uint64_t check_ascii_body(const std::string& path, std::uint64_t header_end,
                               const char* format) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the file for reading");
  in.seekg(static_cast<std::streamoff>(header_end));
  const std::string body((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::uint64_t words = 0;
  std::size_t i = 0;
  const std::size_t n = body.size();
  auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (i < n) {
    while (i < n && space(body[i])) ++i;
    if (i == n) break;
    std::size_t j = i;
    while (j < n && !space(body[j])) ++j;
    const char* first = body.data() + i + (body[i] == '+' ? 1 : 0);
    const char* last = body.data() + j;
    double value = 0.0;
    const std::from_chars_result r = std::from_chars(first, last, value);
    if (first == last || r.ptr != last ||
        (r.ec != std::errc() && r.ec != std::errc::result_out_of_range)) {
      std::ostringstream msg;
      msg << "corrupt " << format << " file: value " << words + 1 << " of the data ('"
          << printable(body.substr(i, j - i)) << "') is not a valid number";
      fail(path, msg.str());
    }
    ++words;
    i = j;
  }
  return words;
}

void precheck_pcd(const std::string& path, std::uint64_t file_size) {
  std::vector<HeaderLine> lines;
  std::uint64_t header_end = 0;
  const bool complete = read_header_lines(
      path, [](const HeaderLine& l) { return !l.words.empty() && l.words[0] == "DATA"; }, lines,
      header_end);
  if (!complete) {
    const bool looks_pcd = !lines.empty() && !lines[0].words.empty() &&
                           (lines[0].words[0][0] == '#' || lines[0].words[0] == "VERSION" ||
                            lines[0].words[0] == "FIELDS");
    fail(path, looks_pcd ? "truncated or corrupt PCD file: no complete DATA line in the header"
                         : "not a PCD file (no PCD header found)");
  }
  // The keywords of PCD v0.7, in the order the format prescribes; each appears at most once.
  static const char* const kKeys[] = {"VERSION", "FIELDS", "SIZE",      "TYPE",   "COUNT",
                                      "WIDTH",   "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
  constexpr int kNumKeys = 10;
  bool seen[kNumKeys] = {};
  int last = -1;
  std::size_t n_fields = 0;
  std::vector<std::uint64_t> sizes, counts;
  std::vector<char> types;
  std::uint64_t width = 0, height = 0, points = 0;
  std::string kind;
  auto corrupt = [&](const std::string& what) { fail(path, "corrupt PCD header (" + what + ")"); };
  for (const HeaderLine& line : lines) {
    if (line.blank) corrupt("a line holds only white space");
    if (line.control) corrupt("a control character in the header");
    if (line.words.empty() || line.words[0][0] == '#') continue;
    std::string key = line.words[0];
    if (key == "COLUMNS") key = "FIELDS";  // PCD v0.5 spelling
    int k = 0;
    while (k < kNumKeys && key != kKeys[k]) ++k;
    if (k == kNumKeys) corrupt("unknown line '" + printable(line.words[0]) + "'");
    if (seen[k] || k < last) corrupt(key + " is repeated or out of order");
    seen[k] = true;
    last = k;
    const std::vector<std::string> args(line.words.begin() + 1, line.words.end());
    if (key == "FIELDS") {
      n_fields = args.size();
      if (n_fields == 0) corrupt("FIELDS names no field");
    } else if (key == "SIZE" || key == "COUNT") {
      if (args.size() != n_fields) corrupt(key + " does not list one value per field");
      for (const std::string& a : args) {
        std::uint64_t v = 0;
        if (!parse_count(a, key == "SIZE" ? 8 : 65536, v) || v == 0 ||
            (key == "SIZE" && v != 1 && v != 2 && v != 4 && v != 8))
          corrupt("bad " + key + " value '" + printable(a) + "'");
        (key == "SIZE" ? sizes : counts).push_back(v);
      }
    } else if (key == "TYPE") {
      if (args.size() != n_fields || !seen[2]) corrupt("TYPE does not list one type per field");
      for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& t = args[i];
        const bool ok = (t == "F" && (sizes[i] == 4 || sizes[i] == 8)) || t == "I" || t == "U";
        if (!ok) corrupt("bad TYPE '" + printable(t) + "' for SIZE " + std::to_string(sizes[i]));
        types.push_back(t[0]);
      }
    } else if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
      std::uint64_t v = 0;
      if (args.size() != 1 || !parse_count(args[0], kMaxCount, v)) corrupt(key + " is not a count");
      (key == "WIDTH" ? width : key == "HEIGHT" ? height : points) = v;
    } else if (key == "VIEWPOINT") {
      if (args.size() != 7) corrupt("VIEWPOINT needs 7 numbers");
      for (const std::string& a : args)
        if (!parse_number(a)) corrupt("VIEWPOINT needs 7 numbers");
    } else if (key == "DATA") {
      if (args.size() != 1 ||
          (args[0] != "ascii" && args[0] != "binary" && args[0] != "binary_compressed"))
        corrupt("DATA must be ascii, binary or binary_compressed");
      kind = args[0];
    }
  }
  if (!seen[1] || !seen[2] || !seen[3] || !seen[8])
    corrupt("FIELDS, SIZE, TYPE and POINTS are required");
  if (seen[6] && !seen[5]) corrupt("HEIGHT without WIDTH");
  if (seen[5] && width * (seen[6] ? height : 1) != points)
    corrupt("WIDTH x HEIGHT differs from POINTS");
  if (points == 0) fail(path, "the point cloud is empty (POINTS 0)");

  std::uint64_t step = 0, values = 0;  // bytes and values per point
  for (std::size_t i = 0; i < n_fields; ++i) {
    const std::uint64_t count = counts.empty() ? 1 : counts[i];
    step += sizes[i] * count;
    values += count;
  }
  if (step > (1u << 20)) corrupt("a point record of more than 1 MiB");
  const std::uint64_t body = file_size > header_end ? file_size - header_end : 0;
  std::uint64_t needed = 0;  // bytes of data the header announces (at least)
  if (kind == "binary") {
    needed = points * step;
  } else if (kind == "ascii") {
    needed = points * values * 2 - 1;  // a character and a separator per value
    if (needed <= body) {
      const std::uint64_t words = check_ascii_body(path, header_end, "PCD");
      if (words != points * values) {
        std::ostringstream msg;
        msg << "truncated or corrupt PCD file: the header announces " << points << " points of "
            << values << " values but the data holds " << words << " values";
        fail(path, msg.str());
      }
    }
  } else {
    // binary_compressed: uint32 compressed size, uint32 uncompressed size, LZF data. PCL sizes
    // its buffer from the uncompressed size; it must be what the header announces.
    needed = 8;
    if (body >= 8) {
      unsigned char sz[8];
      std::ifstream in(path, std::ios::binary);
      in.seekg(static_cast<std::streamoff>(header_end));
      if (!in.read(reinterpret_cast<char*>(sz), 8)) fail(path, "read error");
      const std::uint64_t compressed = u32_from_le(sz), uncompressed = u32_from_le(sz + 4);
      if (uncompressed != points * step)
        fail(path, "corrupt PCD file (the compressed block does not hold " +
                       std::to_string(points) + " points)");
      needed = 8 + compressed;
    }
  }
  if (needed > body) {
    std::ostringstream msg;
    msg << "truncated or corrupt PCD file: the header announces " << points << " points (" << needed
        << " bytes of " << kind << " data at least) but the file holds only " << body
        << " bytes of data";
    fail(path, msg.str());
  }
}

void precheck_ply(const std::string& path, std::uint64_t file_size) {
  std::vector<HeaderLine> lines;
  std::uint64_t header_end = 0;
  const bool complete = read_header_lines(
      path, [](const HeaderLine& l) { return l.words.size() == 1 && l.words[0] == "end_header"; },
      lines, header_end);
  if (lines.empty() || lines[0].words.size() != 1 || lines[0].words[0] != "ply")
    fail(path, "not a PLY file (it does not start with a 'ply' line)");
  if (!complete) fail(path, "truncated or corrupt PLY file: no end_header line in the header");
  auto corrupt = [&](const std::string& what) { fail(path, "corrupt PLY header (" + what + ")"); };
  static const std::vector<std::pair<std::string, int>> kTypes = {
      {"char", 1},  {"uchar", 1},  {"short", 2},   {"ushort", 2}, {"int", 4},   {"uint", 4},
      {"float", 4}, {"double", 8}, {"int8", 1},    {"uint8", 1},  {"int16", 2}, {"uint16", 2},
      {"int32", 4}, {"uint32", 4}, {"float32", 4}, {"float64", 8}};
  auto type_size = [&](const std::string& t) {
    for (const auto& kv : kTypes)
      if (kv.first == t) return kv.second;
    corrupt("unknown property type '" + printable(t) + "'");
    return 0;
  };
  std::string format;
  bool have_vertex = false;
  std::uint64_t elem_count = 0, elem_bytes = 0, elem_values = 0;  // current element
  std::uint64_t min_bytes = 0, min_values = 0;                    // whole body, at least
  bool in_element = false, in_vertex = false;
  auto close_element = [&]() {
    if (!in_element) return;
    min_bytes += elem_count * elem_bytes;
    min_values += elem_count * elem_values;
  };
  for (std::size_t i = 1; i + 1 < lines.size(); ++i) {
    const std::vector<std::string>& w = lines[i].words;
    if (lines[i].blank || w.empty()) corrupt("an empty line");
    if (lines[i].control) corrupt("a control character in the header");
    if (w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "format") {
      if (!format.empty() || i != 1 || w.size() != 3 || w[2] != "1.0" ||
          (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian"))
        corrupt(
            "the second line must be 'format ascii|binary_little_endian|binary_big_endian"
            " 1.0'");
      format = w[1];
    } else if (w[0] == "element") {
      std::uint64_t n = 0;
      if (w.size() != 3 || !parse_count(w[2], kMaxCount, n)) corrupt("bad element line");
      close_element();
      in_element = true;
      elem_count = n;
      elem_bytes = elem_values = 0;
      in_vertex = w[1] == "vertex";
      if (w[1] == "vertex") {
        if (have_vertex) corrupt("two vertex elements");
        have_vertex = true;
      }
    } else if (w[0] == "property") {
      if (!in_element) corrupt("a property before any element");
      if (w.size() == 3) {
        elem_bytes += static_cast<std::uint64_t>(type_size(w[1]));
      } else if (w.size() == 5 && w[1] == "list") {
        // PCL 1.13 shifts the vertex fields after a list (x read from the list's values) or
        // aborts on an int/uint count: refuse such files rather than hand them over.
        if (in_vertex)
          fail(path, "the vertex element has a list property ('" + printable(w[4]) +
                         "'), which PCL 1.13 reads wrongly; keep only scalar properties "
                         "(e.g. re-save the cloud with x, y, z)");
        const int count_size = type_size(w[2]);
        type_size(w[3]);
        if (w[2] == "float" || w[2] == "double" || w[2] == "float32" || w[2] == "float64")
          corrupt("a list count must be an integer type");
        elem_bytes += static_cast<std::uint64_t>(count_size);  // an empty list at least
      } else {
        corrupt("bad property line");
      }
      ++elem_values;
    } else {
      corrupt("unknown line '" + printable(w[0]) + "'");
    }
  }
  close_element();
  if (format.empty()) corrupt("no format line");
  if (!have_vertex) fail(path, "the PLY file has no vertex element (no points)");
  const std::uint64_t body = file_size > header_end ? file_size - header_end : 0;
  const std::uint64_t needed =
      format == "ascii" ? (min_values == 0 ? 0 : 2 * min_values - 1) : min_bytes;
  if (needed > body) {
    std::ostringstream msg;
    msg << "truncated or corrupt PLY file: the header announces " << needed
        << " bytes of data at least but the file holds only " << body;
    fail(path, msg.str());
  }
  if (format == "ascii" && check_ascii_body(path, header_end, "PLY") < min_values)
    fail(path, "truncated or corrupt PLY file: fewer values than the header announces");
}

// ---------------------------------------------------------------------------------------------
// x, y, z out of a PCL blob, checked field by field (float32, or float64 rounded to float32).

PointCloud xyz_from_blob(const pcl::PCLPointCloud2& blob, const std::string& path) {
  const pcl::PCLPointField* fields[3] = {nullptr, nullptr, nullptr};
  const char* names[3] = {"x", "y", "z"};
  for (const pcl::PCLPointField& f : blob.fields)
    for (int a = 0; a < 3; ++a)
      if (f.name == names[a] && fields[a] == nullptr) fields[a] = &f;
  for (int a = 0; a < 3; ++a) {
    if (fields[a] == nullptr) fail(path, std::string("the file has no '") + names[a] + "' field");
    const auto type = fields[a]->datatype;
    if (type != pcl::PCLPointField::FLOAT32 && type != pcl::PCLPointField::FLOAT64)
      fail(path, std::string("field '") + names[a] + "' is not float32 or float64");
    const std::uint64_t bytes = type == pcl::PCLPointField::FLOAT32 ? 4 : 8;
    if (static_cast<std::uint64_t>(fields[a]->offset) + bytes > blob.point_step)
      fail(path, "corrupt file (a field lies outside the point record)");
  }
  const std::uint64_t width = blob.width, height = blob.height, step = blob.point_step;
  const std::uint64_t row_step = blob.row_step != 0 ? blob.row_step : width * step;
  const std::uint64_t n = width * height;
  if (n > 0 && (step == 0 || row_step < width * step ||
                (height - 1) * row_step + width * step > blob.data.size()))
    fail(path, "corrupt file (the point data is shorter than the header announces)");
  if (n > std::numeric_limits<std::uint32_t>::max()) fail(path, "too many points");

  PointCloud cloud(static_cast<std::size_t>(n));
  std::size_t i = 0;
  for (std::uint64_t row = 0; row < height; ++row) {
    for (std::uint64_t col = 0; col < width; ++col, ++i) {
      const std::uint8_t* rec = blob.data.data() + row * row_step + col * step;
      float v[3];
      for (int a = 0; a < 3; ++a) {
        const std::uint8_t* p = rec + fields[a]->offset;
        if (fields[a]->datatype == pcl::PCLPointField::FLOAT32) {
          std::memcpy(&v[a], p, 4);
        } else {
          double d;
          std::memcpy(&d, p, 8);
          v[a] = static_cast<float>(d);
        }
      }
      cloud[i] = Point3{v[0], v[1], v[2]};
    }
  }
  return cloud;
}

PointCloud load_pcd(const std::string& path) {
  precheck_pcd(path, file_size_or_fail(path));
  pcl::PCLPointCloud2 blob;
  int status = -1;
  std::string detail;
  try {
    QuietPcl quiet;
    pcl::PCDReader reader;
    status = reader.read(path, blob);
  } catch (const std::exception& e) {
    detail = e.what();
  }
  if (status < 0)
    fail(path, "unreadable or corrupt PCD file" + (detail.empty() ? "" : " (" + detail + ")"));
  return xyz_from_blob(blob, path);
}

PointCloud load_ply(const std::string& path) {
  precheck_ply(path, file_size_or_fail(path));
  pcl::PCLPointCloud2 blob;
  int status = -1;
  std::string detail;
  try {
    QuietPcl quiet;
    pcl::PLYReader reader;
    status = reader.read(path, blob);
  } catch (const std::exception& e) {
    detail = e.what();
  }
  if (status < 0)
    fail(path, "unreadable or corrupt PLY file" + (detail.empty() ? "" : " (" + detail + ")"));
  return xyz_from_blob(blob, path);
}

pcl::PointCloud<pcl::PointXYZ> to_pcl(const PointCloud& cloud) {
  pcl::PointCloud<pcl::PointXYZ> out;
  out.resize(cloud.size());
  bool dense = true;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    out[i].x = cloud[i].x;
    out[i].y = cloud[i].y;
    out[i].z = cloud[i].z;
    dense = dense && std::isfinite(cloud[i].x) && std::isfinite(cloud[i].y) &&
            std::isfinite(cloud[i].z);
  }
  out.width = static_cast<std::uint32_t>(cloud.size());
  out.height = 1;
  out.is_dense = dense;
  return out;
}

}  // namespace

PointCloud load_cloud(const std::string& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) fail(path, "no such file");
  if (!fs::is_regular_file(st)) fail(path, "not a regular file");
  const std::string ext = lower_extension(path);
  PointCloud cloud;
  if (ext == ".bin") {
    cloud = load_bin(path);
  } else if (ext == ".pcd") {
    cloud = load_pcd(path);
  } else if (ext == ".ply") {
    cloud = load_ply(path);
  } else {
    fail(path, "unknown point-cloud format '" + printable(ext) +
                   "' (expected .bin (KITTI), .pcd or .ply; the extension selects the format)");
  }
  validate_cloud(cloud, path);
  return cloud;
}

void save_cloud(const std::string& path, const PointCloud& cloud) {
  const std::string ext = lower_extension(path);
  if (ext == ".bin") {
    save_bin(path, cloud);
    return;
  }
  if (ext != ".pcd" && ext != ".ply")
    fail(path, "unknown point-cloud format '" + printable(ext) + "' (expected .bin, .pcd or .ply)");
  if (cloud.empty()) fail(path, "cannot write an empty cloud as " + ext + " (PCL refuses it)");
  const pcl::PointCloud<pcl::PointXYZ> pc = to_pcl(cloud);
  int status = -1;
  std::string detail;
  try {
    QuietPcl quiet;
    status =
        ext == ".pcd" ? pcl::io::savePCDFileBinary(path, pc) : pcl::io::savePLYFileBinary(path, pc);
  } catch (const std::exception& e) {
    detail = e.what();
  }
  if (status < 0) fail(path, "cannot write the file" + (detail.empty() ? "" : " (" + detail + ")"));
}

}  // namespace tigris
