// User text quoted in a message, written once: control bytes (NUL above all, which would end the
// message at what(), and escape sequences, which would act on the terminal) shown as \xNN, and a
// long text cut, saying so.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace tigris {

inline bool is_control_byte(unsigned char c) { return c < 0x20 || c == 0x7f; }

inline void append_escaped(std::string& out, unsigned char c) {
  static const char* hex = "0123456789abcdef";
  out += "\\x";
  out += hex[c >> 4];
  out += hex[c & 15];
}

// A name, key or path the user gave: cut to `limit` bytes.
inline std::string visible_text(const std::string& text, std::size_t limit = 200) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (i == limit) return out + "... (" + std::to_string(text.size() - limit) + " more bytes)";
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (is_control_byte(c))
      append_escaped(out, c);
    else
      out += static_cast<char>(c);
  }
  return out;
}

// A whole error message as the terminal should show it: line breaks kept, each line cut at
// `line_limit` bytes (a path or file line the user gave may be a megabyte long).
inline std::string visible_message(const std::string& message, std::size_t line_limit = 400) {
  std::string out;
  std::size_t line = 0;
  for (std::size_t i = 0; i < message.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(message[i]);
    if (c == '\n') {
      out += '\n';
      line = 0;
      continue;
    }
    if (line == line_limit) {
      const std::size_t end = message.find('\n', i);
      const std::size_t rest = (end == std::string::npos ? message.size() : end) - i;
      out += "... (" + std::to_string(rest) + " more bytes)";
      if (end == std::string::npos) break;
      i = end - 1;
      continue;
    }
    if (is_control_byte(c))
      append_escaped(out, c);
    else
      out += static_cast<char>(c);
    ++line;
  }
  return out;
}

// A word from a file's header (a binary file's bytes are mostly junk to a reader): at most 32
// characters, any byte outside printable ASCII shown as '?'.
inline std::string visible_word(std::string_view word) {
  std::string out(word.substr(0, 32));
  for (char& c : out)
    if (is_control_byte(static_cast<unsigned char>(c)) || static_cast<unsigned char>(c) > 0x7e) c = '?';
  return word.size() > 32 ? out + "..." : out;
}

}  // namespace tigris
