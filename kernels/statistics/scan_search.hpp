// One common time of the per-scan candidate index (kernels/statistics/scan_candidates.hpp): each
// sensor's tracks valid there gathered once (position, position block, spread and ball radius), then
// for each pair of sensors whose boxes, widened by the largest bound, meet, a uniform grid over one
// side's tracks searched with the other side's balls, every pair within its bound
// (kernels/statistics/scan_bound.hpp) a hit. The driver (scan_candidates.cpp) runs it over blocks
// of common times and counts each pair's hits.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "kernels/core/allocation_gauge.hpp"
#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc {

// A hit of the index: sensor pair slot, track of the first sensor, track of the second, and the
// number of scans at which the pair was within its bound (saturating at 65 535; the slot fits 16
// bits since S ≤ 256 is checked), so a hit takes 12 bytes.
struct ScanHit {
  int32_t a, b;
  uint16_t slot, count;
  friend bool operator<(const ScanHit& x, const ScanHit& y) {
    return x.slot != y.slot ? x.slot < y.slot : (x.a != y.a ? x.a < y.a : x.b < y.b);
  }
  bool same_pair(const ScanHit& y) const { return slot == y.slot && a == y.a && b == y.b; }
};
static_assert(sizeof(ScanHit) == 12);

// The tracks valid at each common time, ascending: tracks at(k). Built from the spans, O(Σ spans + K).
struct ValidByTime {
  std::vector<int64_t> offset;  // K + 1
  std::vector<int32_t> track;
  std::span<const int32_t> at(std::size_t k) const {
    return {track.data() + offset[k], static_cast<std::size_t>(offset[k + 1] - offset[k])};
  }
};
ValidByTime valid_by_time(const AlignedTracks& x);

// A scan searched in part (the count filter's interior skipping, scan_candidates.hpp): only the
// pairs with a track at its edge there, within its margin (per sensor and track) of its span's first
// or last scan, the other pairs left untested.
struct PartialScan {
  std::span<const std::vector<int32_t>> margin;
  bool edge(const AlignedTracks& x, int32_t sensor, int32_t track, int32_t k) const {
    const AlignedTracks::Span sp = x.span(track);
    const int32_t m = margin[sensor][track];
    return k - sp.begin < m || sp.end - 1 - k < m;
  }
};

// The search of one common time, with one thread's scratch (kept from time to time).
class ScanSearch {
 public:
  ScanSearch();
  ~ScanSearch();
  ScanSearch(const ScanSearch&) = delete;
  ScanSearch& operator=(const ScanSearch&) = delete;

  // Appends the hits of common time k (count 1; a pair may appear more than once) of every pair of
  // sensors s < t (slot s·S + t); `valid` per sensor, c2 the per-scan cap times radius_scale².
  // `gauge` is told the hits as they grow. `partial` (optional): only the pairs it names (a scan
  // with no track at its edge costs one look at each valid track).
  void scan(std::span<const AlignedTracks* const> sensors, std::span<const ValidByTime> valid, int32_t k,
            double c2, std::vector<ScanHit>& out, AllocationGauge* gauge,
            const PartialScan* partial = nullptr);

  // The most one ScanSearch's scratch holds on `sensors` (the tracks valid at one time gathered,
  // the points near the other sensor, the grid and its table), for the memory gauge.
  static double scratch_bytes(std::span<const AlignedTracks* const> sensors,
                              std::span<const ValidByTime> valid);

 private:
  struct Scratch;
  std::unique_ptr<Scratch> scratch_;
};

}  // namespace trackassoc
