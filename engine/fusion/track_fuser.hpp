// Fused tracks of an association (issue 17 item 4; MATLAB trackFuser, Stone Soup #179): for each
// tuple of an /associations/<name> record, the fused state and covariance over time, written to
// /fused/<name> (io/fused_tracks_file.hpp). The rules are the kernels of
// kernels/fusion/track_fusion.hpp: naive (independent errors), Bar-Shalom–Campo (with the
// cross-covariance), covariance intersection (ω by trace or determinant).
//
// Members. A tuple's members are its columns ≠ −1 (the tuple's sensors; S columns in /sensors
// order). Tuples with fewer than two members have nothing to fuse and give no rows (counted in
// the summary). A local track may appear in several tuples of one target (track segments, and
// duplicate tracks of one sensor: engine/pipeline/track_segments.hpp). With the association's
// target numbers, a member holds its tuple's slot only while no later-starting track of its
// target on its sensor reports (the slice rule of the segment pass), so the tuples of one target
// are fused over disjoint times and no local report is fused twice at one time.
//
// Time grid (asynchronous sensors). A member covers [its first report, its last report], less the
// times it has handed over (above). The
// fused times of a tuple are the report times of its members at which at least two members cover
// the time: for a pair, the reports of both within the intersection of their spans. At each fused
// time every covering member contributes its estimate there: the report itself at its own report
// time, else its latest earlier report predicted by the constant-velocity model with continuous
// white-noise acceleration σ = process_noise (align_tracks of
// kernels/statistics/association_statistic.hpp, forward, no manoeuvre-lag inflation), as a
// fusion centre predicts its source tracks to the fusion time (MATLAB trackFuser). `sources` says
// how many members were fused at each time. No estimate is extrapolated past a member's span, and
// a stretch that only one member covers is that local track itself, not written again.
//
// Cross-covariance (rule bsc). Two ways, exactly one:
//  * common_process_noise σ_a > 0: the Bar-Shalom–Campo recursion P_ab(k) = A_a(k)[F P_ab(k−1) Fᵀ
//    + Q]A_b(k)ᵀ over the tuple's fused times, each track's A(k) read off its own covariances
//    (kernels/statistics/cross_covariance.hpp, the same code as the associate statistic's
//    --common-process-noise): 0 at the tuple's first fused time. At a fused time where a member
//    did not report, its estimate is a prediction and its A = I; where it did, A is read off its
//    own consecutive reports (gain_complements at its report times, which are its filter's update
//    times: exact for a CV Kalman filter with that σ_a). Between fused times P_ab is propagated
//    with F and the discrete Q of the grid step; for asynchronous sensors the Q of a filter's
//    whole step and that of the grid's sub-steps differ, so the recursion is approximate there.
//  * correlation ρ in [0, 1): P_ab = ρ·P_a^½ P_b^½ (principal square roots), the approximation the
//    statistic's --correlated uses; the joint covariance is then positive definite.
//  A recorded file carries no process-noise information: fuse_track_file takes σ_a from the
//  file's scenario (tracker.process_noise, what the simulated local CV filters assumed) when
//  neither is given, and refuses bsc on a file without a scenario, asking for one of the two
//  (it does not fall back to the naive rule silently). A cell whose joint covariance is not
//  positive definite with the recursion's P_ab (an inconsistent cross-covariance estimate) has
//  P_ab halved until it is; such cells are counted (`shrunk_cells`).
//
// Registration (fuse_track_file). When the file's /registration belongs to the association fused
// (its attribute `association`) and was applied (the association used the corrected reports),
// every report is first corrected exactly as `associate`'s registration stage corrected it
// (registered_file of engine/registration/registered_reports.hpp: x ← x − J_s(x)·b_s for every sensor
// but the reference, the velocity rotated back by the azimuth bias, the position covariance
// widened by J_s V_s J_sᵀ), so the fused states are those of the registered reports. The
// correction is relative to the reference sensor: its own error stays in every fused state.
// /registration is one per file, of the association `associate` wrote last with the default
// pipeline; any other association (or an estimate not applied) is fused as recorded.
//
// Output rows are ordered by tuple, then time; the tuple's truth is its members' common
// /tracks/truth (−1 when they differ). Work is split over tuples (oneTBB), each tuple serial, so
// the result is bit-identical for any thread count.
// Complexity: O(Σ_tuples K_t·(m·R + m²·D³)) for K_t fused times, m members and R rows per member
// (the alignment walks each member's rows); CI adds its ω search per time.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/track_file.hpp"
#include "kernels/fusion/track_fusion.hpp"

namespace trackassoc {

struct TrackFuserOptions {
  FusionRule rule = FusionRule::kNaive;
  CiOptions ci;                       // rule ci
  double common_process_noise = 0.0;  // rule bsc: σ_a [m/s²] of the BSC recursion; 0 = not given
  double correlation = -1.0;          // rule bsc: ρ in [0, 1) for P_ab = ρ·P_a^½ P_b^½; < 0 = not given
  double process_noise = 2.0;         // σ [m/s²] moving a report to a fused time (the alignment default)
  bool registration = true;           // fuse_track_file: correct by the association's /registration
  void validate() const;              // bsc: exactly one of common_process_noise, correlation
  nlohmann::json to_json() const;
};

struct TrackFuserSummary {
  int32_t tuples = 0;                     // tuples of the association
  int32_t fused_tuples = 0;               // tuples with fused rows
  int32_t single_member = 0;              // tuples of fewer than two members
  int32_t no_overlap = 0;                 // tuples of ≥ 2 members never covered by two at once
  int64_t rows = 0;                       // fused rows written
  int64_t shrunk_cells = 0;               // bsc: cells where P_ab was shrunk to a positive definite joint
  std::string cross_covariance = "none";  // "common-process-noise" | "correlation" (bsc)
  std::string cross_covariance_source;    // where σ_a or ρ came from, for the printout
  bool registered = false;                // fuse_track_file: the reports were corrected by /registration
  std::string registration;               // fuse_track_file: why they were, or were not, for the printout
  double runtime_s = 0.0;
  std::string termination;
};

// The fused tracks of `association` (tuples in /sensors order) as /fused/<name>.
FusedTrackRecord fuse_association(const TrackTable& tracks, const std::vector<Sensor>& sensors,
                                  const AssociationRecord& association, const TrackFuserOptions& options,
                                  const std::string& name, TrackFuserSummary* summary = nullptr);

// Fuses /associations/<association> of `file` ("" = the file's only association) into
// /fused/<name> ("" = the association's name), replacing a group of that name; for bsc without
// σ_a or ρ, σ_a is the scenario's tracker.process_noise (InputError when the file has none).
// With options.registration, the reports are corrected by the association's /registration first
// (above); the group's options JSON records "registration": true when they were. `path` names the
// file in errors.
TrackFuserSummary fuse_track_file(TrackFile& file, const std::string& association, const std::string& name,
                                  TrackFuserOptions options, const std::string& path = "the input file");

}  // namespace trackassoc
