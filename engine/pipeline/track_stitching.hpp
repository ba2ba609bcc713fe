// Fragment stitching (docs/design.md §4.10): one target followed by different sensors at different
// times. A target that leaves one radar's coverage and enters another's, or a track that one
// sensor drops and another picks up later, gives output groups (the tuples of one target number)
// that never coexist; an association over common times can never link them, since they share no
// time. This pass, run on the default path after the association (and its registration), joins
// such groups when the motion of the earlier one explains the start of the later one, unambiguously.
//
// Rule. A *group* is the set of local tracks of one target number of the record (a tuple of one
// member is a group too). Its end is its latest report x₀ (P₀), its start its earliest report.
// For groups G₁, G₂ with G₂'s start within [G₁'s end − max_overlap_s, G₁'s end + max_gap_s], the
// end of G₁ is predicted over the gap Δt by constant velocity with a manoeuvre allowance,
// x̂ = F x₀, P̂ = F P₀ Fᵀ + Q (Q the continuous white-noise acceleration model of spectral density
// σ_a², Bar-Shalom, Li, Kirubarajan 2001 §6.2.2), and compared with G₂'s start x₁ (P₁):
//     m² = (x₁ − x̂)ᵀ (P̂ + P₁)⁻¹ (x₁ − x̂) ≤ χ²_D(gate_probability).
// Groups that coexist longer than max_overlap_s are never candidates (the association at common
// times has had its say on them). A gated pair is ambiguous when G₁ has another gated successor
// that coexists with G₂, or G₂ another gated predecessor that coexists with G₁ (in dense traffic
// the ambiguous fragments are left apart: a missed stitch splits a target, a wrong one joins two;
// a later successor that starts after G₂ ends is no rival, it may be the same target after G₂).
// Of the unambiguous pairs each group keeps its earliest successor and its latest predecessor, and
// a pair kept by both is a *stitch* (a mutual match, as in track-continuity tests at a handover
// between radars). Stitches are chained (G₁ → G₂ → G₃ is one target), and the later groups take
// the earliest group's target number. The tuples are unchanged; only `target` changes (filled
// when it was empty and a stitch was made). Complexity: O(G log G + C·D³) for G groups and C
// candidate pairs (a sweep over groups sorted by start time).
#pragma once

#include <cstdint>

#include "io/track_file.hpp"

namespace trackassoc {

struct TrackStitchOptions {
  bool enabled = true;
  double max_gap_s = 180.0;          // s, the longest gap bridged
  double max_overlap_s = 2.0;        // s, the overlap of a coasting end and its successor's start
  double manoeuvre_sigma = 3.0;      // σ_a [m/s²] of the allowance
  double gate_probability = 0.9999;  // of χ²_D
  void validate() const;
};

struct TrackStitchSummary {
  int32_t groups = 0, candidates = 0, stitches = 0;  // groups, gated pairs, and stitches made
};

// Joins the groups of `record` (its tuple columns are file.sensors, in order) as above; `file`
// gives the reports (the registered reports where registration applies).
TrackStitchSummary stitch_fragments(const TrackFile& file, AssociationRecord& record,
                                    const TrackStitchOptions& options);

}  // namespace trackassoc
