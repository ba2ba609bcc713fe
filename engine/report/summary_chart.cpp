#include "engine/report/summary_chart.hpp"

#include <algorithm>
#include <cstdio>

namespace trackassoc::report {
namespace {

constexpr Rgb kCorrect = rgb(0x2ca02c), kFalse = rgb(0xd62728), kMissed = rgb(0xc7c7c7), kInk = rgb(0x222222);
constexpr int kTop = 92, kRow = 28, kBottom = 44;

std::string label(const char* format, double v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string time_label(double s) {
  return s < 1e-3 ? label("%.0f us", 1e6 * s) : s < 1.0 ? label("%.1f ms", 1e3 * s) : label("%.2f s", s);
}

}  // namespace

int summary_chart_height(std::size_t rows) { return kTop + kRow * static_cast<int>(rows) + kBottom; }

void draw_summary_chart(Canvas& c, const std::string& title, const std::vector<SummaryRow>& rows) {
  int name_width = 60;
  for (const auto& r : rows)
    name_width = std::max(name_width, Canvas::text_width(r.name, r.highlight ? Face::kBold : Face::kRegular));
  const double left = 24 + name_width + 12, right = c.width() - 190.0, width = right - left;
  c.text(24, 28, title, kInk, Anchor::kStart, Face::kBold);
  // Legend of the three shares.
  double lx = 24;
  const std::pair<Rgb, const char*> legend[] = {
      {kCorrect, "correct"}, {kFalse, "false"}, {kMissed, "missed"}};
  for (const auto& [colour, name] : legend) {
    c.fill_rect(lx, 44, 14, 14, colour);
    c.text(lx + 20, 56, name, kInk);
    lx += 20 + Canvas::text_width(name) + 24;
  }
  c.text(lx + 8, 56, "share of the targets seen by 2+ sensors; time: statistics + cost + solve",
         rgb(0x555555));
  for (int p = 0; p <= 100; p += 20) {
    const double x = left + width * p / 100.0;
    c.line(x, kTop - 8, x, kTop + kRow * static_cast<double>(rows.size()), {rgb(0xdddddd), 1.0});
    c.text(x, kTop - 12, std::to_string(p) + " %", rgb(0x555555), Anchor::kMiddle);
  }
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const SummaryRow& r = rows[i];
    const double y = kTop + kRow * static_cast<double>(i);
    if (r.highlight) c.fill_rect(8, y, c.width() - 16, kRow, rgb(0xfff3c4));
    const Face face = r.highlight ? Face::kBold : Face::kRegular;
    c.text(left - 12, y + 19, r.name, kInk, Anchor::kEnd, face);
    double x = left;
    const std::pair<double, Rgb> parts[] = {
        {r.correct, kCorrect}, {r.false_rate, kFalse}, {r.missed, kMissed}};
    for (const auto& [share, colour] : parts) {
      c.fill_rect(x, y + 5, width * share, kRow - 10, colour);
      x += width * share;
    }
    c.text(right + 12, y + 19, label("%.1f %%", 100.0 * r.correct), kInk, Anchor::kStart, face);
    c.text(c.width() - 20.0, y + 19, time_label(r.time_s), kInk, Anchor::kEnd);
  }
  const double bottom = kTop + kRow * static_cast<double>(rows.size());
  c.text(right + 12, bottom + 22, "correct", rgb(0x555555));
  c.text(c.width() - 20.0, bottom + 22, "time", rgb(0x555555), Anchor::kEnd);
}

void write_summary_chart(const std::string& path, ImageFormat format, const std::string& title,
                         const std::vector<SummaryRow>& rows) {
  write_picture(path, format, kSummaryWidth, summary_chart_height(rows.size()),
                [&](Canvas& canvas) { draw_summary_chart(canvas, title, rows); });
}

}  // namespace trackassoc::report
