// The manoeuvre-lag terms and the whiteness test of a sensor's reports (see the header).
#include "kernels/statistics/manoeuvre_lag.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "kernels/statistics/chi_square.hpp"

namespace trackassoc {

// τ² = P_pp/P_vv (the report's own position and velocity variances, averaged over the axes);
// current: â² = max(0, |Δv|² − m·tr(P_v,0 + P_v,1))/Δt² from the neighbouring reports, adding
//   k²·â²·τ⁴ to the position and k²·â²·τ² to the velocity variance (k = lag_inflation);
// look-ahead: the change the velocity still makes over the next τ, Δv_τ = v(t + τ) − v(t) (the
//   last report if the track ends first), with the same noise margin, adding h²·|Δv_τ|²·τ² and
//   h²·|Δv_τ|² (h = lag_look_ahead).
ManoeuvreLag manoeuvre_lag(const TrackTable& tracks, std::span<const std::size_t> rows, std::size_t b,
                           std::size_t e, std::size_t pos, const AlignmentOptions& options) {
  const int D = tracks.dim(), m = D / 2;
  const std::size_t r = rows[pos];
  // |v_j − v_r|² beyond lag_noise_margin times its noise variance.
  auto velocity_change2 = [&](std::size_t i, std::size_t j) {
    double d2 = 0.0, noise = 0.0;
    for (int c = 0; c < m; ++c) {
      const double dv = tracks.state[m + c][j] - tracks.state[m + c][i];
      d2 += dv * dv;
      noise += tracks.cov[packed_index(D, m + c, m + c)][i] + tracks.cov[packed_index(D, m + c, m + c)][j];
    }
    return std::max(0.0, d2 - options.lag_noise_margin * noise);
  };
  double tau2 = 0.0;
  for (int c = 0; c < m; ++c) {
    const double pvv = tracks.cov[packed_index(D, m + c, m + c)][r];
    tau2 += pvv > 0.0 ? tracks.cov[packed_index(D, c, c)][r] / pvv / m : 0.0;
  }
  ManoeuvreLag lag;
  const std::size_t r0 = rows[pos > b ? pos - 1 : pos], r1 = rows[pos + 1 < e ? pos + 1 : pos];
  const double span = tracks.t[r1] - tracks.t[r0];
  if (options.lag_inflation > 0.0 && span > 0.0) {
    const double k2a2 =
        options.lag_inflation * options.lag_inflation * velocity_change2(r0, r1) / (span * span);
    lag.position_variance += k2a2 * tau2 * tau2;  // (k â τ²)²
    lag.velocity_variance += k2a2 * tau2;         // (k â τ)²
  }
  if (options.lag_look_ahead > 0.0) {
    const double tau = std::sqrt(tau2);
    std::size_t j = pos;
    while (j + 1 < e && tracks.t[rows[j]] < tracks.t[r] + tau) ++j;
    const double h2d2 = options.lag_look_ahead * options.lag_look_ahead * velocity_change2(r, rows[j]);
    lag.position_variance += h2d2 * tau2;  // (h |Δv_τ| τ)²
    lag.velocity_variance += h2d2;         // (h |Δv_τ|)²
  }
  return lag;
}

namespace {

// ρ of the triple of reports (i0, i1, i2) (the header's formula), or a negative value when the
// triple is not usable.
double whiteness_ratio(const TrackTable& tracks, std::size_t i0, std::size_t i1, std::size_t i2) {
  const int D = tracks.dim(), m = D / 2;
  const double h0 = tracks.t[i1] - tracks.t[i0], h1 = tracks.t[i2] - tracks.t[i1];
  if (!(h0 > 0.0 && h1 > 0.0)) return -1.0;
  const double r = h1 / h0;
  if (r < 0.1 || r > 10.0) return -1.0;
  double e2 = 0.0, noise = 0.0;
  for (int c = 0; c < m; ++c) {
    const std::vector<double>& v = tracks.state[m + c];
    const double e = v[i2] - v[i1] - r * (v[i1] - v[i0]);
    e2 += e * e;
    const std::vector<double>& p = tracks.cov[packed_index(D, m + c, m + c)];
    noise += p[i2] + (1.0 + r) * (1.0 + r) * p[i1] + r * r * p[i0];
  }
  return noise > 0.0 && std::isfinite(noise) && std::isfinite(e2) ? e2 / noise : -1.0;
}

}  // namespace

ReportWhiteness sensor_reports_are_filtered(const TrackTable& tracks, std::span<const std::size_t> rows,
                                            std::span<const std::size_t> begin,
                                            const AlignmentOptions& options) {
  // The triples in one numbering over the tracks (a track of L reports has L − 2); every stride-th
  // is tested, so at most kMaxTriples, spread evenly over the tracks.
  std::size_t triples = 0;
  for (std::size_t a = 0; a + 1 < begin.size(); ++a)
    triples += std::max<std::size_t>(begin[a + 1] - begin[a], 2) - 2;
  const std::size_t stride = std::max<std::size_t>(1, (triples + kMaxTriples - 1) / kMaxTriples);
  std::vector<double> sample;
  sample.reserve(std::min(triples, kMaxTriples));
  std::size_t first = 0;  // the number of the track's first triple
  for (std::size_t a = 0; a + 1 < begin.size(); ++a) {
    const std::size_t n = std::max<std::size_t>(begin[a + 1] - begin[a], 2) - 2;
    for (std::size_t g = (first + stride - 1) / stride * stride; g < first + n; g += stride) {
      const std::size_t q = begin[a] + (g - first);  // the triple's reports rows[q], rows[q + 1], rows[q + 2]
      const double rho = whiteness_ratio(tracks, rows[q], rows[q + 1], rows[q + 2]);
      if (rho >= 0.0) sample.push_back(rho);
    }
    first += n;
  }
  ReportWhiteness out;
  if (sample.size() < kLeastTriples) return out;
  const auto mid = sample.begin() + static_cast<std::ptrdiff_t>(sample.size() / 2);
  std::nth_element(sample.begin(), mid, sample.end());
  const int m = tracks.dim() / 2;
  out.triples = sample.size();
  out.median_ratio = *mid / (chi_square_quantile(0.5, m) / m);
  out.filtered = out.median_ratio < options.unfiltered_ratio;
  return out;
}

}  // namespace trackassoc
