// `associate --solver siamese`: the Siamese BiLSTM (seed 003, TTCSN) on the local tracks of two
// sensors of a schema v1 track file (docs/design.md §3), written as an /associations/<name>/ record.
//
// Tracks. Each local track (sensor, /tracks/track) of the two sensors becomes one sequence of
// points (x, y, t), in time order. The points are (options key "points"):
//   - "track" (default): the /tracks position estimates (x, y) of its rows — what a recorded
//     track set has;
//   - "plot": the plot each row was updated with (the /measurements row of the same sensor, time
//     and target, converted to Cartesian) — the input the network was trained on (seed 003 §1:
//     the radars' plots). Needs /measurements and /tracks/truth (simulation output).
// Both come from engine/pipeline/fuzzy_pipeline.hpp's make_packets, so the two paths share one conversion.
// Times are taken relative to "time_origin" [s] (default 0): the model's input map is absolute in
// position and time (kernels/learning/siamese.hpp), so a scene must lie where the model was trained
// (the shipped model: the 100 × 100 km area, 0–50 s). Points outside the model's training domain
// are counted (points_outside_domain) so that the caller can warn.
//
// Association (engine/pipeline/siamese_pipeline.hpp): every track embedded once, all N1×N2 pairs scored
// by the head, then a LAP with the probability threshold p_min ("threshold", default 0.5).
//
// Record. Tuples have one column per /sensors entry (the other sensors' columns are −1). An
// associated pair is one tuple, with cost ln p_min − ln p ≤ 0 (its LAP cost); every local track of
// the two sensors not associated is a tuple of its own with cost 0, so every local track of the
// two sensors appears in exactly one tuple (as in engine/pipeline/pipeline.hpp). objective = Σ cost.
// A local track with no point (plot mode: never detected) is never associated.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/pipeline/fuzzy_pipeline.hpp"
#include "engine/pipeline/siamese_pipeline.hpp"
#include "engine/solvers/option_fields.hpp"
#include "io/track_file.hpp"

namespace trackassoc {

struct SiameseTrackFileOptions {
  std::vector<int32_t> sensors;                // two /sensors ids; empty = the first two
  PacketSource points = PacketSource::kTrack;  // "track" | "plot" (see the header comment)
  double time_origin = 0.0;                    // [s], subtracted from every time
  SiameseAssociationOptions association;       // threshold, batch_tracks
  void validate() const;                       // throws InputError naming the key
  nlohmann::json to_json() const;
};

// From the CLI's --options JSON. Keys (all optional): sensors [id, id], points ("track" | "plot"),
// threshold (p_min in (0, 1)), time_origin [s], batch_tracks. Unknown keys are an InputError.
SiameseTrackFileOptions siamese_track_file_options(const nlohmann::json& options);
// The keys above, declared once (engine/solvers/option_fields.hpp): read, write (to_json), help.
const OptionFields<SiameseTrackFileOptions>& siamese_track_file_option_fields();

struct SiameseTrackFileResult {
  AssociationRecord record;
  SiameseAssociationResult association;  // over the tracks that have points
  int32_t sensor_ids[2] = {0, 0};
  int32_t tracks[2] = {0, 0};         // local tracks of each sensor
  int64_t points = 0;                 // points fed to the network
  int64_t points_outside_domain = 0;  // of those, outside the model's training domain
};

// Does not modify `file`; the caller appends result.record (replacing a record of the same name).
SiameseTrackFileResult associate_siamese_tracks(const TrackFile& file, const SiameseModel<float>& model,
                                                const SiameseTrackFileOptions& options,
                                                const std::string& name);

// The model's training domain in normalised coordinates (kernels/learning/siamese.hpp TrackNormalisation):
// the seed 003 targets start in the area and fly up to 30 km out of it, so |x'|, |y'| ≤ 1.6, and
// plot times lie in [t0, t0 + T]: 0 ≤ t' ≤ 1, with a 5 % tolerance.
bool inside_training_domain(const TrackNormalisation& norm, double x, double y, double t);

}  // namespace trackassoc
