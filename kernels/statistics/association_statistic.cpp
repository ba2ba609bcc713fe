// Track alignment at common times and the independent / correlated sequential statistic
// (seed 000 §2 Eq. 1–2; Bar-Shalom & Campo 1986; docs/design.md §4.3). See the header for the contract.
//
// Choices made here (the papers leave them open):
//
// * Alignment model. A track's latest report at or before the common time t is predicted by the
//   constant-velocity model with continuous white-noise acceleration of power spectral density
//   q = process_noise² (Bar-Shalom, Li, Kirubarajan 2001, §6.2.2), per spatial axis:
//       F = [1 Δ; 0 1],   Q = q·[Δ³/3  Δ²/2; Δ²/2  Δ].
//   The continuous model is used rather than the piecewise-constant (discrete) one because the
//   prediction interval Δ varies from track to track and time to time; the continuous Q is
//   consistent under splitting of Δ. Reports at the same time: the last row in table order wins.
//   A track is invalid at t when it has no report at or before t, or its latest report is older
//   than max_extrapolation.
//
// * Correlated errors. Bar-Shalom–Campo need the cross-covariance P_ab of the two local estimates,
//   which a track file does not carry. With common_process_noise it is computed by their recursion
//   from each filter's gain, read off its reported covariances (kernels/statistics/cross_covariance.hpp).
//   Otherwise, with cross_correlation ρ, we approximate it as ρ times the symmetric product of the
//   principal square roots, S_a = P_a^{1/2}, S_b = P_b^{1/2}:
//       P_ab + P_ba ≈ ρ·(S_a S_b + S_b S_a),
//   so C = P_a + P_b − ρ(S_a S_b + S_b S_a) = (1−ρ)(P_a + P_b) + ρ(S_a − S_b)², which is SPD for
//   0 ≤ ρ < 1 whenever P_a + P_b is (a sum of an SPD and a PSD matrix). With ρ = 0 it reduces to
//   the independent form. The square roots are computed once per aligned row, not per pair.
//
// * Pairs that never coexist at a common time get λ = 0, dof = 0 and are outside the gate: there is
//   no evidence that they are the same target.
//
// * C is factorised by Cholesky (LLᵀ) per pair per time; d ᵀC⁻¹d = |L⁻¹d|². A C that is not
//   positive definite means a bad input covariance and raises InputError naming the tracks.
#include "kernels/statistics/association_statistic.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <optional>
#include <string>

#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/statistics/cross_covariance.hpp"
#include "kernels/statistics/report_whiteness.hpp"

