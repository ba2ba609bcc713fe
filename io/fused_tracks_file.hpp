// Fused tracks of an association (`trackassoc fuse`, engine/fusion/track_fuser.hpp), schema v1
// extension. One group per fusion run:
//
//   /fused/<name>/            attrs association (the /associations/<association> it fuses), rule
//                             ("naive" | "bsc" | "ci"), ci_criterion ("trace" | "det"; "" unless ci),
//                             cross_covariance ("none" | "common-process-noise" | "correlation"),
//                             options (JSON), state_layout (as /tracks)
//     tuples  (K×S int32)     the association's tuples when it was fused (a copy: a reader refuses
//                             the group when /associations/<association>/tuples has changed since)
//     tuple   (N int32)       the row of `tuples` each fused estimate belongs to
//     t       (N float64)     time [s]
//     state   (N×D float64)   fused state, columns as state_layout
//     cov     (N×D(D+1)/2)    fused covariance, packed upper triangle, row-major (as /tracks/cov)
//     sources (N int32)       the number of local tracks fused at that time (≥ 2)
//     truth   (N int32)       the target of the tuple: its members' common /tracks/truth, −1 when they
//                             differ or are unknown
//     omega   (N×S float64)   ci only: the weight of each sensor column (0 for absent members; a row
//                             sums to 1)
//   optional, written by `trackassoc evaluate` when /truth exists:
//     attrs position_rmse (fused, m), position_rmse_rows; datasets sensor_position_rmse (S, m, NaN
//     where a sensor has no member rows) and sensor_position_rmse_rows (S int32): the RMSE of the
//     members' own reports at the fused times (the same targets over the same times).
//
// Rows are ordered by tuple, then time (strictly increasing within a tuple). Readers need no C++:
// h5py reads every dataset directly. The group is optional; read_track_file() keeps it across a
// read-modify-write (io/track_file.hpp TrackFile::fused), and a command that replaces an
// association drops the fused groups of it.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "kernels/core/types.hpp"

namespace trackassoc {

namespace h5 {
class Group;
}
struct AssociationRecord;  // io/track_file.hpp

struct FusedTrackRecord {
  std::string name;         // group name under /fused
  std::string association;  // the /associations group fused
  std::string rule;         // "naive", "bsc" or "ci"
  std::string ci_criterion;
  std::string cross_covariance = "none";
  std::string options_json = "{}";
  StateLayout layout = StateLayout::kXY_VXVY;
  int32_t num_sensors = 0;      // S
  std::vector<int32_t> tuples;  // K×S row-major, the association's tuples
  std::vector<int32_t> tuple, sources, truth;
  std::vector<double> t;
  std::vector<std::vector<double>> state;  // [D][N]
  std::vector<std::vector<double>> cov;    // [D(D+1)/2][N]
  std::vector<double> omega;               // N×S row-major (ci), empty otherwise
  // Evaluation against /truth (NaN / empty = not evaluated).
  double position_rmse = std::numeric_limits<double>::quiet_NaN();
  int32_t position_rmse_rows = 0;
  std::vector<double> sensor_position_rmse;
  std::vector<int32_t> sensor_position_rmse_rows;
  std::size_t size() const { return t.size(); }
  std::size_t num_tuples() const { return num_sensors ? tuples.size() / num_sensors : 0; }
};

// Checks names, the layout (that of /tracks), shapes, finiteness, positive-definite covariances, row order,
// that the association exists with the same tuples, and the ranges of sources, truth and omega. Throws
// InputError naming `file`, the dataset and the row.
void check_fused_tracks(const std::string& file, const FusedTrackRecord& r,
                        const std::vector<Sensor>& sensors,
                        const std::vector<AssociationRecord>& associations, StateLayout tracks_layout);

// Writes /fused/<name>/ for every record under `root` (nothing when `records` is empty).
void write_fused_tracks(const h5::Group& root, const std::vector<FusedTrackRecord>& records);

// Reads every /fused/<name>/ group (empty when /fused is absent).
std::vector<FusedTrackRecord> read_fused_tracks(const h5::Group& root, const std::string& file);

}  // namespace trackassoc
