// Joint registration and association (docs/design.md §4.10): the registration stage of the default
// (sparse S-D) path. Registration and association need each other, so they are iterated:
//
//   1. associate the file as recorded (the default association, unchanged);
//   2. fit every sensor's registration relative to a reference sensor (the one with the most
//      local tracks; kernels/registration/registration.hpp) on seed pairs that do not depend on
//      the association, so a bias that split every true pair in step 1 is still seen: the pattern
//      step below (pairs at the mode of the position differences). Pair observations are the
//      members' reports, each partner's state interpolated linearly to the report's time between
//      its two reports around it (at most max_gap apart), at most max_observations_per_pair per
//      pair, spread evenly; their velocities (the clock column's) are central differences of the
//      reported positions, not the reported velocities (errors in variables: docs/design.md
//      §4.10). (No seeds: the linked tuples of step 1.)
//   3. test the estimate: its Wald statistic bᵀV⁻¹b (V the cluster-robust covariance) against
//      χ²_dof at 1 − significance. Not significant: stop, and the association of step 1 is the
//      result (so a file without registration errors is associated exactly as without the stage);
//   3b. test whether it matters (practical beside statistical significance): the effect δ_s of
//      sensor s is the mean over its seed observations of mᵀC⁻¹m, m = J_a(x_a)·b_a − J_b(x_b)·b_b
//      the correction of the pair's difference and C its position covariance (registration_effect):
//      how much the correction changes each scan's term dᵀC⁻¹d of the sequential statistic λ of the
//      pairs it was fitted on (a constant offset of c σ adds about c² per scan; issue 29's harmful
//      offsets are 1–3 filtered σ). Counted only for sensors whose seeds are more than k pairs of
//      tracks (k parameters per sensor): a pair's scans are one correlated sample, so fewer pairs
//      than parameters leave the estimate's covariance to the model, which ignores that correlation
//      (the cluster-robust sandwich has rank ≤ pairs; Cameron and Miller, J. Human Resources 50(2),
//      2015, refer such a Wald statistic to F(k, pairs − 1)). When no sensor's δ_s reaches
//      min_effect (1: the correction moves the pairs by one σ of their difference, RMS), it is
//      too small to matter to the association (a registration error shows as true pairs split
//      apart, which takes offsets of 1–3 σ) and the association of step 1 is the result.
//      Measured (docs/design.md §4.10): on the recorded family the injected registration errors
//      give δ ≥ 5.8 on some sensor in every run (recorded_clock 6.3 – recorded_site 61), the files
//      without errors δ ≤ 1.2 (formation) and mixed local trackers 0.4–92 (their lags act as
//      registration; step 6 still decides there); on `widearea` (no registration error injected, Wald 170.7
//      on 75 dof from 3 503 seed observations) δ ≤ 0.29 on every sensor with more than 5 seed pairs (sensor
//      12: Wald 96 from 2 pairs, δ 1.03), where the re-association cost 280 s and was rejected in step 6;
//   4. correct every report of every sensor but the reference, x ← x − J_s(x)·b_s (the azimuth
//      bias also rotates the velocity back), widen its position covariance by J_s V_s J_sᵀ (the
//      registration's own uncertainty, so the re-association tolerates what is left), and
//      associate the corrected file;
//   5. refit on the new association's linked tuples (always from the reports as recorded), and
//      repeat 4-5 until the
//      tuples stop changing or max_rounds associations have run;
//   6. keep the last association only if it links more local tracks (members of tuples of two or
//      more) than the association of step 1: a registration error shows as true pairs split
//      apart, so correcting it links more; otherwise (a formation whose seeds were ambiguous, a
//      significant but harmless error) the association of step 1 stands and `applied` is false.
// The model (kernels/registration/registration.hpp): range, azimuth (and elevation) biases about
// /sensors/position, a site offset and a clock offset, each under a ridge prior; a translation and
// a clock offset alone when the file says the positions are unknown (/sensors attr unknown).
// The estimate, its standard errors and the per-pair covariance scale go to /registration
// (io/registration_file.hpp) whether applied or not, with the attribute applied.
// Cost: one association, plus one per further round (≤ max_rounds) when the estimate is
// significant and material; the fit is O(observations · k²) + O((S·k)³), the effect
// O(observations · k · d).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine/registration/registered_reports.hpp"
#include "io/track_file.hpp"
#include "kernels/registration/registration.hpp"