namespace trackassoc {

void AlignmentOptions::validate() const {
  require(method == AlignmentMethod::kTwoSided || method == AlignmentMethod::kForward,
          "AlignmentOptions.method", "unknown alignment method");
  require(std::isfinite(process_noise) && process_noise >= 0.0, "AlignmentOptions.process_noise",
          "must be finite and >= 0 [m/s^2], got " + std::to_string(process_noise));
  require(std::isfinite(lag_inflation) && lag_inflation >= 0.0 && lag_inflation <= 100.0,
          "AlignmentOptions.lag_inflation", "must be in [0, 100], got " + std::to_string(lag_inflation));
  require(std::isfinite(lag_look_ahead) && lag_look_ahead >= 0.0 && lag_look_ahead <= 100.0,
          "AlignmentOptions.lag_look_ahead", "must be in [0, 100], got " + std::to_string(lag_look_ahead));
  require(
      whiteness_threshold > 0.0, "AlignmentOptions.whiteness_threshold",
      "must be > 0 (+inf keeps the lag terms for every sensor), got " + std::to_string(whiteness_threshold));
  require(std::isfinite(lag_noise_margin) && lag_noise_margin >= 0.0, "AlignmentOptions.lag_noise_margin",
          "must be finite and >= 0, got " + std::to_string(lag_noise_margin));
  require(std::isfinite(max_extrapolation) && max_extrapolation >= 0.0, "AlignmentOptions.max_extrapolation",
          "must be finite and >= 0 [s], got " + std::to_string(max_extrapolation));
  require(std::isfinite(extent_sigma) && extent_sigma >= 0.0, "AlignmentOptions.extent_sigma",
          "must be finite and >= 0 [m], got " + std::to_string(extent_sigma));
}

void StatisticOptions::validate() const {
  require(std::isfinite(cross_correlation) && cross_correlation >= 0.0 && cross_correlation < 1.0,
          "StatisticOptions.cross_correlation",
          [&] { return "must be in [0, 1), got " + std::to_string(cross_correlation); });
  require(std::isfinite(common_process_noise) && common_process_noise >= 0.0 && common_process_noise <= 1e3,
          "StatisticOptions.common_process_noise",
          [&] { return "must be in [0, 1000] m/s², got " + std::to_string(common_process_noise); });
  require(!(common_process_noise > 0.0 && correlated && cross_correlation > 0.0), "StatisticOptions",
          "choose one cross-covariance: common_process_noise (Bar-Shalom–Campo recursion) or "
          "cross_correlation (ρ)");
  require(gate_probability > 0.0 && gate_probability <= 1.0, "StatisticOptions.gate_probability",
          [&] { return "must be in (0, 1] (1 disables gating), got " + std::to_string(gate_probability); });
  require(gate == GateMethod::kCalibrated || gate == GateMethod::kChiSquareSum, "StatisticOptions.gate",
          "unknown gate method");
  require(link == LinkCost::kPerScan || link == LinkCost::kPerIndependentScan, "StatisticOptions.link",
          "unknown link cost");
  require(cap_probability > 0.0 && cap_probability < 1.0, "StatisticOptions.cap_probability",
          [&] { return "must be in (0, 1), got " + std::to_string(cap_probability); });
  require(
      std::isfinite(scans_per_independent) && scans_per_independent >= 1.0 && scans_per_independent <= 1e3,
      "StatisticOptions.scans_per_independent",
      [&] { return "must be in [1, 1000], got " + std::to_string(scans_per_independent); });
}

SequentialGate::SequentialGate(int dim, const StatisticOptions& o, int32_t max_scans)
    : dim_(dim),
      enabled_(o.gate_probability < 1.0),
      calibrated_(o.gate == GateMethod::kCalibrated),
      per_scan_(o.link == LinkCost::kPerScan),
      p_(o.gate_probability),
      f_(o.gate == GateMethod::kCalibrated ? o.scans_per_independent : 1.0),
      cap_(o.gate == GateMethod::kCalibrated ? chi_square_quantile(o.cap_probability, dim)
                                             : std::numeric_limits<double>::infinity()) {
  require(dim > 0, "SequentialGate", "state dimension must be positive");
  std::vector<double> cache(std::max(max_scans, 0) + 1, std::numeric_limits<double>::quiet_NaN());
  for (int32_t n = 1; n <= max_scans; ++n) cache[n] = threshold(n);
  cache_ = std::move(cache);
}

double SequentialGate::threshold(int32_t scans) const {
  if (scans <= 0) return -std::numeric_limits<double>::infinity();
  if (static_cast<std::size_t>(scans) < cache_.size() && !std::isnan(cache_[scans])) return cache_[scans];
  if (!enabled_) return std::numeric_limits<double>::infinity();
  // kCalibrated: Satterthwaite, λ_c ≈ f·χ²(n·D/f) with f ≤ n (n scans are at most one independent
  // scan's worth when perfectly correlated); kChiSquareSum: f = 1, χ²(n·D) (seed 000).
  const double f = std::min(f_, static_cast<double>(scans));
  return f * chi_square_quantile(p_, static_cast<double>(scans) * dim_ / f);
}

bool SequentialGate::accepts(double lambda, int32_t scans, int32_t below_cap) const {
  if (scans <= 0) return false;
  if (calibrated_ && below_cap <= 0) return false;
  return lambda <= threshold(scans);
}

double SequentialGate::link_cost(double lambda, int32_t scans) const {
  if (scans <= 0) return 0.0;
  return excess_cost(enabled_ ? lambda - threshold(scans) : lambda, scans);
}

double SequentialGate::excess_cost(double excess, int32_t scans) const {
  if (scans <= 0) return 0.0;
  return per_scan_ ? excess / scans : excess / f_;
}

namespace {

// The manoeuvre-lag variance added per axis to the report rows[pos] of a track (rows [b, e) in
// time order), AlignmentOptions' lag terms (see the header):
//   τ² = P_pp/P_vv (the report's own position and velocity variances, averaged over the axes);
//   current: â² = max(0, |Δv|² − m·tr(P_v,0 + P_v,1))/Δt² from the neighbouring reports, adding
//     k²·â²·τ⁴ to the position and k²·â²·τ² to the velocity variance (k = lag_inflation);
//   look-ahead: the change the velocity still makes over the next τ, Δv_τ = v(t + τ) − v(t) (the
//     last report if the track ends first), with the same noise margin, adding h²·|Δv_τ|²·τ² and
//     h²·|Δv_τ|² (h = lag_look_ahead).
struct ManoeuvreLag {
  double position_variance = 0.0, velocity_variance = 0.0;
};

ManoeuvreLag manoeuvre_lag(const TrackTable& tracks, const std::vector<std::size_t>& rows, std::size_t b,
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

}  // namespace

AlignedTracks align_tracks(const TrackTable& tracks, int32_t sensor, std::span<const double> common_times,
                           const AlignmentOptions& options) {
  options.validate();
  const int D = tracks.dim();
  const int P = packed_size(D);
  const int m = D / 2;  // spatial dimension: state = (position[m], velocity[m])
  const int32_t K = static_cast<int32_t>(common_times.size());
  const bool has_truth = tracks.truth.size() == tracks.size();
  require(tracks.sensor.size() == tracks.size() && tracks.track.size() == tracks.size() &&
              tracks.state.size() == static_cast<std::size_t>(D) &&
              tracks.cov.size() == static_cast<std::size_t>(P),
          "align_tracks", "the track table's columns are inconsistent");
  for (const auto& col : tracks.state)
    require(col.size() == tracks.size(), "align_tracks", "a state column has the wrong length");
  for (const auto& col : tracks.cov)
    require(col.size() == tracks.size(), "align_tracks", "a covariance column has the wrong length");
  for (int32_t k = 0; k < K; ++k) {
    require(std::isfinite(common_times[k]), "align_tracks.common_times",
            "time " + std::to_string(k) + " is not finite");
    require(k == 0 || common_times[k] > common_times[k - 1], "align_tracks.common_times",
            "must be strictly ascending, time " + std::to_string(k) + " is not");
  }

  // Rows of this sensor, ordered by (track, t, row): the stable order makes ties deterministic.
  std::vector<std::size_t> rows;
  for (std::size_t r = 0; r < tracks.size(); ++r)
    if (tracks.sensor[r] == sensor) {
      if (!std::isfinite(tracks.t[r]))
        throw InputError("/tracks/t: row " + std::to_string(r) + " is not finite");
      rows.push_back(r);
    }
  std::stable_sort(rows.begin(), rows.end(), [&](std::size_t x, std::size_t y) {
    if (tracks.track[x] != tracks.track[y]) return tracks.track[x] < tracks.track[y];
    return tracks.t[x] < tracks.t[y];
  });

  AlignedTracks out;
  out.sensor = sensor;
  out.dim = D;
  out.n_times = K;
  out.times.assign(common_times.begin(), common_times.end());
  std::vector<std::size_t> begin;  // first row (in `rows`) of each track
  for (std::size_t q = 0; q < rows.size(); ++q)
    if (q == 0 || tracks.track[rows[q]] != tracks.track[rows[q - 1]]) {
      begin.push_back(q);
      out.track.push_back(tracks.track[rows[q]]);
    }
  begin.push_back(rows.size());
  const int32_t n = out.n_tracks();
  out.truth.resize(n);
  // Each track is stored over its span only (alignment_span: the times where it can be valid).
  std::vector<int32_t> span_begin(n), span_length(n);
  for (int32_t a = 0; a < n; ++a) {
    const AlignedTracks::Span sp =
        alignment_span(tracks.t[rows[begin[a]]], tracks.t[rows[begin[a + 1] - 1]], common_times, options);
    span_begin[a] = sp.begin;
    span_length[a] = sp.size();
  }
  out.allocate(span_begin, span_length);
  const double q = options.process_noise * options.process_noise;
  const double half_extent2 = 0.5 * options.extent_sigma * options.extent_sigma;  // σ_r²/2 per report

  const bool two_sided = options.method == AlignmentMethod::kTwoSided;
  // The lag terms, unless the sensor's reports have independent errors (no filter, no lag).
  if (two_sided && (options.lag_inflation > 0.0 || options.lag_look_ahead > 0.0)) {
    const ReportWhiteness w = measure_report_whiteness(tracks, rows, begin, options);
    out.lag_terms = w.filtered;
    out.report_whiteness = w.median_ratio;
  }
  const bool lag_terms = out.lag_terms;
  // One track's cells (each track writes its own only, so the output does not depend on the number
  // of threads); its matrices are allocated once for all its cells.
  auto align_one = [&](int32_t a) {
    Eigen::MatrixXd Pm(D, D), F(D, D), Pp(D, D);
    out.truth[a] = has_truth ? tracks.truth[rows[begin[a + 1] - 1]] : -1;
    const double first = tracks.t[rows[begin[a]]], last = tracks.t[rows[begin[a + 1] - 1]];
    std::size_t cur = begin[a];  // walks forward: common times are ascending
    const AlignedTracks::Span sp = out.span(a);
    for (int32_t k = sp.begin; k < sp.end; ++k) {
      const double t = common_times[k];
      while (cur < begin[a + 1] && tracks.t[rows[cur]] <= t) ++cur;
      std::size_t pos;  // the report moved to t is rows[pos]
      if (two_sided) {
        if (t < first - options.max_extrapolation || t > last + options.max_extrapolation) continue;
        // The nearest report in time: the latest at or before t, or the earliest after it.
        const bool has_before = cur > begin[a], has_after = cur < begin[a + 1];
        if (has_before && has_after)
          pos = t - tracks.t[rows[cur - 1]] <= tracks.t[rows[cur]] - t ? cur - 1 : cur;
        else
          pos = has_before ? cur - 1 : cur;
      } else {
        if (cur == begin[a]) continue;  // no report yet
        pos = cur - 1;
        if (t - tracks.t[rows[pos]] > options.max_extrapolation) continue;
      }
      const std::size_t r = rows[pos];
      const double dt = t - tracks.t[r];  // < 0: retrodiction to an earlier time
      const double adt = std::fabs(dt);
      const int64_t cell = out.cell_base(a) + k;
      out.valid[cell] = 1;
      double* x = out.state_at(cell);
      for (int c = 0; c < D; ++c) x[c] = tracks.state[c][r];
      for (int c = 0; c < m; ++c) x[c] += dt * x[m + c];  // x ← F(Δ) x
      // P ← F P Fᵀ + Q(|Δ|) on the full matrix, then packed back. Backwards, F(−|Δ|) with the same
      // Q: the uncertainty grows with the time moved in either direction (an approximation to a
      // fixed-interval smoother's retrodiction, which would need the filter's gains).
      for (int i = 0, p = 0; i < D; ++i)
        for (int j = i; j < D; ++j, ++p) Pm(i, j) = Pm(j, i) = tracks.cov[p][r];
      F.setIdentity();
      for (int c = 0; c < m; ++c) F(c, m + c) = dt;
      Pp = F * Pm * F.transpose();
      const double sgn = dt < 0 ? -1.0 : 1.0;  // Q's cross term follows the direction of F
      for (int c = 0; c < m; ++c) {
        Pp(c, c) += q * adt * adt * adt / 3.0;
        Pp(c, m + c) += sgn * q * adt * adt / 2.0;
        Pp(m + c, c) += sgn * q * adt * adt / 2.0;
        Pp(m + c, m + c) += q * adt;
      }
      if (lag_terms && begin[a + 1] - begin[a] >= 2) {
        const ManoeuvreLag lag = manoeuvre_lag(tracks, rows, begin[a], begin[a + 1], pos, options);
        for (int c = 0; c < m; ++c) {
          Pp(c, c) += lag.position_variance;
          Pp(m + c, m + c) += lag.velocity_variance;
        }
      }
      for (int c = 0; c < m; ++c) Pp(c, c) += half_extent2;
      double* pc = out.cov_at(cell);
      for (int i = 0, p = 0; i < D; ++i)
        for (int j = i; j < D; ++j, ++p) pc[p] = Pp(i, j);
    }
  };
  parallel_for_range(static_cast<std::size_t>(n), 64, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t a = lo; a < hi; ++a) align_one(static_cast<int32_t>(a));
  });
  return out;
}

