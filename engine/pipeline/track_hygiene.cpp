// Track hygiene; see engine/pipeline/track_hygiene.hpp.
#include "engine/pipeline/track_hygiene.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <span>

#include "kernels/core/error.hpp"
#include "kernels/core/local_track_rows.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/statistics/chi_square.hpp"

namespace trackassoc {

void TrackSplitOptions::validate() const {
  require(std::isfinite(min_gap_s) && min_gap_s > 0.0, "track_split.min_gap_s", "expected a gap > 0 [s]");
  require(std::isfinite(gap_factor) && gap_factor >= 1.0, "track_split.gap_factor", "expected a factor >= 1");
  require(std::isfinite(manoeuvre_sigma) && manoeuvre_sigma >= 0.0, "track_split.manoeuvre_sigma",
          "expected σ >= 0 [m/s²]");
  require(gate_probability > 0.0 && gate_probability < 1.0, "track_split.gate_probability",
          "expected a probability in (0, 1)");
  require(jump_probability > 0.0 && jump_probability < 1.0, "track_split.jump_probability",
          "expected a probability in (0, 1)");
}

namespace {

// The statistic for a fixed state dimension D (4 or 6): fixed-size matrices, unrolled by Eigen.
template <int D>
double continuation_statistic_of(const TrackTable& t, std::size_t before, std::size_t after, double q) {
  using Vector = Eigen::Matrix<double, D, 1>;
  using Matrix = Eigen::Matrix<double, D, D>;
  constexpr int d = D / 2;
  const double dt = t.t[after] - t.t[before];
  const double adt = std::fabs(dt), sgn = dt < 0 ? -1.0 : 1.0;  // Q's cross term follows F's direction
  Matrix F = Matrix::Identity(), Q = Matrix::Zero(), P0, P1;
  for (int i = 0; i < d; ++i) {
    F(i, d + i) = dt;
    Q(i, i) = q * adt * adt * adt / 3.0;
    Q(i, d + i) = Q(d + i, i) = sgn * q * adt * adt / 2.0;
    Q(d + i, d + i) = q * adt;
  }
  Vector x0, x1;
  for (int r = 0; r < D; ++r) x0[r] = t.state[r][before], x1[r] = t.state[r][after];
  for (int r = 0, k = 0; r < D; ++r)
    for (int c = r; c < D; ++c, ++k) {
      P0(r, c) = P0(c, r) = t.cov[k][before];
      P1(r, c) = P1(c, r) = t.cov[k][after];
    }
  const Vector e = x1 - F * x0;
  const Matrix C = F * P0 * F.transpose() + Q + P1;
  return e.dot(C.ldlt().solve(e));
}

}  // namespace

double continuation_statistic(const TrackTable& t, std::size_t before, std::size_t after, double q) {
  return t.dim() == 4 ? continuation_statistic_of<4>(t, before, after, q)
                      : continuation_statistic_of<6>(t, before, after, q);
}

namespace {

using Key = LocalTrackRows::Key;  // (sensor, track)

// The gap of a key (its rows in time order): max(min_gap_s, gap_factor × median report interval).
double gap_of(const TrackTable& t, std::span<const std::size_t> v, const TrackSplitOptions& o) {
  std::vector<double> intervals;
  for (std::size_t i = 1; i < v.size(); ++i) intervals.push_back(t.t[v[i]] - t.t[v[i - 1]]);
  std::nth_element(intervals.begin(), intervals.begin() + intervals.size() / 2, intervals.end());
  return std::max(o.min_gap_s, o.gap_factor * intervals[intervals.size() / 2]);
}

// Gives the rows of key k from each of cuts[k] (positions in its rows, ascending) on a new number:
// one above the sensor's largest, in order of cuts by sensor, key and time; source_track keeps
// the recorded numbers. Returns the number of cuts.
int32_t renumber_at_cuts(TrackFile& file, const LocalTrackRows& keys,
                         const std::vector<std::vector<std::size_t>>& cuts) {
  TrackTable& t = file.tracks;
  std::map<int32_t, int32_t> next_number;  // per sensor: one above its largest number
  for (std::size_t r = 0; r < t.size(); ++r) {
    int32_t& n = next_number[t.sensor[r]];
    n = std::max(n, t.track[r] + 1);
  }
  std::vector<int32_t> source = file.source_track.empty() ? t.track : file.source_track;
  int32_t count = 0;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const Key key = keys.key[k];
    const std::span<const std::size_t> v = keys.rows(k);
    int32_t number = key.second;
    std::size_t next = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (next < cuts[k].size() && cuts[k][next] == i) {
        number = next_number[key.first]++;
        ++next;
        ++count;
      }
      t.track[v[i]] = number;
    }
  }
  if (count > 0) file.source_track = std::move(source);
  return count;
}

}  // namespace

