// Batched alpha-beta filter bank (docs/design.md §4.2), structure of arrays, 2-D and 3-D.
//
// Algorithm. Each track is a constant-velocity state per axis a (position p, velocity v), filtered
// independently per axis with scalar gains α, β (Bar-Shalom, Li, Kirubarajan, "Estimation with
// Applications to Tracking and Navigation", 2001, §6.5; Kalata 1984):
//   predict(T):  p ← p + T·v                       (v unchanged)
//   update(z):   r = z − p;  p ← p + α·r;  v ← v + (β/T)·r
// T is the time step of the preceding predict. Gains, either
//   - fixed: the user's α, β (stable for 0 < α < 2, 0 < β < 4 − 2α), or
//   - Kalata steady state (default): tracking index λ = σ_w·T²/σ_v, where σ_w is the σ of the
//     piecewise-constant white acceleration [m/s²] and σ_v the position measurement σ [m];
//       α = −(λ² + 8λ − (λ + 4)·√(λ² + 8λ))/8,   β = (λ² + 4λ − λ·√(λ² + 8λ))/4
//     (Kalata, "The tracking index", IEEE T-AES 20(2), 1984, Eq. 27–28). These are the gains of
//     the steady-state Kalman filter of the same model, so the filter is optimal in steady state.
//     σ_v is per track (measurement_noise[i], initialised to the option), so a bank can hold
//     tracks measured with different accuracy (e.g. converted radar plots at different ranges).
//   Expanding-memory start (default on): a track that has absorbed n measurements (n = 2 after a
//   two-point initialisation) updates with the least-squares straight-line gains
//     g_n = 2(2n + 1)/((n + 2)(n + 1)),   h_n = 6/((n + 2)(n + 1))
//   (Brookner, "Tracking and Kalman Filtering Made Easy", 1998, §1.2.6; Morrison 1969) while g_n
//   exceeds the steady-state α, then switches to (α, β). So a new track converges as fast as a
//   least-squares fit of its measurements instead of creeping from its initial state.
//   Gains are recomputed at every predict from its T (so irregular steps are handled); a predict
//   with T = 0 keeps the previous gains and step, and the following update corrects the position
//   with α and the velocity with β over the last positive step. A track not predicted since
//   initialise has zero gains, so an update leaves it unchanged.
// Covariance: an α-β filter carries none; alpha_beta_steady_covariance() gives the exact
// steady-state covariance of the closed loop (any stable gains, with process and measurement
// noise) by solving its discrete Lyapunov equation, e.g. to fill /tracks/cov.
//
// Layout. position[a][i], velocity[a][i] for axis a < spatial_dim, track i; alpha[i], beta[i],
// step[i] hold the gains of the current step. One predict/update call advances the whole bank by
// one scan; the loops run over contiguous blocks (vectorised) split across TBB by
// parallel_for_range. The per-track calls (predict_track, update_track) use the same element
// kernels, for sequential (packet-by-packet) users such as the fuzzy association of seed 001.
// Complexity: O(n·spatial_dim) per call, memory 2·spatial_dim + 3 doubles per track.
// Deterministic: every element is independent, so results are bit-identical for any thread count.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "kernels/core/enum_names.hpp"

