// Experiment `recorded` (docs/design.md §5; issue 20 item 7): the default association on the engine's
// realistic-recording family, side by side with Stone Soup on the same files.
//
// Each scenario of the family (data/scenarios/recorded_*.json: asynchronous radars, targets some
// sensors never see, partial track lifetimes, false tracks, turns and acceleration steps, 2- and
// 10-minute recordings, a dense and a formation case, 3 to 5 sensors; and, issue 29, registration
// errors (range, azimuth, elevation biases, a site-survey error, clock offsets; recorded_bias,
// _bias_dense, _bias_3d, _site, _clock), mis-stated covariances (_covscale), recycled track numbers
// (_recycled), swaps at crossings (_swaps), local trackers that differ per sensor (_trackers) and
// all of them at once (_mixed)) is simulated `runs` times;
// each run's track file is kept in `files_dir` (schema v1, readable with h5py) and associated by:
//   default      `trackassoc associate` with no flags: every sensor, the sparse S-D pipeline, the
//                calibrated gate, all-pairs cost, lr+ls (engine/pipeline/sparse_sd_pipeline.hpp),
//                with the joint registration stage (engine/pipeline/registration_stage.hpp), on the
//                file with its recycled track numbers split (engine/pipeline/track_hygiene.hpp; it
//                is scored on the split keys, so its target count may exceed the others');
//   unregistered the same without the registration stage (`associate --no-registration`);
//   exact        the same pipeline with the exact S-D solver per component;
//   chi2-sum     the same pipeline with the seed 000 gate (χ²(n·D) on the summed statistic) and
//                forward alignment: what the gate was before issue 20;
//   3d-exact     three-sensor scenarios only: the dense all-pairs 3-D tensor (seed 000 Eq. 3 with
//                the λ_ik term) with the calibrated gate, solved by the exact branch and bound;
//   3d-nogate    the same tensor with the gate off on the summed statistic, exact (the
//                reference rate for the dense and formation cases).
// and, when `peer` is on, by Stone Soup's OneToOneTrackAssociator and TrackToTrackCounting,
// pairwise chained (bench/stonesoup_t2t.py, run with Debian's Python): as shipped
// (stonesoup-one2one, stonesoup-counting: states compared only at timestamps two tracks share, so
// nothing is linked on asynchronous files) and resampled (stonesoup-one2one-resampled,
// stonesoup-counting-resampled: every track first predicted onto a common grid with Stone Soup's
// KalmanPredictor and a CV model, bench/stonesoup_resample.py). Every method is scored on the
// decoded tuples it writes, by the rule of `trackassoc evaluate` (engine/pipeline/metrics.hpp).
// Times: ours = the pipeline from the loaded file to the tuples; the peer's = its association
// calls, plus the predictions for the resampled rows (its Track objects' construction reported
// apart).
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace trackassoc {

struct RecordedExperimentOptions {
  std::vector<std::string> scenarios{"recorded_sync",      "recorded_3s",    "recorded_3s_long",
                                     "recorded_4s",        "recorded_5s",    "recorded_dense",
                                     "recorded_formation", "recorded_bias",  "recorded_bias_dense",
                                     "recorded_site",      "recorded_clock", "recorded_covscale",
                                     "recorded_recycled",  "recorded_swaps", "recorded_bias_3d",
                                     "recorded_trackers",  "recorded_mixed"};
  std::vector<std::string> methods{"default", "unregistered", "exact", "chi2-sum", "3d-exact", "3d-nogate"};
  int32_t runs = 3;
  std::string files_dir = "experiment-recorded-files";  // the simulated track files, kept for peers
  bool peer = true;         // run Stone Soup (skipped with a note when it cannot be imported)
  std::string peer_script;  // bench/stonesoup_t2t.py (the CLI fills in the repo's copy)
  std::string python = "/usr/bin/python3";
  uint64_t seed = 1;
  std::string output = "experiment-recorded.h5";
  std::string plot = "experiment-recorded.svg";
  void validate() const;
};

struct RecordedRow {
  std::string scenario, method;
  int32_t run = 0, sensors = 0;
  int32_t targets = 0, correct = 0, false_associations = 0, missed = 0;  // targets tracked by ≥ 2 sensors
  int32_t linked_tuples = 0, false_tuples = 0;
  double time_s = 0.0;  // association time (see the header)
};

std::vector<RecordedRow> run_recorded_experiment(const RecordedExperimentOptions& options,
                                                 std::ostream* progress);
std::string recorded_summary_table(const std::vector<RecordedRow>& rows,
                                   const RecordedExperimentOptions& options);
void write_recorded_outputs(const std::vector<RecordedRow>& rows, const RecordedExperimentOptions& options);

}  // namespace trackassoc
