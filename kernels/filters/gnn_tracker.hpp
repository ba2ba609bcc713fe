// Global nearest neighbour (GNN) tracker for unlabeled 2-D position plots (issue 17 item 2), after
// MATLAB's trackerGNN (Sensor Fusion and Tracking Toolbox) and Blackman & Popoli, "Design and
// Analysis of Modern Tracking Systems", 1999, §6.3 (GNN) and §6.2 (track initiation by M-of-N).
//
// Algorithm, one scan at time t with plots z_1..z_M (already in the world frame):
//   1. Clustering (extended targets, Granström et al., "Extended object tracking", 2017 §3): the
//      plots are grouped by single linkage, two plots closer than cluster_distance being in one
//      cluster (DBSCAN with min_pts = 1); each cluster's centroid is one measurement with
//      covariance R = σ² I (σ = measurement_sigma: the spread of the centroid over the hull, not
//      shrunk by the number of plots, whose errors are not independent).
//   2. Prediction of every track to t with the CV model (kernels/filters/kalman_bank.hpp:
//      kinematic_transition, kinematic_process_noise).
//   3. Gating and assignment: d² = νᵀ S⁻¹ ν with ν = z − H x̂, S = H P Hᵀ + R (Bar-Shalom et al. 2001,
//      Eq. 5.2.3-13); a pair is allowed when d² ≤ χ²₂(gate_probability); the tracks × measurements
//      matrix of d² (+inf outside the gate) is solved by the Jonker–Volgenant LAP
//      (kernels/assignment/lap.hpp) with a row or column left unassigned at half the gate each, so every
//      gated pair that does not conflict with a cheaper one is assigned.
//   4. Update of the assigned tracks (Kalman update), coasting of the others.
//   5. Track management (trackerGNN's history logic):
//      - every unassigned measurement outside the gates of the confirmed tracks (or every one, with
//        initiate_in_gate) starts a tentative track at the measured position, velocity 0 with σ
//        initial_speed_sigma per axis;
//      - a tentative track is confirmed when it has confirm_hits (M) hits within its first
//        confirm_window (N) scans; it is deleted as soon as it can no longer reach M in N;
//      - a confirmed track is deleted after delete_misses (K) consecutive misses.
//   Confirmed tracks are numbered 0, 1, 2, ... in the order they are confirmed (ties: the order of
//   the tracks' creation), so numbers are deterministic and dense.
// Output: after each scan, one row (track number, t, x, y, vx, vy, packed P) per confirmed track
// alive after the scan, updated or coasted.
//
// Complexity per scan: O(M²) for the clustering, O(T·C) for gating and O(max(T, C)³) for the LAP,
// with T tracks and C clusters (tens in a harbour scene).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "kernels/assignment/lap_sparse.hpp"

namespace trackassoc {

struct GnnTrackerOptions {
  double measurement_sigma = 2.0;    // σ of a measurement (cluster centroid) per axis [m]
  double process_noise = 0.5;        // σ of the CV model's white-noise acceleration [m/s²]
  double initial_speed_sigma = 5.0;  // σ of a new track's velocity per axis [m/s]
  double gate_probability = 0.999;   // χ² gate on the 2-D innovation: 13.82 (trackerGNN: 0.999 too)
  double cluster_distance = 5.0;     // single-linkage distance between plots of one target [m]
  int confirm_hits = 2;              // M of M-of-N confirmation (trackerGNN default [2 3])
  int confirm_window = 3;            // N
  int delete_misses = 5;             // K consecutive misses delete a confirmed track (trackerGNN 5)
  // true (default, trackerGNN's rule): every unassigned measurement starts a tentative track.
  // false: one inside the gate of a confirmed track starts none. An extended target gives several
  // clusters in a scan when its returns have gaps; the one not assigned lies in its track's gate
  // and would start a duplicate track of the same target (Blackman & Popoli 1999 §6.2: initiate
  // from the measurements no track can use). The price: a second target that stays inside a
  // confirmed track's gate gets no track of its own until it leaves it.
  bool initiate_in_gate = true;
  // The scan's gated track × measurement LAP goes to the sparse solver when it is large and sparse
  // (kernels/assignment/lap_sparse.hpp; many targets far apart); lap.max_density = 0: always dense.
  GatedLapOptions lap;
  void validate() const;  // throws InputError naming the field
};

struct GnnScanSummary {
  int32_t plots = 0, clusters = 0;  // input plots and the measurements they formed
  int32_t assigned = 0;             // measurements assigned to existing tracks
  int32_t started = 0;              // tentative tracks started
  int32_t confirmed = 0;            // tracks confirmed in this scan
  int32_t deleted = 0;              // tracks deleted in this scan (tentative or confirmed)
};

// One output row of a confirmed track.
struct GnnTrackRow {
  int32_t track = 0;  // confirmation number
  double t = 0.0;
  Eigen::Vector4d x;  // x, y, vx, vy
  Eigen::Matrix4d P;
};

// Single-linkage clusters of the plots (x[i], y[i]): cluster index per plot, clusters numbered in
// the order of their first plot. Exposed for tests.
std::vector<int32_t> single_linkage_clusters(std::span<const double> x, std::span<const double> y,
                                             double distance);

class GnnTracker {
 public:
  explicit GnnTracker(const GnnTrackerOptions& options);  // validates
  // Processes one scan at time t (non-decreasing across calls) with plots (x[i], y[i]) in the
  // world frame; appends the confirmed tracks' rows to `rows`.
  GnnScanSummary step(double t, std::span<const double> x, std::span<const double> y,
                      std::vector<GnnTrackRow>& rows);
  int32_t confirmed_count() const { return next_number_; }  // tracks ever confirmed
  std::size_t live_tracks() const { return tracks_.size(); }

 private:
  struct Track {
    Eigen::Vector4d x;
    Eigen::Matrix4d P;
    int32_t number = -1;  // confirmation number; -1 while tentative
    int32_t scans = 0;    // scans since creation, the creating one included
    int32_t hits = 0;     // hits in those scans
    int32_t misses = 0;   // consecutive misses
  };
  GnnTrackerOptions options_;
  double gate_ = 0.0;
  double last_t_ = 0.0;
  bool started_ = false;
  int32_t next_number_ = 0;
  std::vector<Track> tracks_;  // in creation order
};

}  // namespace trackassoc