namespace {

template <int D>
using Mat = Eigen::Matrix<double, D, D>;
template <int D>
using Vec = Eigen::Matrix<double, D, 1>;

template <int D>
Mat<D> unpack(const double* packed, int d) {
  Mat<D> M(d, d);
  for (int i = 0, p = 0; i < d; ++i)
    for (int j = i; j < d; ++j, ++p) M(i, j) = M(j, i) = packed[p];
  return M;
}

// Principal square roots of every valid aligned covariance (correlated form only), per cell.
template <int D>
std::vector<double> covariance_square_roots(const AlignedTracks& x) {
  const int d = x.dim, P = packed_size(d);
  std::vector<double> out(x.valid.size() * P, 0.0);
  parallel_for_range(x.n_tracks(), 16, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) {
      const AlignedTracks::Span sp = x.span(static_cast<int32_t>(i));
      for (int32_t k = sp.begin; k < sp.end; ++k) {
        const int64_t cell = x.cell(static_cast<int32_t>(i), k);
        if (!x.valid[cell]) continue;
        Eigen::SelfAdjointEigenSolver<Mat<D>> es(unpack<D>(x.cov_at(cell), d));
        if (es.info() != Eigen::Success || es.eigenvalues().minCoeff() < 0.0)
          throw InputError("independent_sequential_statistic: covariance of sensor " +
                           std::to_string(x.sensor) + " track " + std::to_string(x.track[i]) +
                           " at common time " + std::to_string(k) + " is not positive semi-definite");
        const Mat<D> S = es.operatorSqrt();
        for (int r = 0, p = 0; r < d; ++r)
          for (int c = r; c < d; ++c, ++p) out[cell * P + p] = S(r, c);
      }
    }
  });
  return out;
}

