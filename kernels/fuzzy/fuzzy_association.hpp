// Fuzzy track-to-track association with temporary tracks and track reliability (seed 001,
// Fan, Xie, Liu, Li 2011; docs/design.md §4.6).
//
// The fusion centre receives the local tracks as a stream of packets, one plot each
// (seed 001 §2: s_l^i(k) = {x_l^i(k), h_l^i, t_k, ω'_l}), and processes them sequentially in time
// order:
//   1. Temporary track (§2): the packet and the previous packet of the same local track,
//      S_T = {s(k−1), s(k)}: position p = x(k), velocity v = (x(k) − x(k−1)) / (t_k − t_{k−1}).
//      The first packet of a local track forms none.
//   2. Fuzzy factors (§3.1) against every live system track j, predicted to t_k at constant
//      velocity (sensors are asynchronous here, the paper assumes synchronous ones):
//        u1 = |p_T − p_j|                                 Eq. 2
//        u2 = | |v_T| − |v_j| |                           Eq. 3 as printed adds x and y of the
//             positions inside one root; the intended factor is the speed difference (erratum)
//        u3 = |wrap(atan2(v_T) − atan2(v_j))| ∈ [0, π]    Eq. 4 as printed uses arctan(y/x), which
//             loses the quadrant, and does not wrap (erratum: 359° vs 1° is 2°, not 358°)
//   3. Gaussian memberships d(u) = exp(−(u/u_max)²) (Eq. 5) and a synthesis function S (Eq. 9–13;
//      Eq. 11 with a = (0.55, 0.35, 0.1) by default).
//   4. Weighted association degree μ = ω'·S(M) (Eq. 15–16), ω' = ω / max ω (Eq. 1). Which ω' the
//      paper means is ambiguous: the temporary track's (its node's) reliability is the same for all
//      candidate system tracks, so on its own it could never change the choice the paper says it
//      changes; the paper also defines a system track's reliability as that of its latest packet.
//      ReliabilityWeighting selects the reading; the default, kProduct, uses ω'_T·ω'_j: the argmax
//      follows the system track's reliability, and min_degree sees the temporary track's.
//   5. The temporary track joins the system track of maximum μ among those with u1 ≤ gate and
//      μ ≥ min_degree; otherwise it starts a new system track (§1, Fig. 1).
//   6. System tracks are smoothed by an alpha-beta filter (kernels/filters/alpha_beta.hpp) updated with
//      the temporary track's position; a new system track starts at the temporary track's state.
// The factors are horizontal (x, y), as in the paper.
//
// Complexity: O(J) per packet for J live system tracks (one pass of a few flops each), O(P·J) for
// P packets; memory O(P + J). Serial by design: the decision for a packet depends on every earlier
// one (a sequential, streaming fusion centre); Monte Carlo runs are what parallelise.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "kernels/assignment/assignment_types.hpp"
#include "kernels/core/enum_names.hpp"
#include "kernels/filters/alpha_beta.hpp"

