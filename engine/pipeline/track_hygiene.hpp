// Track hygiene (docs/design.md §4.10): a recorded (sensor, track) key is not always one track. A sensor
// that recycles its track numbers reuses a number after the track ends, so one key stops, pauses
// and jumps to where the track's own motion cannot take it. Such keys are split here before the
// association, each piece a new local track.
//
// Rule, per key, its rows in time order: a gap is two consecutive reports more than
// max(min_gap_s, gap_factor × the key's median report interval) apart. At a gap, the state before
// it, x₀ (P₀), is predicted over the gap Δt by constant velocity with a manoeuvre allowance:
// x̂ = F x₀, P̂ = F P₀ Fᵀ + Q, Q the continuous white-noise acceleration model of spectral density
// σ_a² (per axis: Δt³/3, Δt²/2, Δt times σ_a²; Bar-Shalom, Li, Kirubarajan 2001 §6.2.2), and
// compared with the first report after it, x₁ (P₁): m² = (x₁ − x̂)ᵀ (P̂ + P₁)⁻¹ (x₁ − x̂). The
// key is cut there when m² > χ²_D(gate_probability): the jump is one its own motion cannot explain.
// The rows after a cut get a new track number (one above the sensor's largest, in order of cuts
// by sensor, key and time), and TrackFile::source_track keeps the recorded number of every row.
// A key without gaps, or whose gaps its motion explains, is left as it is.
//
// Swaps at crossings: two local tracks of one sensor whose targets pass close to each other may
// exchange targets (track swap, or track coalescence followed by a swap; Blackman & Popoli 1999
// §9.5), so each key follows one target and then the other. Their reports show it as a pair of
// jumps at one scan that the other key explains: for keys A and B of one sensor, with consecutive
// reports a₀ → a₁ and b₀ → b₁ whose intervals overlap in time, the own continuations
// m²(a₀ → a₁) + m²(b₀ → b₁) (the statistic above, with the same allowance) exceed χ²_2D(p) while the
// crossed ones m²(a₀ → b₁) + m²(b₀ → a₁) stay within it and below the own sum. Only reports whose
// own continuation exceeds χ²_D(jump_probability) are candidates (a jump), so the test is
// O(jumps × concurrent jumps). A candidate pair is taken in order of the crossed sum, each report
// transition at most once; both keys are cut there (their rows from a₁ and b₁ on get new
// numbers), and the association's segment pass (engine/pipeline/track_segments.hpp) joins each
// piece to the target it follows. A manoeuvre or a lagging tracker makes a key jump alone, with
// no partner that explains it, so it is not cut. Swaps are cut before recycled numbers.
// Complexity: O(rows · (log rows + D³) + jumps · concurrent jumps · D³), rows in parallel.
#pragma once

#include <cstdint>
#include <vector>

#include "io/track_file.hpp"

namespace trackassoc {

struct TrackSplitOptions {
  bool enabled = true;
  double min_gap_s = 10.0;           // s, shorter pauses are never cut
  double gap_factor = 3.0;           // a gap is longer than this many median report intervals
  double manoeuvre_sigma = 3.0;      // σ_a [m/s²] of the allowance
  double gate_probability = 0.9999;  // of χ²_D (recycled numbers) and χ²_2D (swaps)
  bool swaps = true;                 // split swaps at crossings too
  double jump_probability = 0.99;    // a swap candidate's own continuation exceeds χ²_D of it
  void validate() const;
};

struct TrackSplitSummary {
  int32_t gaps = 0, cuts = 0;  // recycled numbers: gaps tested, and cut
  int32_t swaps = 0;           // swaps: pairs of keys cut where they exchanged targets
  bool any() const { return cuts > 0 || swaps > 0; }
};

// m² of report `after` against report `before` predicted to its time by constant velocity with
// the allowance q = σ_a² (the rule above; `after` may be earlier than `before` by a short overlap,
// the prediction then runs backwards with the same Q). Fragment stitching uses it too
// (engine/pipeline/track_stitching.hpp).
double continuation_statistic(const TrackTable& tracks, std::size_t before, std::size_t after, double q);

// Splits the recycled keys of file.tracks in place and fills file.source_track (when any key is
// cut; left as it was otherwise). Returns what it did.
TrackSplitSummary split_recycled_tracks(TrackFile& file, const TrackSplitOptions& options);

// Splits the keys of file.tracks that swapped targets at a crossing (the rule above), in place,
// and fills file.source_track when any key is cut. Returns the number of swaps (pairs of keys cut).
int32_t split_swapped_tracks(TrackFile& file, const TrackSplitOptions& options);

// Both, as the default association does it: swaps (when options.swaps), then recycled numbers.
TrackSplitSummary split_tracks(TrackFile& file, const TrackSplitOptions& options);

}  // namespace trackassoc
