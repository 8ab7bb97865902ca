#include "common/terminal_text.hpp"

#include <algorithm>
#include <cstdio>

namespace clr {
namespace {

// The length of the well-formed UTF-8 sequence at the start of `s` (1 to 4), or 0 where it is not one (a stray
// continuation byte, a truncated sequence, an overlong form, a surrogate or a code point past U+10FFFF).
std::size_t utf8_length(std::string_view s) {
  const auto b = [&](std::size_t i) { return static_cast<unsigned char>(s[i]); };
  const unsigned char c = b(0);
  if (c < 0x80) return 1;
  std::size_t n = 0;
  if (c >= 0xc2 && c <= 0xdf)
    n = 2;
  else if (c >= 0xe0 && c <= 0xef)
    n = 3;
  else if (c >= 0xf0 && c <= 0xf4)
    n = 4;
  if (n == 0 || s.size() < n) return 0;
  for (std::size_t i = 1; i < n; ++i)
    if ((b(i) & 0xc0) != 0x80) return 0;
  if ((c == 0xe0 && b(1) < 0xa0) || (c == 0xed && b(1) >= 0xa0) || (c == 0xf0 && b(1) < 0x90) ||
      (c == 0xf4 && b(1) >= 0x90))
    return 0;
  return n;
}

}  // namespace

std::string terminal_safe(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t n = utf8_length(text.substr(at));
    const auto c = static_cast<unsigned char>(text[at]);
    // C1 controls (U+0080 – U+009F) are two bytes, 0xc2 0x80 – 0xc2 0x9f; terminals act on them too.
    const bool c1 = n == 2 && c == 0xc2 && static_cast<unsigned char>(text[at + 1]) < 0xa0;
    if (n == 1 && c >= 0x20 && c != 0x7f) {
      out += char(c);
    } else if (n > 1 && !c1) {
      out.append(text.substr(at, n));
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else {
      // A control character, or a byte that is no UTF-8: its value, never the byte itself.
      const std::size_t len = c1 ? 2 : 1;
      for (std::size_t i = 0; i < len; ++i) {
        char hex[5];
        std::snprintf(hex, sizeof hex, "\\x%02x", static_cast<unsigned char>(text[at + i]));
        out += hex;
      }
      at += len;
      continue;
    }
    at += std::max<std::size_t>(n, 1);
  }
  return out;
}

}  // namespace clr
