// Input text shown in an error line (issue 30, README Reliability): every preview of a user's bytes
// goes through printable_text, so that an error never rings the terminal bell, never sends an
// escape sequence to the terminal and is never cut off at a NUL byte (what() is a C string).
//   printable_text("a\x07b")      -> "a\x07b" written as the four characters \ x 0 7
//   quoted_preview(field, 40)     -> "'first 40 bytes...'" escaped as above
//   not_utf8_text_reason(head, "UTF-8 CSV") -> "" or "not UTF-8 text (UTF-16? save as UTF-8 CSV): ..."
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace trackassoc {

// `s` with every byte that is not printable text written as \xHH: the C0 controls (NUL, bell,
// escape, tab, newline ...), DEL, the C1 controls (U+0080..U+009F, which some terminals obey),
// and bytes that are not part of a well-formed UTF-8 sequence. Printable ASCII and well-formed
// UTF-8 (σ, °, –) are kept, so an already printable message is returned unchanged and the
// function may be applied twice.
inline std::string printable_text(std::string_view s) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(s.size());
  auto escape = [&](unsigned char c) {
    out += "\\x";
    out += kHex[c >> 4];
    out += kHex[c & 15];
  };
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
      ++i;
      continue;
    }
    // A well-formed UTF-8 sequence (no overlong form, no surrogate, <= U+10FFFF) of length n.
    std::size_t n = c >= 0xc2 && c <= 0xdf ? 2 : c >= 0xe0 && c <= 0xef ? 3 : c >= 0xf0 && c <= 0xf4 ? 4 : 0;
    uint32_t cp = n == 2 ? c & 0x1fu : n == 3 ? c & 0x0fu : c & 0x07u;
    for (std::size_t k = 1; k < n; ++k) {
      const auto d = i + k < s.size() ? static_cast<unsigned char>(s[i + k]) : 0;
      if ((d & 0xc0) != 0x80) {
        n = 0;
        break;
      }
      cp = (cp << 6) | (d & 0x3fu);
    }
    const bool well_formed = n > 0 && !(n == 3 && cp < 0x800) &&
                             !(n == 4 && (cp < 0x10000 || cp > 0x10ffff)) &&
                             !(cp >= 0xd800 && cp <= 0xdfff) && !(cp >= 0x80 && cp <= 0x9f);
    if (!well_formed) {
      escape(c);
      ++i;
      continue;
    }
    out.append(s.substr(i, n));
    i += n;
  }
  return out;
}

// 'the first `max` bytes of s' (then "..." when longer), escaped by printable_text: the one form of
// a quoted preview of input in an error message.
inline std::string quoted_preview(std::string_view s, std::size_t max = 40) {
  std::string out(1, '\'');  // (appended, not "'" + string: GCC 12's -Wrestrict false positive)
  out += printable_text(s.substr(0, max));
  out += s.size() > max ? "...'" : "'";
  return out;
}

// Why the start of a text input (CSV, JSON) is not UTF-8 text, or "" when it may be: a UTF-16
// byte-order mark (FF FE, FE FF; Excel's "Unicode text"), or a NUL byte, which UTF-8 text never
// holds but UTF-16 text of ASCII characters holds in every other byte. `save_as` names the fix
// ("UTF-8 CSV").
inline std::string not_utf8_text_reason(std::string_view head, const std::string& save_as) {
  const bool bom =
      head.size() >= 2 &&
      ((static_cast<unsigned char>(head[0]) == 0xff && static_cast<unsigned char>(head[1]) == 0xfe) ||
       (static_cast<unsigned char>(head[0]) == 0xfe && static_cast<unsigned char>(head[1]) == 0xff));
  if (!bom && head.find('\0') == std::string_view::npos) return "";
  return "not UTF-8 text (UTF-16? save as " + save_as + "): found " +
         (bom ? "a UTF-16 byte-order mark" : "NUL bytes");
}

}  // namespace trackassoc
