// Validation of the in-memory content of a schema v1 track file (io/track_file.hpp).
//
// The same checks run in the reader (on what it loaded) and in the writer (before each section
// is written), so the engine never writes a file its own reader would refuse. Each check throws
// InputError "FILE: /dataset: row R: what was expected, found what".
#pragma once

#include <string>
#include <vector>

#include "io/track_file.hpp"

namespace trackassoc::track_validation {

// A valid HDF5 link name for /associations/<name>, /metrics/<name> and table names:
// non-empty, no '/', not "." (and, for readability in h5py, no control characters).
void check_object_name(const std::string& file, const std::string& group, const std::string& name);

// Ids unique; positions finite; σ, period, clutter rate, reliability finite and >= 0; offset
// finite; p_detect in [0, 1].
void check_sensors(const std::string& file, const std::vector<Sensor>& sensors);

// Column lengths agree; every sensor is a /sensors id; track >= 0; t, state finite; every
// covariance finite, symmetric by construction (packed) and positive definite (Cholesky);
// truth >= -1; no two rows with the same (sensor, track, t). A sensor with zero tracks is valid.
void check_tracks(const std::string& file, const TrackTable& tracks, const std::vector<Sensor>& sensors);

// frame "" or "ENU" (or "NED"); frame_origin, when given, a latitude in [-90, 90], a longitude
// in [-180, 360] and a finite height; frame_origin only with a frame.
void check_recording_info(const std::string& file, const RecordingInfo& info);

void check_truth(const std::string& file, const TruthTable& truth);
void check_measurements(const std::string& file, const Measurements& m, const std::vector<Sensor>& sensors);

// For a tracker run on /measurements (`trackassoc filter`): every sensor that reports measurements
// has σ_range > 0 and σ_bearing > 0 (and σ_elevation > 0 when `three_d`), the measurement noise of
// its filters; a σ of 0 would give singular track covariances.
void check_measurement_noise(const std::string& file, const Measurements& m,
                             const std::vector<Sensor>& sensors, bool three_d);

// tuples K×S with S = number of sensors and K = number of costs; every entry is -1 or a local
// track number that sensor reports in /tracks; energy is rows×cols.
void check_association(const std::string& file, const AssociationRecord& a,
                       const std::vector<Sensor>& sensors, const TrackTable& tracks);
void check_metrics(const std::string& file, const MetricsRecord& m);

// Positive definiteness of a packed upper-triangular D×D matrix; empty string when it is, the
// reason otherwise ("diagonal element (2,2) = -1 is not positive", "Cholesky pivot 3 = -0.5").
std::string positive_definite_failure(const double* packed, int d);

}  // namespace trackassoc::track_validation