TrackSplitSummary split_recycled_tracks(TrackFile& file, const TrackSplitOptions& o) {
  o.validate();
  TrackSplitSummary summary;
  if (!o.enabled) return summary;
  const TrackTable& t = file.tracks;
  const LocalTrackRows keys = local_track_rows(t);
  const double gate = chi_square_quantile(o.gate_probability, t.dim());
  const double q = o.manoeuvre_sigma * o.manoeuvre_sigma;
  std::vector<std::vector<std::size_t>> cuts(keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const std::span<const std::size_t> v = keys.rows(k);
    if (v.size() < 2) continue;
    const double gap = gap_of(t, v, o);
    for (std::size_t i = 1; i < v.size(); ++i)
      if (t.t[v[i]] - t.t[v[i - 1]] > gap) {
        ++summary.gaps;
        if (continuation_statistic(t, v[i - 1], v[i], q) > gate) cuts[k].push_back(i);
      }
  }
  summary.cuts = renumber_at_cuts(file, keys, cuts);
  return summary;
}

int32_t split_swapped_tracks(TrackFile& file, const TrackSplitOptions& o) {
  o.validate();
  if (!o.enabled) return 0;
  const TrackTable& t = file.tracks;
  const LocalTrackRows keys = local_track_rows(t);
  const double q = o.manoeuvre_sigma * o.manoeuvre_sigma;
  const double jump = chi_square_quantile(o.jump_probability, t.dim());
  const double pair_gate = chi_square_quantile(o.gate_probability, 2 * t.dim());
  // A jump: a report transition (rows v[i − 1] → v[i] of key k, no gap) its own motion cannot explain.
  struct Jump {
    std::size_t key, i, r0, r1;
    double own;
  };
  std::vector<std::vector<Jump>> per_key(keys.size());
  parallel_for_range(keys.size(), 16, [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) {
      const std::span<const std::size_t> v = keys.rows(k);
      if (v.size() < 2) continue;
      const double gap = gap_of(t, v, o);
      for (std::size_t i = 1; i < v.size(); ++i) {
        if (t.t[v[i]] - t.t[v[i - 1]] > gap) continue;
        const double m = continuation_statistic(t, v[i - 1], v[i], q);
        if (m > jump) per_key[k].push_back({k, i, v[i - 1], v[i], m});
      }
    }
  });
  std::vector<Jump> jumps;  // by sensor, then by the time of their first report
  for (const auto& j : per_key) jumps.insert(jumps.end(), j.begin(), j.end());
  std::stable_sort(jumps.begin(), jumps.end(), [&](const Jump& x, const Jump& y) {
    const int32_t sx = keys.key[x.key].first, sy = keys.key[y.key].first;
    return sx != sy ? sx < sy : t.t[x.r0] < t.t[y.r0];
  });
  // Pairs of one sensor's jumps whose intervals overlap, explained by crossing the keys over.
  struct Swap {
    double crossed;
    std::size_t x, y;  // positions in jumps
  };
  std::vector<Swap> swaps;
  for (std::size_t x = 0; x < jumps.size(); ++x) {
    const Jump& a = jumps[x];
    for (std::size_t y = x + 1; y < jumps.size(); ++y) {
      const Jump& b = jumps[y];
      if (keys.key[b.key].first != keys.key[a.key].first || t.t[b.r0] > t.t[a.r1]) break;
      if (b.key == a.key) continue;
      const double own = a.own + b.own;
      if (own <= pair_gate) continue;
      const double crossed =
          continuation_statistic(t, a.r0, b.r1, q) + continuation_statistic(t, b.r0, a.r1, q);
      if (crossed <= pair_gate && crossed < own) swaps.push_back({crossed, x, y});
    }
  }
  std::stable_sort(swaps.begin(), swaps.end(),
                   [](const Swap& u, const Swap& w) { return u.crossed < w.crossed; });
  std::vector<char> used(jumps.size(), 0);
  std::vector<std::vector<std::size_t>> cuts(keys.size());
  int32_t count = 0;
  for (const Swap& s : swaps) {
    if (used[s.x] || used[s.y]) continue;
    used[s.x] = used[s.y] = 1;
    cuts[jumps[s.x].key].push_back(jumps[s.x].i);
    cuts[jumps[s.y].key].push_back(jumps[s.y].i);
    ++count;
  }
  for (auto& c : cuts) std::sort(c.begin(), c.end());
  renumber_at_cuts(file, keys, cuts);
  return count;
}

TrackSplitSummary split_tracks(TrackFile& file, const TrackSplitOptions& o) {
  const int32_t swaps = o.swaps ? split_swapped_tracks(file, o) : 0;
  TrackSplitSummary summary = split_recycled_tracks(file, o);
  summary.swaps = swaps;
  return summary;
}

}  // namespace trackassoc
