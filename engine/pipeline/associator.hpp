// One association interface for every path of `associate` and `run` (issue 16 item 1), after
// Stone Soup's TrackToTrackAssociator.associate_tracks(*track_sets): the track sets in (a schema v1
// TrackFile and the pipeline and solver choice); the tuples with their costs, the summary and the
// local tracks left unassociated out.
//
// choose_association_plan (engine/pipeline/association_plan.hpp) picks the stages of a request —
// front end, pair source, partition, component solver — and the plan's path is the implementation
// that runs them (engine/pipeline/associators.cpp, each a thin wrapper of its problem builder and
// solve):
//   sparse S-D   candidate index → components → S-D tensor (engine/pipeline/sparse_sd_pipeline.hpp):
//                the default, for its solvers (sparse_sd_solver_names: lr+ls, lr, exact) without
//                --sd, --3d or --sparse, whatever the number of --sensors
//   dense S-D    all pairs → the whole problem → S-D tensor (pipeline_sd.hpp): --sd, or chnn-pseudo;
//                also a solver of no other rule with two or more than three --sensors, which this
//                path then refuses as it is not an S-D solver (require_sd_solver)
//   dense 3-D    all pairs → the whole problem → 3-D tensor (pipeline.hpp): a 3-D solver
//                (engine/solvers/solver_registry.hpp) on the file's three sensors or three
//                --sensors; --3d for a default-path solver
//   sparse 3-D   candidate index → components → 3-D tensor (sparse_pipeline.hpp): --sparse
//   fusion       engine/pipeline/fuzzy_pipeline.hpp: seed 001's fusion centre (fuzzy, ftaa); side
//                output: the system tracks (/system_tracks/<name>/)
//   siamese      engine/pipeline/siamese_track_file.hpp: seed 003's Siamese BiLSTM on two sensors
// A new component solver of an existing kind is one file and one line of the solver registry; a
// new combination of stages is one implementation plus its row in implementations()
// (engine/pipeline/association_plan.cpp).
//
// Unassociated tracks (Stone Soup #1170): every path puts each local track of the sensors it
// associates in exactly one tuple, a track it linked to no other sensor's track being a tuple of
// one — except the segments that the sparse S-D path joins to a target
// (engine/pipeline/track_segments.hpp), which may appear in several tuples of one target number. A
// local track of an associated sensor is unassociated when no tuple with two or more members holds
// it and no target of two or more tracks does (it is alone in its tuple, or in none).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "engine/distributed/communicator.hpp"
#include "engine/pipeline/association_plan.hpp"
#include "engine/pipeline/pipeline.hpp"
#include "engine/pipeline/registration_stage.hpp"
#include "engine/pipeline/sparse_pipeline.hpp"
#include "engine/pipeline/track_hygiene.hpp"
#include "engine/pipeline/track_segments.hpp"
#include "engine/pipeline/track_stitching.hpp"
#include "io/track_file.hpp"

