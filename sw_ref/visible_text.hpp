// User text quoted in an error message: control bytes (NUL above all, which would end the
// message at what(), and escape sequences, which would act on the terminal) shown as \xNN, and
// a long text cut to `limit` bytes, saying so.
#pragma once

#include <string>

namespace tigris {

inline std::string visible_text(const std::string& text, std::size_t limit = 200) {
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (i == limit) return out + "... (" + std::to_string(text.size() - limit) + " more bytes)";
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c == 0x7f) {
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    } else {
      out += static_cast<char>(c);
    }
  }
  return out;
}

}  // namespace tigris
