// The summary chart of `trackassoc run`: one bar per solver, split into the shares of correct,
// false and missed targets (engine/pipeline/metrics.hpp), labelled with the solver's name, its
// correct rate and its time; the highlighted row (the default pipeline) on a tinted band in bold.
#pragma once

#include <string>
#include <vector>

#include "engine/report/canvas.hpp"
#include "engine/report/figure.hpp"

namespace trackassoc::report {

struct SummaryRow {
  std::string name;
  double correct = 0.0, false_rate = 0.0, missed = 0.0;  // fractions of the targets, summing to 1
  double time_s = 0.0;
  bool highlight = false;
};

inline constexpr int kSummaryWidth = 900;
int summary_chart_height(std::size_t rows);

void draw_summary_chart(Canvas& canvas, const std::string& title, const std::vector<SummaryRow>& rows);

void write_summary_chart(const std::string& path, ImageFormat format, const std::string& title,
                         const std::vector<SummaryRow>& rows);

}  // namespace trackassoc::report