namespace trackassoc {

// The request: solver, pipeline choice and options. Defaults are those of `associate`.
struct AssociatorOptions {
  std::string solver = "lr+ls";  // an S-D solver, a 3-D solver (solver_registry), fuzzy, ftaa or siamese
  bool sd = false;               // --sd: the dense S-D formulation
  bool three_d = false;          // --3d: the three-sensor tensor for any 3-D solver
  bool sparse = false;           // --sparse: the three-sensor sparse path
  PipelineOptions pipeline;      // sensors (empty = the path's default), grid, alignment, gate, cost
  nlohmann::json solver_options = nlohmann::json::object();  // the solver's own options (--options)
  uint64_t seed = 1;
  std::string name;           // /associations group; empty = the solver name
  std::string siamese_model;  // --solver siamese: model file (io/siamese_model_file.hpp)
  // The sparse paths (the default and --sparse): the candidate bound's widening (≥ 1,
  // kernels/statistics/scan_candidates.hpp), and the largest dense sub-tensor of a component,
  // Π(n_s + 1) entries: the default path solves a larger component by sequential LAP merging,
  // --sparse refuses it (SparseSDOptions, SparsePipelineOptions).
  double radius_scale = 1.0;
  std::size_t max_component_entries = std::size_t{1} << 24;
  // The default (sparse S-D) path: the exponent κ ≥ 0 of the rival-weighted link cost
  // (SparseSDOptions::rival_exponent, engine/pipeline/sparse_sd_pipeline.hpp; docs/design.md §4.9);
  // 0 = every gated pair against the gate itself.
  double rival_exponent = 2.0;
  // The default (sparse S-D) path: a coexisting pair outside the gate forbids a tuple only when it
  // fails the family-wise gate too (SparseSDOptions::family_wise_veto; docs/design.md §4.3).
  bool family_wise_veto = true;
  // --sparse: the cost of a missing index in a component's sub-tensor (+inf: padded, every track
  // assigned; finite: the solvers' dummy index; engine/pipeline/sparse_pipeline.hpp). ≥ 0.
  float miss_cost = std::numeric_limits<float>::infinity();
  SegmentOptions segments;  // the default (sparse S-D) path: track segments joined to targets
  // The default (sparse S-D) path: joint registration and association (engine/pipeline/
  // registration_stage.hpp); over MPI ranks every re-association is sharded as the first.
  RegistrationStageOptions registration;
  // The default (sparse S-D) path: recycled track numbers split before the association
  // (split_recorded_keys below, engine/pipeline/track_hygiene.hpp); the CLI's --no-split.
  TrackSplitOptions split;
  // The default (sparse S-D) path: groups that never coexist joined when one continues the other
  // (engine/pipeline/track_stitching.hpp); the CLI's --no-stitch.
  TrackStitchOptions stitching;
  // The default (sparse S-D) path and --sparse: the MPI ranks that share its components (rank 0's
  // call; the others run serve_sd_components, engine/pipeline/sparse_sd_components.hpp, or
  // serve_sparse_components, engine/pipeline/sparse_pipeline.hpp). Null: this process.
  distributed::Communicator* ranks = nullptr;
  // Throws InputError when more than one of sd, three_d, sparse is set, solver_options is not a
  // JSON object, or radius_scale, max_component_entries, rival_exponent or miss_cost is out of its
  // range.
  void validate() const;
};

struct UnassociatedTracks {
  int32_t sensor_id = 0;        // a /sensors id
  std::vector<int32_t> tracks;  // its /tracks/track numbers in no tuple of two or more, ascending
};

// What an association did, typed, after ceres::Solver::Summary: the result, the stage times, the
// counts of each stage, and the termination. Every path fills path, solver, sensor_ids, the result
// and runtime_s; the rest is filled by the paths that have it (the comments say which), and is
// zero or empty otherwise. BriefReport() is one line, FullReport() that line and one line per
// stage result (what `associate` prints).
struct AssociationSummary {
  AssociationPath path = AssociationPath::kSparseSD;
  std::string solver;
  std::vector<int32_t> sensor_ids;    // the sensors associated, in the path's order
  std::vector<int32_t> track_counts;  // the problem's local tracks per sensor (3-D and S-D paths)
  int32_t file_sensors = 0;           // the file's /sensors (the tuples' columns)
  // The result (the record's): tuples, objective, Lagrangian lower bound (NaN: none), relative gap
  // and termination.
  int64_t tuples = 0;
  double objective = 0.0, lower_bound = 0.0, gap = 0.0;
  std::string termination;
  // The record's run time: every stage's (the solve alone when `run` shares one problem among
  // solvers, make_three_sensor_associator); the fusion centre's wall time for fuzzy/FTAA.
  double runtime_s = 0.0;
  // The tensor paths' stages (engine/pipeline/stage_report.hpp). Sparse: alignment, candidates,
  // statistics, components, solve; sparse S-D then segments, stitching and registration (the kept
  // association's stages, and the stage's own time). Dense (--3d, --sd): alignment, statistics,
  // tensor, solve.
  std::vector<StageReport> stages;
  // The tensor paths: the partition's components (1: a dense path's whole problem), the pair
  // source's candidate pairs (the index's, found at the scans it searched, before its count filter
  // and the gate: kernels/statistics/scan_candidates.hpp; a dense path's every pair) and those
  // in the gate. Sparse S-D: the components solved by LAP merging.
  int32_t components = 0;
  int64_t candidate_pairs = 0, gated_pairs = 0, fallback_components = 0;
  // Sparse S-D: components solved over their listed tuples (engine/pipeline/sparse_sd_tuples.hpp),
  // the largest list, the largest per-component relative duality gap and the components above 1 %.
  int64_t listed_components = 0, largest_listed_tuples = 0, components_above_1pct_gap = 0;
  double largest_component_gap = 0.0;
  std::optional<SegmentSummary> segments;  // sparse S-D with segments: the segment pass (track_segments.hpp)
  TrackStitchSummary stitching;  // sparse S-D: groups that never coexist, joined (track_stitching.hpp)
  // Sparse S-D with registration, when fitted: the estimate (AssociationOutcome::registration's copy).
  std::optional<RegistrationRecord> registration;
  // Sparse S-D: recycled track numbers split before the association. split_recorded_keys runs on
  // the file before the associator does, so its caller sets this (split = split_recorded_keys(...)).
  TrackSplitSummary split;
  std::vector<int32_t> empty_sensors;  // sparse S-D: chosen sensors without local tracks (column -1)
  // The tensor paths: sensors whose reports read as independent errors, aligned without the lag
  // terms (engine/pipeline/front_end.hpp).
  std::vector<UnfilteredSensor> unfiltered_sensors;
  std::vector<int64_t> unassociated;  // per sensor_ids: local tracks in no tuple of two or more
  int64_t local_tracks = 0, packets = 0, system_tracks = 0;  // fusion centre
  int64_t points = 0, points_outside_domain = 0;             // siamese

