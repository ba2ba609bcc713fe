// Track-to-track association statistics (seed 000 §2 Eq. 1–2; Bar-Shalom & Campo 1986) and the
// gate that decides which pairs of local tracks may be the same target (docs/design.md §4.3).
//
// Alignment. Local tracks of one sensor are resampled at common times. Two ways (AlignmentOptions):
//  * two-sided (default, for recorded data): a track's report nearest in time to the common time t,
//    before or after it, is moved to t by the constant-velocity model (a prediction forward or a
//    retrodiction backward), so a track is never extrapolated across its own gaps and a common
//    time between two reports uses the closer one. Valid from max_extrapolation before the track's
//    first report to max_extrapolation after its last.
//  * forward (seed 000's simulation): the latest report at or before t is predicted forward.
// For a pair of tracks a (sensor s) and b (sensor t) the sequential statistic accumulates over the
// common times k where both exist:
//
//   λ(k) = λ(k−1) + dᵀ C⁻¹ d,   d = x̂_a(k) − x̂_b(k),   C = P_a + P_b              (Eq. 1–2)
//
// and the correlated-error variant uses C = P_a + P_b − P_ab − P_ba (Bar-Shalom–Campo), with the
// cross-covariance either computed by the Bar-Shalom–Campo recursion from common process noise
// (StatisticOptions::common_process_noise; kernels/statistics/cross_covariance.hpp), or approximated as
// P_ab = ρ·(P_a^{1/2} P_b^{1/2}) for a user-chosen ρ, using the
// principal (symmetric) square roots, so that C = (1−ρ)(P_a + P_b) + ρ(P_a^{1/2} − P_b^{1/2})² stays
// SPD for 0 ≤ ρ < 1. Alignment uses continuous white-noise acceleration (details in the .cpp).
//
// Gates (GateMethod):
//  * kChiSquareSum, as in seed 000: λ over n common times is taken as χ² with n·D degrees of
//    freedom and the pair is gated in when λ ≤ χ²_p(n·D). That holds for independent errors only.
//    The errors of two *filtered* tracks are correlated from scan to scan (a Kalman filter's error
//    has a memory of several scans) and a manoeuvre breaks the motion model for a stretch, so on
//    recorded data this gate rejects 12–22 % of the true pairs at p = 0.99 (docs/design.md §4.3).
//  * kCalibrated (default): capped robust accumulation with Satterthwaite moment matching.
//      - Each scan's term is capped: λ_c = Σ_k min(dᵀC⁻¹d, c), c = χ²_D(cap_probability), so one
//        manoeuvre or one bad report adds at most c and cannot veto a pair alone.
//      - The scan terms are correlated; with f = scans_per_independent the sum behaves as
//        f·χ²(n·D/f): the same mean n·D, a variance f times the independent one (Satterthwaite
//        1946, moment matching of a sum of correlated χ² terms with a variance inflation f =
//        1 + 2Σρ_l from the lag autocorrelation ρ_l of the scan terms). The gate is
//        λ_c ≤ G(n) = f·χ²_p(n·D/f), and at least one scan must be below the cap.
//      - f is a measured constant: at the default grid step (the largest scan period) the scan
//        terms of same-target CV-filtered tracks decorrelate over ~5 steps; tests/test_gate_
//        calibration.cpp measures the acceptance of simulated same-target pairs (straight and
//        turning targets, 3 to 150 common scans) and requires ≥ 0.98 at the nominal 0.99.
//    The pair's evidence (the cost) is λ_c, and its link cost in the S-D assignment is its excess
//    over the gate in units of independent scans, (λ_c − G(n))/f, negative inside the gate
//    (link_cost()): the evidence grows with the common scans, as a log-likelihood ratio summed over
//    independent samples does (docs/design.md §4.3, "Cost").
//    The mean per common scan, (λ_c − G(n))/n (kPerScan), was the default until the family had
//    registration, hygiene, segments and stitching: measured then (3 runs) it won on formations
//    only (83 % against 74 %); at 100 runs now it loses on dense traffic, formations, mixed
//    trackers and swaps, and on the wide-area files (docs/design.md §4.3, "Cost").
// Pairs with no common time carry no evidence: dof = 0, not in the gate, and `overlap` = 0, so a
// caller can tell them from a pair that was tested and failed.
//
// Complexity: O(Σ_pairs |span_a ∩ span_b| · D³): each pair visits the common times where both spans
// lie (at most K); the pair loop is split across TBB. Memory of the alignment: O(Σ spans).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "kernels/core/enum_names.hpp"
#include "kernels/core/types.hpp"
#include "kernels/statistics/chi_square.hpp"  // chi_square_quantile, used with the gates