// What a failure of the common-process-noise recursion means, appended to its error.
constexpr const char* kCommonProcessNoiseHint =
    " (common_process_noise: the recursion reads each track as a CV Kalman filter updated at every "
    "common time with the given process noise, which recorded tracks of other periods, filters or "
    "lag widening are not, and its cross-covariance then exceeds P_a + P_b; the correlated form "
    "--correlated RHO bounds it for any tracks)";

// The scan terms dᵀC⁻¹d of a pair of aligned tracks, for the three forms of C (independent, ρ,
// common process noise): what sequential_statistic sums and scan_terms returns, computed once.
template <int D>
class PairTerms {
 public:
  PairTerms(const AlignedTracks& a, const AlignedTracks& b, const StatisticOptions& opt)
      : a_(a), b_(b), d_(a.dim), P_(packed_size(a.dim)), K_(a.n_times) {
    rho_ = opt.correlated ? opt.cross_correlation : 0.0;
    if (rho_ > 0.0) {
      sqrt_a_ = covariance_square_roots<D>(a);
      sqrt_b_ = covariance_square_roots<D>(b);
    }
    common_ = opt.common_process_noise > 0.0;
    if (common_) {
      gain_a_ = gain_complements(a, opt.common_process_noise);
      gain_b_ = gain_complements(b, opt.common_process_noise);
      F_.resize(K_);
      Q_.resize(K_);
      for (int32_t k = 1; k < K_; ++k) {
        Eigen::MatrixXd F, Q;
        cv_transition(d_, a.times[k] - a.times[k - 1], opt.common_process_noise, F, Q);
        F_[k] = F;
        Q_[k] = Q;
      }
    }
  }