  // "associated <what> with '<solver>': <result>, <n> tuples (<termination>), <t> ms".
  std::string BriefReport() const;
  // BriefReport(), then a line per stage result: the sparse S-D stages and counts, the empty
  // sensors, the sensors with independent errors, the registration (and a line per sensor), the
  // unassociated local tracks, the split.
  // Every line ends in '\n'.
  std::string FullReport() const;
};

struct AssociationOutcome {
  AssociationRecord record;  // /associations/<name>/: tuples, cost, objective, bound, termination
  AssociationSummary summary;
  std::vector<UnassociatedTracks> unassociated;    // one entry per associated sensor, in summary order
  std::optional<SystemTrackRecord> system_tracks;  // fusion centre: /system_tracks/<name>/
  std::optional<RegistrationRecord> registration;  // the default path: /registration
};

class TrackAssociator {
 public:
  virtual ~TrackAssociator() = default;
  virtual AssociationPath path() const = 0;
  // Associates the local tracks of `file` (validated, schema v1). Throws InputError on input the
  // path cannot take (too few sensors, a tensor over the memory budget, ...).
  virtual AssociationOutcome associate(const TrackFile& file) const = 0;
};

// choose_association_plan(options).path(): the implementation of the stages `associate` runs for
// `options` (engine/pipeline/association_plan.hpp). Validates the request and the solver name
// before any file is read.
AssociationPath choose_association_path(const AssociatorOptions& options);

// The associator of choose_association_path(options); parses the solver's options and, for
// siamese, reads the model, so that bad input fails before the track file is read.
std::unique_ptr<TrackAssociator> make_associator(const AssociatorOptions& options);
// The associator of a given path (run: its default rows are the sparse S-D path for any sensors).
std::unique_ptr<TrackAssociator> make_associator(AssociationPath path, const AssociatorOptions& options);

// A three-sensor problem built once and shared by the associators of several solvers (run: every
// 3-D solver on one tensor). Exactly one of the two is set; the record's runtime_s is then the
// solve alone, as solve_association's and solve_sparse_association's.
struct PreparedThreeSensorProblem {
  std::shared_ptr<const AssociationProblem> dense;
  std::shared_ptr<const SparseAssociationProblem> sparse;
};
std::unique_ptr<TrackAssociator> make_three_sensor_associator(const AssociatorOptions& options,
                                                              PreparedThreeSensorProblem prepared);

// Track hygiene before the association, the same for `associate`, the Python module and the studies:
// on the default (sparse S-D) path with options.split.enabled, the recorded keys of `file` that are
// really two tracks (a recycled number) are split in place (split_recycled_tracks); other paths
// and a disabled split leave `file` as it is. Call it on the file the association's output stores.
TrackSplitSummary split_recorded_keys(TrackFile& file, const AssociatorOptions& options);

// The local tracks of the sensors `sensor_ids` in no tuple of `rec` with two or more members.
std::vector<UnassociatedTracks> unassociated_tracks(const TrackFile& file,
                                                    const std::vector<int32_t>& sensor_ids,
                                                    const AssociationRecord& rec);

// Adds the outcome's association (and system tracks, and registration) to `file`, replacing those of
// the same name.
void store_outcome(TrackFile& file, const AssociationOutcome& outcome);

}  // namespace trackassoc
