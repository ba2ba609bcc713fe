// Track segments (issue 17 item 5): one target followed on one sensor by several local tracks in
// sequence (a track break: the tracker lost the target and started a new track, or a track was
// dropped and re-initiated), each of which must still be associated with the target's tracks on
// the other sensors.
//
// The S-D assignment is one-to-one per sensor over the whole recording, so of the segments
// s₁, s₂, … that one sensor gives a target, it links at most one with the target's track on
// another sensor; the others stay unassociated. This pass, run after the assignment of the
// sparse S-D pipeline (engine/pipeline/sparse_sd_pipeline.hpp), joins them. A *target* is a
// tuple of the assignment with ≥ 2 members; it holds, per sensor, a list of segments that follow
// each other. In rounds, until no segment joins:
//   * every local track u in no target (sensor s) is a candidate for every target T such that
//     (a) u follows or precedes every segment T already holds on s: their report intervals
//         overlap by at most `max_overlap_s`, the earlier track's *coasted tail* left out (of two
//         that start together, neither's): the trailing
//         run of reports whose position variance (the trace of the position block) grows by more
//         than (1 + coast_growth)² from one report to the next, a local tracker's predictions
//         after it lost the target (its updates keep the variance about level). A tracker that
//         loses a target in a turn coasts a few scans while it starts the successor from the
//         target's plots, so the two overlap by those scans (Stone Soup's tracker on
//         bench/stonesoup_recordings.py's files: 2-3 scans, 6-10 s; docs/status.md, "Independent
//         recordings"). Such a pair counts as one after the other only when the later one's first
//         report continues the earlier one's last report before its tail (the continuation
//         statistic of engine/pipeline/track_hygiene.hpp with σ_a = successor_manoeuvre_sigma), and
//         only for a join (a merge, below, allows the plain overlap and the takeover); or, on a sensor listed
//         in `duplicate_sensors`, u is a *duplicate* of each segment it overlaps by more: a second track of
//         the same target at the same time (a lidar resolves a long hull into two clusters 15–30 m apart, and
//         each starts a track). The duplicate test, over the common times inside both report intervals (at
//         least `min_duplicate_times` of them; the common times are the pipeline's grid, at the slowest
//         sensor's period, not the sensor's own scans): every one passes the full-state gate
//             Δᵀ (P_u + P_m)⁻¹ Δ ≤ χ²_D(duplicate_probability),
//         Δ the difference of the aligned states (position and velocity), P the aligned
//         covariances with the reference-point σ_r of AlignmentOptions::extent_sigma. Two tracks of
//         one sensor share its measurements, so their errors are positively correlated and the sum
//         P_u + P_m overstates the variance of Δ: the test is lenient on the errors and is meant
//         to separate two points of one hull from two craft, which differ in velocity or drift
//         apart. Every time must pass, so a long overlap of true duplicates is refused more often
//         (0.999ⁿ for n independent times; their errors are correlated, which helps). It is per sensor
//         because a sensor that gives one plot per target (a radar with a beam wider than the hull) has no
//         such duplicates, and there two tracks side by side are two craft (Autoferry scenario 17: a jet boat
//         beside Havfruen);
//         The *takeover*: a tracker may also go on updating the lost track now and then (a plot in
//         its gate) while the successor reports. The two then follow each other when they overlap
//         by at most `takeover_s`, the later one goes on after the earlier one ends, the earlier
//         one ends coasting and of its reports after the later one's first at least two and at
//         least half grow in position variance as a coasted report does (a *lost* track,
//         engine/pipeline/coasted_tail.hpp; a second craft tracked beside the target keeps its
//         variance level), and the later one's first report continues the earlier one's last
//         report at most `max_overlap_s` after that first report, as above (docs/status.md,
//         "Independent recordings": Stone Soup's GNN tracker overlaps them by 4-18 s). In joins
//         and merges;
//     (b) u is linked — gated in by the sequential statistic, with a link cost ≤ 0
//         (SequentialGate::link_cost) — to at least one member of T on another sensor whose
//         report interval overlaps u's (evidence from common reports, not from extrapolation);
//     (c) no member of T on another sensor was tested against u and failed the gate (a pair with
//         common valid times and no gated link, the rule of the S-D tuples); a doubtful pair (the
//         family-wise veto, engine/pipeline/tuple_cost.hpp) does not fail it: it adds its positive
//         link cost and is no evidence for (b), as in a tuple;
//     with cost Σ of u's link costs to T's members on the other sensors;
//   * one LAP over candidates × targets (kernels/assignment/lap.hpp, unassigned allowed at 0, so
//     every allowed join is worth making) gives each target at most one new segment per round
//     and each candidate at most one target: two segments that overlap each other never join
//     one target on one sensor in the same round, and (a) keeps it so in later rounds unless the
//     later one is a duplicate of the earlier (a listed sensor).
//   * when a round joins nothing, targets merge: two targets whose members on each sensor follow
//     each other (a; the plain overlap or a takeover, never the coasted tail: on a dense airway it
//     merged neighbours, docs/design.md §4.9) and, on at least one sensor they share, each member
//     whose predecessor is the other target's continues from it by constant velocity (d;
//     predecessors_across below; a takeover by its own continuation test), with at least one pair of members
//     on different sensors linked
//     over common reports (b) and none tested and failed (c), are one target's fragments that the
//     one-per-sensor assignment put into two tuples: two sensors that broke their tracks at about the same
//     time (both keys of a swap cut, engine/pipeline/track_hygiene.hpp), or one after the other (a radar
//     network's handovers and fades: {A₁, B₁} and {A₂, B₂} linked only by B₁–A₂). Candidates are taken
//     cheapest first (Σ of the link costs between them), each target in one merge per round; then
//     the rounds of joins go on.
// A track joins at most one target, so the pass only adds links; it never undoes the assignment.
//
// Output (the record's tuples, over the file's sensor columns): each target's segments are cut
// into time slices at every segment's first and last report; in each slice the tuple holds, per
// sensor, the segment reporting then (of two overlapping segments or duplicates, the one whose
// first report is later, which took the target over; of equal first reports, the one that joined
// first); a slice equal to an earlier one is not written again, slices of one member are dropped
// (the fuser, engine/fusion/track_fuser.hpp, applies the same rule to fuse each tuple over its
// slices only). A target that
// gained no segment gives its assignment tuple unchanged. Every track of a target appears in at
// least one tuple (a segment in no slice of two members is written as a tuple of one), and every
// tuple carries its target number in `target` (/associations/<name>/target, io/track_file.hpp):
// tuples of one target are the same vessel, aircraft, ... over time. The local tracks in no
// target keep their tuples of one with a target number of their own.
//
// Complexity: per round O(U·T·m) to build the candidates (U free tracks, T targets, m members per
// target, each link looked up in a hash map) and O(max(U, T)³) for the LAP; rounds ≤ the largest
// number of segments one target gains (a few on recorded data).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <utility>
#include <vector>