  // Calls fn(k, term) for every common time k where tracks i (of a) and j (of b) both exist: the
  // times where both spans lie, in order.
  template <class Fn>
  void for_each(std::size_t i, std::size_t j, Fn&& fn) const {
    Mat<D> Pab = Mat<D>::Zero(d_, d_);  // Bar-Shalom–Campo cross-covariance (common_ only)
    bool chained = false;               // both tracks existed at k − 1
    const auto ti = static_cast<int32_t>(i), tj = static_cast<int32_t>(j);
    const AlignedTracks::Span both = common_span(a_.span(ti), b_.span(tj));
    const int64_t base_a = a_.cell_base(ti), base_b = b_.cell_base(tj);
    for (int32_t k = both.begin; k < both.end; ++k) {
      const int64_t ca = base_a + k, cb = base_b + k;
      if (!a_.valid[ca] || !b_.valid[cb]) {
        chained = false;
        continue;
      }
      Vec<D> diff(d_);
      const double *xa = a_.state_at(ca), *xb = b_.state_at(cb);
      for (int c = 0; c < d_; ++c) diff[c] = xa[c] - xb[c];
      Mat<D> C = unpack<D>(a_.cov_at(ca), d_) + unpack<D>(b_.cov_at(cb), d_);  // seed 000 Eq. 2
      if (rho_ > 0.0) {
        // Bar-Shalom–Campo: C = P_a + P_b − P_ab − P_ba, P_ab + P_ba ≈ ρ(S_a S_b + S_b S_a).
        const Mat<D> Sa = unpack<D>(&sqrt_a_[ca * P_], d_), Sb = unpack<D>(&sqrt_b_[cb * P_], d_);
        const Mat<D> SaSb = Sa * Sb;
        C.noalias() -= rho_ * (SaSb + SaSb.transpose());
      }
      if (common_) {
        // P_ab(k) = A_a(k)[F P_ab(k−1) Fᵀ + Q]A_b(k)ᵀ (kernels/statistics/cross_covariance.hpp), 0 at a
        // start.
        if (chained) {
          const Eigen::Map<const Eigen::Matrix<double, D, D, Eigen::RowMajor>> Aa(&gain_a_[ca * d_ * d_], d_,
                                                                                  d_),
              Ab(&gain_b_[cb * d_ * d_], d_, d_);
          Pab = cross_covariance_step(Aa, Ab, F_[k], Q_[k], Pab);
        } else {
          Pab.setZero();
        }
        C.noalias() -= Pab + Pab.transpose();
      }
      chained = true;
      Eigen::LLT<Mat<D>> llt(C);
      if (llt.info() != Eigen::Success)  // build the message only on failure: this is the hot loop
        throw InputError("independent_sequential_statistic: C = P_a + P_b" +
                         std::string(rho_ > 0.0 || common_ ? " − P_ab − P_ba" : "") +
                         " is not positive definite for sensor " + std::to_string(a_.sensor) + " track " +
                         std::to_string(a_.track[i]) + " vs sensor " + std::to_string(b_.sensor) + " track " +
                         std::to_string(b_.track[j]) + " at common time " + std::to_string(k) +
                         (common_ ? std::string(kCommonProcessNoiseHint) : std::string()));
      fn(k, llt.matrixL().solve(diff).squaredNorm());
    }
  }