namespace trackassoc {

// ---- Memberships and synthesis functions (seed 001 §3.1–3.2) ----

// Gaussian membership exp(−(u/u_max)²), Eq. 5. u ≥ 0, u_max > 0.
double gaussian_membership(double u, double u_max);

enum class SynthesisFunction {
  kPowerMean,          // Eq. 9:  [(1/n) Σ d_l^q]^(1/q), q > 0
  kGeometricMean,      // Eq. 10: (Π d_l)^(1/n)
  kWeightedMean,       // Eq. 11: Σ a_l d_l, a_l ≥ 0, Σ a_l = 1  (the paper's choice, default)
  kWeightedPowerMean,  // Eq. 12: [Σ a_l d_l^q]^(1/q)
  kMinMaxMean,         // Eq. 13: (min d_l + max d_l) / 2
};
inline constexpr EnumName<SynthesisFunction> kSynthesisFunctionNames[]{
    {SynthesisFunction::kPowerMean, "power-mean", "Eq. 9"},
    {SynthesisFunction::kGeometricMean, "geometric-mean", "Eq. 10"},
    {SynthesisFunction::kWeightedMean, "weighted-mean", "Eq. 11"},
    {SynthesisFunction::kWeightedPowerMean, "weighted-power-mean", "Eq. 12"},
    {SynthesisFunction::kMinMaxMean, "min-max-mean", "Eq. 13"}};
constexpr std::span<const EnumName<SynthesisFunction>> enum_names(SynthesisFunction) {
  return kSynthesisFunctionNames;
}

struct SynthesisOptions {
  SynthesisFunction function = SynthesisFunction::kWeightedMean;
  std::vector<double> weights{0.55, 0.35, 0.1};  // a_l of Eq. 11–12 (seed 001 §3.2)
  double q = 2.0;                                // exponent of Eq. 9 and 12
  void validate(std::size_t num_factors = 3) const;
};

// S_n(M) for memberships M ∈ [0,1]^n. Every function satisfies Eq. 7 (monotone) and Eq. 8
// (min ≤ S ≤ max).
double synthesise(std::span<const double> memberships, const SynthesisOptions& options);

// Eq. 1: ω'_l = ω_l / max ω. Throws InputError on an empty list, a negative or non-finite weight,
// or all weights zero.
std::vector<double> normalise_reliabilities(std::span<const double> reliabilities);

// ---- Fuzzy factors between two kinematic states (horizontal) ----

struct PlanarState {
  double x = 0, y = 0, vx = 0, vy = 0;
};
struct FuzzyFactors {
  double position = 0;  // u1 [m]
  double speed = 0;     // u2 [m/s]
  double heading = 0;   // u3 [rad], in [0, π]
};
FuzzyFactors fuzzy_factors(const PlanarState& a, const PlanarState& b);
// Absolute heading difference wrapped to [0, π].
double heading_difference(double heading_a, double heading_b);

struct FactorScales {       // u_max of Eq. 5: the largest tolerable difference of each factor
  double position = 400.0;  // [m]
  double speed = 40.0;      // [m/s]
  double heading = 0.35;    // [rad] (20°)
  void validate() const;
};

// Memberships of the three factors (Eq. 5).
std::array<double, 3> fuzzy_memberships(const FuzzyFactors& u, const FactorScales& scales);

// ---- The packet stream ----

// Packets in SoA form. `local` is a dense local-track index in [0, num_local) (one per
// (sensor, local track) pair), `sensor` the sensor index in [0, S) into the reliability list.
struct PacketSpans {
  std::span<const int32_t> sensor;
  std::span<const int32_t> local;
  std::span<const double> t, x, y;
  std::size_t size() const { return t.size(); }
};

// Throws InputError unless all columns have the same length, values are finite and indices are in
// range.
void validate_packets(const PacketSpans& packets, std::size_t num_sensors, std::size_t num_local);

// The order in which a fusion centre receives the packets: by time, ties in input order.
std::vector<std::size_t> arrival_order(std::span<const double> t);

// The per-packet output of a sequential fusion centre (this kernel and FTAA, kernels/fuzzy/ftaa.hpp):
// the system track the packet went to (−1 = none: a first plot) and the fused system-track
// state right after processing it, at the packet's time, and the association degree μ of the
// decision (NaN when none: a first plot, a new system track, or a method without μ). Rows are in
// input order.
struct FusionOutput {
  std::vector<int32_t> system_track;
  std::vector<double> x, y, vx, vy, degree;
  int32_t num_system_tracks = 0;
  SolverSummary summary;  // termination kHeuristic; iterations = association decisions
  void resize(std::size_t n);
};

// ---- The fuzzy associator ----

enum class ReliabilityWeighting {
  kNone,            // μ = S (the equally reliable case, Eq. 14)
  kTemporaryTrack,  // μ = ω'_T·S
  kSystemTrack,     // μ = ω'_j·S, ω'_j of the system track's latest packet
  kProduct,         // μ = ω'_T·ω'_j·S (default)
};
inline constexpr EnumName<ReliabilityWeighting> kReliabilityWeightingNames[]{
    {ReliabilityWeighting::kNone, "none"},
    {ReliabilityWeighting::kTemporaryTrack, "temporary"},
    {ReliabilityWeighting::kSystemTrack, "system"},
    {ReliabilityWeighting::kProduct, "product"}};
constexpr std::span<const EnumName<ReliabilityWeighting>> enum_names(ReliabilityWeighting) {
  return kReliabilityWeightingNames;
}

struct FuzzyAssociationOptions {
  FactorScales scales;
  SynthesisOptions synthesis;
  ReliabilityWeighting weighting = ReliabilityWeighting::kProduct;
  double gate = 800.0;         // [m], on u1 (seed 001 §4: tracking gate radius 800 m)
  double min_degree = 0.0;     // μ below this never associates
  double track_timeout = 0.0;  // [s]; a system track not updated for longer is dropped; 0 = never
  AlphaBetaOptions smoother = default_smoother();  // alpha-beta of the system tracks
  static AlphaBetaOptions default_smoother();      // Kalata, σ_w = 2 m/s², σ_v = 150 m
  void validate() const;
};

// The streaming fusion centre: feed packets in time order; each call makes one decision.
class FuzzyAssociator {
 public:
  FuzzyAssociator(const FuzzyAssociationOptions& options, std::span<const double> reliabilities,
                  std::size_t num_local);
  struct Decision {
    int32_t system_track = -1;  // −1: a first plot, no temporary track yet
    bool new_track = false;
    double degree = 0.0;  // μ of the chosen system track (0 for a new one)
    PlanarState fused;    // the system track's smoothed state after the update
  };
  Decision process(int32_t sensor, int32_t local, double t, double x, double y);

  std::size_t num_system_tracks() const { return last_time_.size(); }
  int64_t decisions() const { return decisions_; }

 private:
  FuzzyAssociationOptions options_;
  std::vector<double> reliability_;  // ω' per sensor
  // Last plot per local track.
  std::vector<double> last_t_, last_x_, last_y_;
  std::vector<uint8_t> has_last_;
  // System tracks: smoothed state in the bank, time and reliability of the latest packet.
  AlphaBetaBank bank_;
  std::vector<double> last_time_, system_reliability_;
  int64_t decisions_ = 0;
};

// Runs the associator over all packets in arrival order. Throws InputError on bad input.
FusionOutput run_fuzzy_association(const PacketSpans& packets, std::span<const double> reliabilities,
                                   std::size_t num_local, const FuzzyAssociationOptions& options);

}  // namespace trackassoc