#include "io/track_file.hpp"
#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc {

struct SparseSDProblem;  // engine/pipeline/sparse_sd_pipeline.hpp

struct SegmentOptions {
  bool enabled = true;         // join the segments of a target (off: the assignment's tuples)
  double max_overlap_s = 2.0;  // [s] report overlap (a) that still counts as "one after the other"
  // (a): a report whose position variance exceeds (1 + coast_growth)² times the one before it, in
  // the run that ends a track, is a coasted prediction, left out of the overlap (0: none).
  double coast_growth = 0.1;
  // (a): the successor of a coasted track continues its last report before the tail by constant
  // velocity with this manoeuvre allowance σ_a [m/s²] (the tracker lost the target in a manoeuvre:
  // the stitching's manoeuvring model, engine/pipeline/track_stitching.hpp), at χ²_D(0.9999).
  double successor_manoeuvre_sigma = 20.0;
  // (a): the takeover of a lost track (engine/pipeline/coasted_tail.hpp): a successor that starts
  // while its predecessor goes on reporting, by at most this overlap [s], and outlasts it, follows
  // it when the predecessor's reports after the successor's start are a lost track's and the
  // successor's first report continues the predecessor's last report at most max_overlap_s after
  // that start, as above (0: no takeover; coast_growth 0 turns it off too). The lost-track test
  // sees a track's latest 12 reports (kCoastWindow): an overlap holding more than 11 of the
  // predecessor's reports is refused (a sensor scanning faster than every 1.8 s reaches 20 s less).
  double takeover_s = 20.0;
  std::vector<int32_t> duplicate_sensors;  // sensor ids whose tracks may be duplicates (a); none
  double duplicate_probability = 0.999;    // of the per-time full-state duplicate gate (a)
  int32_t min_duplicate_times = 3;         // common times the duplicate test needs (a)
  void validate() const;                   // throws InputError naming the field
  nlohmann::json to_json() const;
};

struct SegmentSummary {
  int32_t targets = 0;         // tuples of ≥ 2 members of the assignment
  int32_t joined = 0;          // segments joined to them
  int32_t duplicates = 0;      // of which duplicates (a) of a segment on their sensor
  int32_t rounds = 0;          // rounds run (the last one joins nothing)
  int32_t targets_joined = 0;  // targets that gained at least one segment
  int32_t targets_merged = 0;  // targets merged into another (the merge rule above)
};

// Throws InputError (naming segments.duplicate_sensors) when a listed sensor is not among
// `sensor_ids`, the associated sensors: checked before the assignment runs.
void check_duplicate_sensors(const SegmentOptions& options, const std::vector<int32_t>& sensor_ids);

// Rule (a)'s duplicate statistic of tracks i and j (rows of one sensor's aligned tracks): the
// largest per-time full-state Δᵀ(P_i + P_j)⁻¹Δ over the common times in [t_lo, t_hi] where both
// are valid (+inf at a time whose sum is not positive definite), and the number of those times.
struct DuplicateStatistic {
  double max_d2 = 0.0;
  int32_t times = 0;
};
DuplicateStatistic duplicate_statistic(const AlignedTracks& a, int32_t i, int32_t j, double t_lo,
                                       double t_hi);

// Rule (d) of a merge: of the members `a` and `b` of two targets on one sensor (nodes indexing
// `first` and `last`, their first and last report times), each member's predecessor — of the
// members that start before it (ties by node), the one whose last report is latest — when it belongs
// to the other target: the pairs (predecessor, member), by the member's first report. Tracks that
// follow each other give consecutive pairs; of a track and its duplicate nested in it (a listed
// sensor), the longer one precedes what follows both.
std::vector<std::pair<int32_t, int32_t>> predecessors_across(std::span<const int32_t> a,
                                                             std::span<const int32_t> b,
                                                             std::span<const double> first,
                                                             std::span<const double> last);

// Joins the segments of `record` (the assignment of `p`, tuples over p.file_sensors columns) by the
// rule above; `tracks` gives the report intervals. Throws InputError when
// options.duplicate_sensors names a sensor that is not associated. Returns the record with the tuples
// rewritten, `target` filled, and the cost of each new tuple the sum of its members' link costs (the
// objective and the bound stay the assignment's).
AssociationRecord join_track_segments(const SparseSDProblem& p, const TrackTable& tracks,
                                      const AssociationRecord& record, const SegmentOptions& options,
                                      SegmentSummary* summary = nullptr);

}  // namespace trackassoc