 private:
  const AlignedTracks &a_, &b_;
  int d_, P_;
  int32_t K_;
  double rho_ = 0.0;
  bool common_ = false;
  std::vector<double> sqrt_a_, sqrt_b_, gain_a_, gain_b_;
  std::vector<Mat<D>> F_, Q_;
};

template <int D>
PairStatistic sequential_statistic(const AlignedTracks& a, const AlignedTracks& b,
                                   const StatisticOptions& opt, const SequentialGate* shared_gate) {
  const int d = a.dim;
  const int32_t K = a.n_times, na = a.n_tracks(), nb = b.n_tracks();
  PairStatistic s;
  s.n_a = na;
  s.n_b = nb;
  const std::size_t pairs = static_cast<std::size_t>(na) * nb;
  s.lambda.assign(pairs, 0.0);
  s.dof.assign(pairs, 0);
  s.in_gate.assign(pairs, 0);

  const PairTerms<D> terms(a, b, opt);
  // A pair has at most min(longest spans) common times: thresholds up to there only (each is a χ²
  // quantile; a 2-hour grid has 600 times, a wide-area track's span a few dozen).
  const int32_t most = std::min({K, longest_span(a), longest_span(b)});
  const std::optional<SequentialGate> own =
      shared_gate ? std::nullopt : std::optional<SequentialGate>(std::in_place, d, opt, most);
  const SequentialGate& gate = shared_gate ? *shared_gate : *own;
  std::vector<double> threshold(most + 1, 0.0);
  for (int32_t k = 1; k <= most; ++k) threshold[k] = gate.threshold(k);
  const double cap = gate.cap();

  // One task per block of rows a; each pair is a serial loop over k, so the result does not
  // depend on the split (bit-identical for any thread count).
  parallel_for_range(na, 1, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i)
      for (int32_t j = 0; j < nb; ++j) {
        double lambda = 0.0;
        int32_t times = 0, below_cap = 0;
        terms.for_each(i, static_cast<std::size_t>(j), [&](int32_t, double term) {
          below_cap += term <= cap;
          lambda += std::min(term, cap);  // seed 000 Eq. 1: λ(k) = λ(k−1) + dᵀC⁻¹d (capped: kCalibrated)
          ++times;
        });
        const std::size_t idx = i * nb + j;
        s.lambda[idx] = lambda;
        s.dof[idx] = d * times;
        s.in_gate[idx] =
            times > 0 && lambda <= threshold[times] && (opt.gate != GateMethod::kCalibrated || below_cap > 0);
      }
  });
  return s;
}