namespace trackassoc {

enum class AlphaBetaGainMode {
  kFixed,   // the user's alpha, beta
  kKalata,  // steady-state gains from the tracking index (default)
};
inline constexpr EnumName<AlphaBetaGainMode> kAlphaBetaGainModeNames[]{
    {AlphaBetaGainMode::kFixed, "fixed"}, {AlphaBetaGainMode::kKalata, "kalata"}};
constexpr std::span<const EnumName<AlphaBetaGainMode>> enum_names(AlphaBetaGainMode) {
  return kAlphaBetaGainModeNames;
}

struct AlphaBetaOptions {
  AlphaBetaGainMode gains = AlphaBetaGainMode::kKalata;
  double alpha = 0.5;                  // fixed gains only; 0 < α < 2
  double beta = 0.2;                   // fixed gains only; 0 < β < 4 − 2α
  double process_noise = 1.0;          // σ_w [m/s²], Kalata gains only; > 0
  double measurement_noise = 100;      // σ_v [m], Kalata gains only; > 0
  bool expanding_memory_start = true;  // least-squares gains until they fall to the steady ones
  std::size_t grain = 4096;            // smallest block of tracks per TBB task
  // Throws InputError naming the field.
  void validate() const;
};

struct AlphaBetaGains {
  double alpha = 0.0, beta = 0.0;
};

// Kalata's tracking index λ = σ_w·T²/σ_v.
double tracking_index(double process_noise, double measurement_noise, double step);
// Expanding-memory (least-squares line) gains for the update that brings a track to n + 1
// measurements: (g_n, h_n) of the header comment.
AlphaBetaGains expanding_memory_gains(int64_t n);
// Steady-state α, β for a tracking index λ ≥ 0 (Kalata 1984 Eq. 27–28).
AlphaBetaGains kalata_gains(double lambda);
// The gains the bank uses for a step T > 0 under `options` (σ_v = options.measurement_noise),
// and the same for a track with its own measurement σ_v.
AlphaBetaGains alpha_beta_gains(const AlphaBetaOptions& options, double step);
AlphaBetaGains alpha_beta_gains(const AlphaBetaOptions& options, double step, double measurement_noise);

// Steady-state covariance (per axis) of the filtered estimate, packed (pp, pv, vv), for gains g,
// step T, white acceleration σ_w (0 = none) and measurement σ_v: the fixed point of
//   P = (I − K H)(F P Fᵀ + Q)(I − K H)ᵀ + K σ_v² Kᵀ,  K = [α, β/T]ᵀ, Q = σ_w²·[T⁴/4 T³/2; T³/2 T²].
// Throws InputError when the gains are not stable.
std::array<double, 3> alpha_beta_steady_covariance(AlphaBetaGains g, double step, double process_noise,
                                                   double measurement_noise);

class AlphaBetaBank {
 public:
  AlphaBetaBank(int spatial_dim, std::size_t num_tracks, const AlphaBetaOptions& options);

  int spatial_dim() const { return spatial_dim_; }
  std::size_t size() const { return alpha.size(); }
  const AlphaBetaOptions& options() const { return options_; }

  // Sets track i's state; `measurements` is how many measurements it already summarises (2 for a
  // two-point initialisation, 1 for a first plot with zero velocity, 0 for a prior guess), which
  // sets the expanding-memory start. pos and vel have spatial_dim entries.
  void initialise(std::size_t i, std::span<const double> pos, std::span<const double> vel,
                  int64_t measurements = 2);
  // Appends a track and returns its index.
  std::size_t add_track(std::span<const double> pos, std::span<const double> vel, int64_t measurements = 2);

  // Advances every track by `step` ≥ 0 seconds and sets the step's gains.
  void predict(double step);
  // Advances track i by steps[i] (one entry per track; 0 leaves the track where it is).
  void predict(std::span<const double> steps);
  // Corrects every track i with detected[i] != 0 by the position measurement z[a][i]
  // (z has spatial_dim spans of size() entries).
  void update(std::span<const std::span<const double>> z, std::span<const uint8_t> detected);

  // The same element kernels for one track.
  void predict_track(std::size_t i, double step);
  void update_track(std::size_t i, std::span<const double> z);

  // The (α, β) the next update of track i applies (expanding-memory or steady; zero when the
  // track has not been predicted since initialise). The velocity gain is β / step[i]. Lets a
  // caller propagate the estimate's covariance for the gains actually used.
  AlphaBetaGains next_update_gains(std::size_t i) const;

  // State, SoA: position[a][i], velocity[a][i]; gains and step of the current step.
  std::array<std::vector<double>, 3> position, velocity;
  std::vector<double> alpha, beta, step;
  std::vector<int64_t> measurements;  // measurements absorbed per track (expanding-memory start)
  // σ_v per track [m] for the Kalata gains (options.measurement_noise when added); read at predict.
  std::vector<double> measurement_noise;

 private:
  int spatial_dim_;
  AlphaBetaOptions options_;
};

}  // namespace trackassoc
