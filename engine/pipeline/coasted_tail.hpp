// A local track's coasted tail (engine/pipeline/track_segments.hpp, rule (a); docs/design.md §4.9):
// a tracker that loses a target reports its track's predictions for a few scans, each with a larger
// position variance than the report before (an update keeps it about level), while it starts the
// successor. The tail is the trailing run of reports whose position variance grows by more than
// (1 + growth)² from one to the next; its start is the track's last update.
// LatestReports keeps a track's latest kCoastWindow reports as its rows stream in (any order: an
// insertion by time into a fixed array), so the tail is found in O(1) memory a track, and a tail
// longer than kCoastWindow − 1 reports is cut to that (the last update then seems later, which
// makes rule (a) stricter, never laxer). O(kCoastWindow) a report.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>

namespace trackassoc {

// A track's latest kCoastWindow reports (time, position variance, row), latest last.
constexpr int kCoastWindow = 6;
struct LatestReports {
  std::array<double, kCoastWindow> t, variance;
  std::array<std::size_t, kCoastWindow> row;
  int n = 0;
  void add(double time, double var, std::size_t r) {  // insertion by time (rows mostly come in order)
    int at = 0;
    if (n == kCoastWindow) {
      if (time < t[0]) return;  // older than every kept report
      std::copy(t.begin() + 1, t.end(), t.begin());
      std::copy(variance.begin() + 1, variance.end(), variance.begin());
      std::copy(row.begin() + 1, row.end(), row.begin());
      at = kCoastWindow - 1;
    } else {
      ++n;
      at = n - 1;
    }
    while (at > 0 && t[at - 1] > time) {
      t[at] = t[at - 1], variance[at] = variance[at - 1], row[at] = row[at - 1];
      --at;
    }
    t[at] = time, variance[at] = var, row[at] = r;
  }
  // The index of the last report before the trailing run whose position variance grows by more
  // than (1 + growth)² a report.
  int held(double growth) const {
    int k = n - 1;
    const double factor = (1.0 + growth) * (1.0 + growth);
    while (growth > 0.0 && k > 0 && variance[k] > factor * variance[k - 1]) --k;
    return k;
  }
};

}  // namespace trackassoc