void check_aligned_pair(const AlignedTracks& a, const AlignedTracks& b, const char* who) {
  require(a.dim == b.dim, who, [&] {
    return "state dimensions differ: " + std::to_string(a.dim) + " vs " + std::to_string(b.dim);
  });
  require(a.n_times == b.n_times, who, [&] {
    return "numbers of common times differ: " + std::to_string(a.n_times) + " vs " +
           std::to_string(b.n_times);
  });
  a.check_layout(who);
  b.check_layout(who);
}

}  // namespace

namespace {

PairStatistic statistic_with_gate(const AlignedTracks& a, const AlignedTracks& b,
                                  const StatisticOptions& options, const SequentialGate* gate) {
  options.validate();
  check_aligned_pair(a, b, "independent_sequential_statistic");
  switch (a.dim) {
    case 4:
      return sequential_statistic<4>(a, b, options, gate);
    case 6:
      return sequential_statistic<6>(a, b, options, gate);
    default:
      return sequential_statistic<Eigen::Dynamic>(a, b, options, gate);
  }
}

}  // namespace

PairStatistic independent_sequential_statistic(const AlignedTracks& a, const AlignedTracks& b,
                                               const StatisticOptions& options) {
  return statistic_with_gate(a, b, options, nullptr);
}

PairStatistic independent_sequential_statistic(const AlignedTracks& a, const AlignedTracks& b,
                                               const StatisticOptions& options, const SequentialGate& gate) {
  return statistic_with_gate(a, b, options, &gate);
}

SequentialGate sequential_gate_for(const AlignedTracks& a, const AlignedTracks& b,
                                   const StatisticOptions& options) {
  options.validate();
  check_aligned_pair(a, b, "sequential_gate_for");
  return SequentialGate(a.dim, options, std::min({a.n_times, longest_span(a), longest_span(b)}));
}

std::vector<double> scan_terms(const AlignedTracks& a, int32_t ia, const AlignedTracks& b, int32_t ib,
                               const StatisticOptions& options) {
  options.validate();
  check_aligned_pair(a, b, "scan_terms");
  require(ia >= 0 && ia < a.n_tracks() && ib >= 0 && ib < b.n_tracks(), "scan_terms", "track out of range");
  std::vector<double> out(a.n_times, std::numeric_limits<double>::quiet_NaN());
  const PairTerms<Eigen::Dynamic> terms(a, b, options);
  terms.for_each(static_cast<std::size_t>(ia), static_cast<std::size_t>(ib),
                 [&](int32_t k, double term) { out[k] = term; });
  return out;
}

}  // namespace trackassoc