namespace trackassoc {

// Tracks of one sensor at common times, in spans (SoA). Track i is stored only over its span, the
// common times k ∈ [span_begin[i], span_begin[i] + length_i) at which it can be valid (align_tracks:
// two-sided, max_extrapolation before its first report to max_extrapolation after its last;
// forward, its first report to max_extrapolation after its last), length_i = span_offset[i + 1] −
// span_offset[i]. The cells of track i are span_offset[i] .. span_offset[i + 1] − 1, cell(i, k) =
// span_offset[i] + k − span_begin[i]; state[cell·D + c], cov[cell·P + p] (the packed triangle),
// valid[cell] = 1 when the track exists at common time k (outside its span it never does).
// Memory O(Σ_i length_i), not O(n·K): a track of a long recording costs its own duration only.
struct AlignedTracks {
  int32_t sensor = 0;
  int32_t dim = 4;  // D
  int32_t n_times = 0;
  std::vector<double> times;         // the common times (n_times; align_tracks fills it)
  std::vector<int32_t> track;        // local track number of each row
  std::vector<int32_t> truth;        // truth id of each row (-1 unknown)
  std::vector<int32_t> span_begin;   // first common time stored, per track
  std::vector<int64_t> span_offset;  // first cell of each track; n_tracks + 1 entries
  std::vector<double> state;
  std::vector<double> cov;
  std::vector<uint8_t> valid;
  // align_tracks: whether the manoeuvre-lag terms widened this sensor's reports, and its reports'
  // whiteness ratio (kernels/statistics/report_whiteness.hpp; 0 when not tested). Two-sided only.
  bool lag_terms = false;
  double report_whiteness = 0.0;

  // Common times [begin, end) stored for a track; empty spans have begin == end.
  struct Span {
    int32_t begin = 0, end = 0;
    int32_t size() const { return end > begin ? end - begin : 0; }
  };
  int32_t n_tracks() const { return static_cast<int32_t>(track.size()); }
  Span span(int32_t i) const {
    return {span_begin[i], span_begin[i] + static_cast<int32_t>(span_offset[i + 1] - span_offset[i])};
  }
  // The cell of track i at common time k, −1 outside its span.
  int64_t cell(int32_t i, int32_t k) const {
    const int64_t c = static_cast<int64_t>(k) - span_begin[i];
    return c >= 0 && c < span_offset[i + 1] - span_offset[i] ? span_offset[i] + c : -1;
  }
  // cell(i, k) = cell_base(i) + k for k inside the span (hot loops add k to it).
  int64_t cell_base(int32_t i) const { return span_offset[i] - span_begin[i]; }
  bool valid_at(int32_t i, int32_t k) const {
    const int64_t c = cell(i, k);
    return c >= 0 && valid[c];
  }
  const double* state_at(int64_t c) const { return &state[c * dim]; }
  double* state_at(int64_t c) { return &state[c * dim]; }
  const double* cov_at(int64_t c) const { return &cov[c * packed_size(dim)]; }
  double* cov_at(int64_t c) { return &cov[c * packed_size(dim)]; }
  int64_t cells() const { return span_offset.empty() ? 0 : span_offset.back(); }

