// The bitmap font of the pictures: printable ASCII of DejaVu Sans at two pixel sizes, rasterised
// once by scripts/make_font.py into engine/report/font_data.cpp (4-bit coverage per pixel), so the
// binary draws labels without a font library. Proportional: each glyph has its own advance.
#pragma once

#include <array>
#include <string>

namespace trackassoc::report {

struct Glyph {
  int advance;           // pen advance [px]
  int dx, dy;            // top-left of the bitmap from the pen on the baseline (dy < 0: above)
  int width, height;     // bitmap size [px]
  const char* coverage;  // width·height hex digits, row by row, 0 = empty .. f = full
};

struct FontFace {
  int size, ascent, descent;     // [px]
  std::array<Glyph, 95> glyphs;  // ASCII 32..126
  // The glyph of `c`; anything outside printable ASCII is drawn as '?'.
  const Glyph& glyph(char c) const {
    const int code = static_cast<unsigned char>(c);
    return glyphs[(code >= 32 && code <= 126 ? code : '?') - 32];
  }
  int text_width(const std::string& text) const {
    int w = 0;
    for (char c : text) w += glyph(c).advance;
    return w;
  }
};

const FontFace& regular_face();  // 13 px, labels
const FontFace& bold_face();     // 16 px bold, titles

}  // namespace trackassoc::report
