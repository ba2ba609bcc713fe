// A local track's coasted tail (engine/pipeline/track_segments.hpp, rule (a); docs/design.md §4.9):
// a tracker that loses a target reports its track's predictions for a few scans, each with a larger
// position variance than the report before (an update keeps it about level), while it starts the
// successor. The tail is the trailing run of reports whose position variance grows by more than
// (1 + growth)² from one to the next; its start is the track's last update.
// A *lost* track (the takeover of rule (a)): a tracker that loses a target may go on updating the
// old track now and then (a plot that falls in its gate) while it starts the successor, so the old
// track's variance grows at most of its reports but not at all of them, and its tail is not one
// unbroken run of growth (Stone Soup's GNN tracker on bench/stonesoup_recordings.py's files: old and
// new tracks overlap 4-18 s; docs/status.md, "Independent recordings"). lost_after(t) asks that
// the track end coasting (its last report grows by more than (1 + growth)² from the one before)
// and that, of its reports after time t, at least kLostGrowths and at least half grow so: a track
// that keeps its variance level (a second craft tracked beside the target) is not lost, nor one
// whose missed updates fall elsewhere.
// LatestReports keeps a track's latest kCoastWindow reports as its rows stream in (any order: an
// insertion by time into a fixed array), so both are found in O(1) memory a track. The tail is
// looked for in the latest kTailWindow of them, a tail longer than kTailWindow − 1 reports cut to
// that (the last update then seems later, which makes rule (a) stricter, never laxer); a takeover
// whose overlap holds more reports than the window keeps (less one) is refused. O(kCoastWindow) a
// report.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>

namespace trackassoc {

// A track's latest kCoastWindow reports (time, position variance, row), latest last.
constexpr int kCoastWindow = 12;
constexpr int kTailWindow = 6;
constexpr int kLostGrowths = 2;
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
    const int first = std::max(0, n - kTailWindow);
    while (growth > 0.0 && k > first && grows(k, growth)) --k;
    return k;
  }
  // Report k (≥ 1) grows in position variance by more than (1 + growth)² from report k − 1.
  bool grows(int k, double growth) const {
    return variance[k] > (1.0 + growth) * (1.0 + growth) * variance[k - 1];
  }
  // The index of the latest report at or before time `t` (−1: none kept).
  int last_at_or_before(double time) const {
    int k = n - 1;
    while (k >= 0 && t[k] > time) --k;
    return k;
  }
  // True when the reports after time `after` are those of a lost track (above): the last one and
  // at least kLostGrowths and at least half of them grow by more than (1 + growth)² from the report
  // before (the report at or before `after` kept, so that the first has one).
  bool lost_after(double after, double growth) const {
    const int k0 = last_at_or_before(after);
    if (k0 < 0 || growth <= 0.0 || k0 == n - 1 || !grows(n - 1, growth)) return false;  // (ends coasting)
    int grown = 0;
    for (int k = k0 + 1; k < n; ++k) grown += grows(k, growth);
    return grown >= kLostGrowths && 2 * grown >= n - 1 - k0;
  }
};

}  // namespace trackassoc
