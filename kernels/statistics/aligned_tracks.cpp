// The span layout of AlignedTracks and the spans of align_tracks; see
// kernels/statistics/association_statistic.hpp.
#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include "kernels/core/error.hpp"
#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc {

void AlignedTracks::allocate(std::span<const int32_t> begin, std::span<const int32_t> length) {
  const std::size_t n = track.size();
  require(begin.size() == n && length.size() == n, "AlignedTracks::allocate",
          "one span per track is needed, got " + std::to_string(begin.size()) + " for " + std::to_string(n));
  span_begin.assign(begin.begin(), begin.end());
  span_offset.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    require(length[i] >= 0 && begin[i] >= 0 && static_cast<int64_t>(begin[i]) + length[i] <= n_times,
            "AlignedTracks::allocate",
            "span of track " + std::to_string(i) + " is outside the " + std::to_string(n_times) +
                " common times");
    span_offset[i + 1] = span_offset[i] + length[i];
  }
  const auto cells = static_cast<std::size_t>(span_offset[n]);
  state.assign(cells * dim, 0.0);
  cov.assign(cells * packed_size(dim), 0.0);
  valid.assign(cells, 0);
}

void AlignedTracks::allocate_full() {
  const std::vector<int32_t> begin(track.size(), 0), length(track.size(), n_times);
  allocate(begin, length);
}

std::size_t AlignedTracks::bytes() const {
  return static_cast<std::size_t>(cells()) * bytes_per_cell(dim) +
         (track.size() + truth.size() + span_begin.size()) * sizeof(int32_t) +
         span_offset.size() * sizeof(int64_t) + times.size() * sizeof(double);
}

void AlignedTracks::check_layout(const char* who) const {
  const std::size_t n = track.size();
  if (n == 0 && span_begin.empty() && span_offset.empty() && valid.empty() && state.empty() && cov.empty())
    return;  // no tracks, nothing allocated
  bool ok = dim > 0 && span_begin.size() == n && span_offset.size() == n + 1 && span_offset[0] == 0;
  for (std::size_t i = 0; ok && i < n; ++i)
    ok = span_offset[i + 1] >= span_offset[i] && span_begin[i] >= 0 &&
         span_begin[i] + (span_offset[i + 1] - span_offset[i]) <= n_times;
  const auto c = static_cast<std::size_t>(ok ? span_offset[n] : 0);
  ok = ok && valid.size() == c && state.size() == c * dim && cov.size() == c * packed_size(dim);
  require(ok, who, "aligned tracks of sensor " + std::to_string(sensor) + " have inconsistent array sizes");
}

AlignedTracks::Span alignment_span(double first, double last, std::span<const double> times,
                                   const AlignmentOptions& options) {
  const double mx = options.max_extrapolation;
  // align_tracks skips t when (two-sided) t < first − mx or t > last + mx; (forward) t < first,
  // no report yet, or t − last > mx past the last report. Each test is monotone in t.
  const bool two_sided = options.method == AlignmentMethod::kTwoSided;
  const auto lo =
      two_sided ? std::partition_point(times.begin(), times.end(), [&](double t) { return t < first - mx; })
                : std::partition_point(times.begin(), times.end(), [&](double t) { return t < first; });
  const auto hi = two_sided
                      ? std::partition_point(lo, times.end(), [&](double t) { return !(t > last + mx); })
                      : std::partition_point(lo, times.end(), [&](double t) { return !(t - last > mx); });
  return {static_cast<int32_t>(lo - times.begin()), static_cast<int32_t>(hi - times.begin())};
}

AlignedSize aligned_size(const TrackTable& tracks, int32_t sensor, std::span<const double> common_times,
                         const AlignmentOptions& options) {
  std::unordered_map<int32_t, std::pair<double, double>> interval;  // track → [first, last] report time
  for (std::size_t r = 0; r < tracks.size(); ++r)
    if (tracks.sensor[r] == sensor) {
      auto [it, fresh] = interval.try_emplace(tracks.track[r], tracks.t[r], tracks.t[r]);
      if (!fresh) {
        it->second.first = std::min(it->second.first, tracks.t[r]);
        it->second.second = std::max(it->second.second, tracks.t[r]);
      }
    }
  AlignedSize size;
  size.tracks = static_cast<int64_t>(interval.size());
  for (const auto& [track, t] : interval)
    size.cells += alignment_span(t.first, t.second, common_times, options).size();
  return size;
}

}  // namespace trackassoc
