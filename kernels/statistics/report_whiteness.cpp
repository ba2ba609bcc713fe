// The whiteness test of a sensor's reports (see the header).
#include "kernels/statistics/report_whiteness.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "kernels/statistics/chi_square.hpp"

namespace trackassoc {

namespace {

// ρ of the triple of reports (i0, i1, i2) (the header's formula), or a negative value when the
// triple is not usable.
double whiteness_ratio(const TrackTable& tracks, std::size_t i0, std::size_t i1, std::size_t i2) {
  const int D = tracks.dim(), m = D / 2;
  const double h0 = tracks.t[i1] - tracks.t[i0], h1 = tracks.t[i2] - tracks.t[i1];
  if (!(h0 > 0.0 && h1 > 0.0)) return -1.0;
  const double r = h1 / h0;
  if (r < 0.1 || r > 10.0) return -1.0;
  double e2 = 0.0, trace = 0.0;
  for (int c = 0; c < m; ++c) {
    const std::vector<double>& v = tracks.state[m + c];
    const double e = v[i2] - v[i1] - r * (v[i1] - v[i0]);
    e2 += e * e;
    const std::vector<double>& p = tracks.cov[packed_index(D, m + c, m + c)];
    if (!(p[i0] >= 0.0 && p[i1] >= 0.0 && p[i2] >= 0.0)) return -1.0;
    trace += p[i2] + (1.0 + r) * (1.0 + r) * p[i1] + r * r * p[i0];
  }
  const double rho = e2 / trace;  // |e|² / tr S
  return trace > 0.0 && std::isfinite(rho) ? rho : -1.0;
}

// The golden ratio's fractional part: j·φ mod 1 spreads any number of samples evenly over [0, 1)
// (a Weyl sequence), so no track length aliases with the sampling.
constexpr double kGolden = 0.6180339887498949;

}  // namespace

ReportWhiteness measure_report_whiteness(const TrackTable& tracks, std::span<const std::size_t> rows,
                                         std::span<const std::size_t> begin,
                                         const AlignmentOptions& options) {
  // The triples numbered over the tracks (a track of L reports has L − 2; prefix[a] the first of
  // track a's): all of them, or kMaxTriples positions of a Weyl sequence over them.
  const std::size_t n_tracks = begin.empty() ? 0 : begin.size() - 1;
  std::vector<std::size_t> prefix(n_tracks + 1, 0);
  for (std::size_t a = 0; a < n_tracks; ++a)
    prefix[a + 1] = prefix[a] + std::max<std::size_t>(begin[a + 1] - begin[a], 2) - 2;
  const std::size_t triples = prefix.back(), n = std::min(triples, kMaxTriples);
  std::vector<std::size_t> position(n);
  std::iota(position.begin(), position.end(), std::size_t{0});
  if (triples > kMaxTriples) {
    for (std::size_t& g : position) {
      const double u = std::fmod(static_cast<double>(g) * kGolden, 1.0);
      g = std::min(triples - 1, static_cast<std::size_t>(u * static_cast<double>(triples)));
    }
    std::sort(position.begin(), position.end());  // the tracks in order: the table read forwards
  }
  std::vector<double> sample;
  sample.reserve(n);
  std::size_t a = 0;  // the track of the triple g: prefix[a] <= g < prefix[a + 1]
  for (const std::size_t g : position) {
    while (prefix[a + 1] <= g) ++a;
    const std::size_t q = begin[a] + (g - prefix[a]);  // the triple rows[q], rows[q + 1], rows[q + 2]
    const double rho = whiteness_ratio(tracks, rows[q], rows[q + 1], rows[q + 2]);
    if (rho >= 0.0) sample.push_back(rho);
  }
  ReportWhiteness out;
  if (sample.size() < kLeastTriples) return out;
  const auto mid = sample.begin() + static_cast<std::ptrdiff_t>(sample.size() / 2);
  std::nth_element(sample.begin(), mid, sample.end());
  const int m = tracks.dim() / 2;
  out.triples = sample.size();
  out.median_ratio = *mid / (chi_square_quantile(0.5, m) / m);
  out.filtered = out.median_ratio < options.whiteness_threshold;
  return out;
}

}  // namespace trackassoc