  // Zeroed cells for the spans [begin[i], begin[i] + length[i]) of the n_tracks() tracks.
  void allocate(std::span<const int32_t> begin, std::span<const int32_t> length);
  // Every track over every one of the n_times common times (hand-built tracks in tests, benches).
  void allocate_full();
  // Bytes of one cell (state, packed covariance, flag) and of the whole object.
  static std::size_t bytes_per_cell(int dim) {
    return sizeof(double) * static_cast<std::size_t>(dim + packed_size(dim)) + sizeof(uint8_t);
  }
  std::size_t bytes() const;
  // Throws (require(), naming `who`) when the arrays do not match the spans.
  void check_layout(const char* who) const;
};

// The longest span of `x`'s tracks: no pair with them has more common times (the gate's
// thresholds are needed up to min(longest_span(a), longest_span(b)) only, not the grid's K).
inline int32_t longest_span(const AlignedTracks& x) {
  int32_t n = 0;
  for (int32_t i = 0; i < x.n_tracks(); ++i) n = n > x.span(i).size() ? n : x.span(i).size();
  return n;
}

// The common times where both spans lie: loops over a pair visit these only.
inline AlignedTracks::Span common_span(AlignedTracks::Span a, AlignedTracks::Span b) {
  return {a.begin > b.begin ? a.begin : b.begin, a.end < b.end ? a.end : b.end};
}

enum class AlignmentMethod {
  kTwoSided,  // the nearest report, before or after the common time (recorded data; default)
  kForward,   // the latest report at or before the common time, predicted forward (seed 000)
};
inline constexpr EnumName<AlignmentMethod> kAlignmentMethodNames[]{{AlignmentMethod::kTwoSided, "two-sided"},
                                                                   {AlignmentMethod::kForward, "forward"}};
constexpr std::span<const EnumName<AlignmentMethod>> enum_names(AlignmentMethod) {
  return kAlignmentMethodNames;
}

struct AlignmentOptions {
  AlignmentMethod method = AlignmentMethod::kTwoSided;
  // White-noise acceleration σ [m/s²] of the CV model used to move a report to the common time.
  // 0 moves the covariance without process noise. 2 m/s² is the measured best on the recorded family
  // (tests/kernels/statistics/test_gate_calibration.cpp); seed 000's studies use 1.
  double process_noise = 2.0;
  // kForward: a track is valid at a common time only if its latest report is at most this old [s].
  // kTwoSided: valid from this long before its first report to this long after its last [s].
  double max_extrapolation = 10.0;
  // Manoeuvre lag inflation (kTwoSided only; 0 = off): the covariance of a report is inflated by
  // the bias that a constant-velocity filter builds up under acceleration â (its position lags by
  // â·τ², its velocity by â·τ, with τ² = P_pp/P_vv, the steady-state lag time² of a CV Kalman
  // filter read off its own covariance), times this factor²; â is the track's own velocity
  // change between its neighbouring reports. See the .cpp.
  double lag_inflation = 0.5;  // measured: tests/kernels/statistics/test_gate_calibration.cpp
  // Look-ahead lag (kTwoSided only; 0 = off): a filter that lags a turn is still turning after
  // it, so the velocity change the track still makes over the next τ, Δv_τ, is its velocity lag
  // now (a low-process-noise tracker lags for minutes after a turn, longer than â lasts): the
  // report's velocity variance gains (h·|Δv_τ|)² and its position variance (h·|Δv_τ|·τ)², h this
  // factor.
  double lag_look_ahead = 1.1;
  // Both lag terms count a velocity change only beyond this many times its noise variance,
  // |Δv|² − margin·tr(P_v,i + P_v,j) (an unbiased |Δv|² at margin 1 for independent errors): noisy
  // velocities of a steady track then widen nothing, which would blur neighbours in dense traffic.
  // Measured on the recorded family, recorded_10k and the gate calibration (docs/status.md).
  double lag_noise_margin = 1.5;
  // Both lag terms apply to a sensor only if its reports are a filter's output: the median of the
  // whiteness ratio of its velocities' second differences, relative to independent errors' (1), is
  // below this (kernels/statistics/report_whiteness.hpp: simulated CV Kalman filters give 0.01–0.5,
  // independent errors 1). +inf keeps them for every sensor.
  double whiteness_threshold = 0.6;
  // Reference-point σ_r [m] per position axis (0 = off: point targets, the default). Two sensors
  // tracking an extended target follow different points of it (the centroid of the returns each
  // sees from its own aspect: the near side of a hull for a lidar, the strongest scatterers for a
  // radar), and a residual registration bias shifts one sensor's tracks as a whole; neither is in
  // the local covariances, and neither averages out over scans. Each aligned report's position
  // variance gains σ_r²/2, so every pair's C = P_a + P_b gains σ_r²·I on its position block, and
  // the candidate bounds, the pruning and the statistic all see it (Bar-Shalom, Willett & Tian,
  // "Tracking and Data Fusion", 2011, §8.4 on registration errors in track association).
  double extent_sigma = 0.0;
  void validate() const;
};

// Resamples the tracks of `sensor` in `tracks` at `common_times` (ascending), each over its span.
// O(rows log rows + Σ spans · D³) time, the tracks in parallel (TBB; the same output for any number
// of threads), O(Σ spans) memory.
AlignedTracks align_tracks(const TrackTable& tracks, int32_t sensor, std::span<const double> common_times,
                           const AlignmentOptions& options);

// The span of a track reporting over [first, last]: the common times where align_tracks can find
// it valid (AlignmentOptions::max_extrapolation, by method), as indices [begin, end) into
// `common_times`; the same comparisons as the validity rule, so no valid time is left out. O(log K).
AlignedTracks::Span alignment_span(double first, double last, std::span<const double> common_times,
                                   const AlignmentOptions& options);

// The number of tracks and of cells (Σ of their span lengths) align_tracks would store for
// `sensor`, in O(rows·log tracks + tracks·log K) without allocating them: what a caller checks
// against a memory budget.
struct AlignedSize {
  int64_t tracks = 0, cells = 0;
};
AlignedSize aligned_size(const TrackTable& tracks, int32_t sensor, std::span<const double> common_times,
                         const AlignmentOptions& options);

// The link cost of a gated-in pair, from its excess over the gate λ − G(n) ≤ 0 (see the header):
enum class LinkCost {
  kPerScan,            // (λ − G(n)) / n, the mean excess per common scan
  kPerIndependentScan  // (λ − G(n)) / f, in units of independent scans (default, measured:
                       // docs/design.md §4.3, "Cost")
};

enum class GateMethod {
  kCalibrated,    // capped terms, f·χ²(n·D/f) (default; see the header comment)
  kChiSquareSum,  // λ ≤ χ²_p(n·D), seed 000 as printed (independent scans)
};
inline constexpr EnumName<GateMethod> kGateMethodNames[]{{GateMethod::kCalibrated, "calibrated"},
                                                         {GateMethod::kChiSquareSum, "chi2-sum"}};
constexpr std::span<const EnumName<GateMethod>> enum_names(GateMethod) { return kGateMethodNames; }

struct StatisticOptions {
  bool correlated = false;         // Bar-Shalom–Campo correlated-error form
  double cross_correlation = 0.0;  // ρ in [0, 1) for the correlated form
  // Correlated errors from common process noise (Bar-Shalom & Campo 1986; seed 000 §4's
  // "节点间误差相关" case): σ_a [m/s²] of the targets' white-noise acceleration, which the local
  // CV Kalman filters also assume; > 0 computes the cross-covariance by the recursion
  //   P_ab(k) = A_a(k)·[F P_ab(k−1) Fᵀ + Q]·A_b(k)ᵀ,   A(k) = I − K(k)H = P(k)·[F P(k−1) Fᵀ + Q]⁻¹,
  // reading each filter's gain off its own reported covariances (kernels/statistics/cross_covariance.hpp),
  // and uses C = P_a + P_b − P_ab − P_abᵀ. 0 = off. Exclusive with `correlated`.
  double common_process_noise = 0.0;
  double gate_probability = 0.99;  // nominal acceptance of a true pair; 1.0 disables gating
  GateMethod gate = GateMethod::kCalibrated;
  double cap_probability = 0.999;      // kCalibrated: c = χ²_D(cap_probability) per scan, in (0, 1)
  double scans_per_independent = 5.0;  // kCalibrated: f ≥ 1, the variance inflation (measured)
  LinkCost link = LinkCost::kPerIndependentScan;
  void validate() const;
};

// The gate and the link cost for one statistic (D, options): what every pipeline uses, dense or
// sparse, so the decision is made in one place.
class SequentialGate {
 public:
  // Thresholds for 1..max_scans common scans are computed once here (a χ² quantile each); others
  // on demand.
  SequentialGate(int dim, const StatisticOptions& options, int32_t max_scans = 0);
  // The largest accepted statistic over n ≥ 1 common scans (+inf with the gate off).
  double threshold(int32_t scans) const;
  // The per-scan cap c (kCalibrated; +inf for kChiSquareSum).
  double cap() const { return cap_; }
  // Gate decision for a statistic `lambda` over `scans` common scans, of which `below_cap` had a
  // term ≤ c (kCalibrated needs at least one).
  bool accepts(double lambda, int32_t scans, int32_t below_cap) const;
  // ≤ 0 inside the gate: the cost of linking two tracks in the S-D assignment, where not linking
  // costs 0; (λ − G(n))/f or (λ − G(n))/n by StatisticOptions::link (kChiSquareSum: f = 1).
  double link_cost(double lambda, int32_t scans) const;
  // The same for an excess λ − G already taken against some threshold G (a tightened gate's:
  // engine/pipeline/sparse_sd_pipeline.hpp, rival_link_costs): excess/f or excess/n.
  double excess_cost(double excess, int32_t scans) const;
  bool enabled() const { return enabled_; }