namespace trackassoc {

struct RegistrationStageOptions {
  bool enabled = true;
  // false: steps 1-3 only (the estimate is written, never applied): the default path over MPI
  // ranks, whose servers solve one association (engine/pipeline/sparse_sd_components.hpp).
  bool reassociate = true;
  int32_t max_rounds = 4;      // associations in all (≥ 2)
  double significance = 1e-6;  // Wald test level: apply when p < significance
  // Step 3b: re-associate only when some sensor's effect δ_s (squared σ per scan, see above)
  // reaches this; 0: the Wald test alone decides.
  double min_effect = 1.0;
  int32_t max_observations_per_pair = 24;  // per pair of local tracks
  double max_gap = 30.0;                   // s, the largest gap between a partner's reports bridged
  double pattern_radius = 5000.0;          // m, the largest registration offset the pattern step looks for
  int32_t pattern_tracks = 300;            // reference tracks the pattern step samples (evenly)
  int32_t reference_sensor = -1;  // a /sensors id held at zero; −1: the sensor in the most observations
  RegistrationOptions fit{.clock_offset = true};  // model and priors (fit.reference_sensor is set here)
  void validate() const;
  nlohmann::json to_json() const;
};

struct RegistrationStageResult {
  bool fitted = false;   // there were linked tuples to fit on
  bool applied = false;  // the association returned used the corrected reports (step 6)
  int32_t rounds = 0;    // associations run
  double wald = 0.0;
  int32_t wald_dof = 0;
  // Step 3b's largest δ_s of the estimate tested in step 3 (NaN when step 3b did not run).
  double effect = std::numeric_limits<double>::quiet_NaN();
  RegistrationEstimate estimate;  // rows in /sensors order
  // When applied: the corrected reports the returned association used (later stages, such as
  // fragment stitching, work on them).
  std::optional<TrackFile> registered;
  RegistrationRecord to_record(const TrackFile& file, const std::string& association,
                               const RegistrationStageOptions& options) const;
};

// The pair observations of the linked tuples of `rec` (columns in /sensors order).
RegistrationObservations registration_observations(const TrackFile& file, const AssociationRecord& rec,
                                                   const RegistrationStageOptions& options);

// The pattern step (Levedahl's global nearest pattern, in its translation form): for every other
// sensor, the position differences of its tracks with up to pattern_tracks tracks of the reference
// (at the middle of their common span, within pattern_radius); their mode (the difference with the
// most others within ρ = 3 × the median position σ of the pairs); the pairs within ρ of it that are
// each other's nearest to it are the seeds, whose observations these are.
RegistrationObservations pattern_observations(const TrackFile& file, int32_t reference,
                                              const RegistrationStageOptions& options);

// Step 3b: the correction's effect on the association statistic of the pairs in `obs`. Per sensor
// (/sensors order): delta, the mean over the observations of a pair with it of mᵀC⁻¹m (m = J_a(x_a)·
// b_a − J_b(x_b)·b_b, C the observation's position covariance; 0 without observations), and pairs,
// the pairs of tracks (clusters) they come from; largest, the largest delta of a sensor other than
// the reference with more than k pairs (0 when none).
struct RegistrationEffect {
  std::vector<double> delta;
  std::vector<int64_t> pairs;
  double largest = 0.0;
};
RegistrationEffect registration_effect(const RegistrationObservations& obs,
                                       const RegistrationEstimate& estimate, const RegistrationOptions& model,
                                       std::span<const std::array<double, 3>> sites);

// Steps 1-6 with `associate` as the association; `result` (optional) gets the registration.
AssociationRecord associate_with_registration(
    const TrackFile& file, const RegistrationStageOptions& options,
    const std::function<AssociationRecord(const TrackFile&)>& associate, RegistrationStageResult* result);

}  // namespace trackassoc