 private:
  int dim_ = 4;
  bool enabled_ = true, calibrated_ = true, per_scan_ = true;
  double p_ = 0.99, f_ = 1.0, cap_ = 0.0;
  std::vector<double> cache_;  // threshold by scans, 1..max_scans
};

// λ for every pair (a, b): lambda[a·n_b + b], with its degrees of freedom and the gate decision.
struct PairStatistic {
  int32_t n_a = 0, n_b = 0;
  std::vector<double> lambda;    // Eq. 1–2 (kCalibrated: with capped terms)
  std::vector<int32_t> dof;      // D · (number of common times); 0 when never together
  std::vector<uint8_t> in_gate;  // 1 when the pair is a candidate
  int32_t scans(std::size_t pair, int32_t dim) const { return dim > 0 ? dof[pair] / dim : 0; }
};

PairStatistic independent_sequential_statistic(const AlignedTracks& a, const AlignedTracks& b,
                                               const StatisticOptions& options);

// The gate independent_sequential_statistic(a, b, options) makes for itself (its thresholds
// computed up to the longest common span of a and b), to be made once and shared by calls on
// tables of rows of a and b (sparse_sequential_statistic's blocks): a threshold is the same number
// whichever gate computed it, so the statistic is identical.
SequentialGate sequential_gate_for(const AlignedTracks& a, const AlignedTracks& b,
                                   const StatisticOptions& options);
PairStatistic independent_sequential_statistic(const AlignedTracks& a, const AlignedTracks& b,
                                               const StatisticOptions& options, const SequentialGate& gate);

// Per-scan terms dᵀC⁻¹d of one pair at every common time (NaN where either track is invalid):
// the raw series behind λ, for calibration studies and tests.
std::vector<double> scan_terms(const AlignedTracks& a, int32_t ia, const AlignedTracks& b, int32_t ib,
                               const StatisticOptions& options);

}  // namespace trackassoc
