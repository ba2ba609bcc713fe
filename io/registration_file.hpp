// The sensor registration an association estimated (docs/design.md §4.10; engine/pipeline/
// registration_stage.hpp), schema v1 extension, readable with h5py without knowing C++:
//
//   /registration/           attrs reference_sensor (a /sensors id, held at zero), parameters
//                            (comma-separated names, in the order below), applied (1 when the
//                            association used the corrected reports, 0 when the reports were
//                            left as recorded: the estimate not significant, or immaterial, or
//                            the corrected reports linked no more tracks), rounds
//                            (associations run), wald, wald_dof (the Wald statistic of every
//                            estimate together and its degrees of freedom), observations (pair
//                            observations fitted), effect (the largest per-sensor effect δ of
//                            the correction, squared σ per scan, that decided whether it mattered;
//                            NaN when the Wald test was not significant; absent in older files),
//                            association (the /associations group it
//                            belongs to), options (JSON)
//     sensor        (S int32)      the /sensors ids, in /sensors order
//     <parameter>   (S float64)    one per parameter: range_bias [m], azimuth_bias [rad],
//                                  elevation_bias [rad] (3-D), site_offset_x/_y(/_z) [m] (the true
//                                  site minus /sensors/position), clock_offset [s] (reported minus
//                                  true time); 0 for the reference sensor
//     <parameter>_se (S float64)   its standard error (0 for the reference)
//     covariance    (S×k×k float64) each sensor's covariance of its k estimates, parameters in the
//                                  order of `parameters` (its diagonal is the squared _se; 0 for
//                                  the reference): what `fuse` widens the corrected covariances by.
//                                  Optional (absent in files written before it; then diag(_se²))
//     covariance_scale  (S×S float64)  per pair of sensors, the mean normalised squared residual
//                                      per coordinate of their paired reports after registration
//                                      (≈ 1 when the reported covariances are right; NaN: no pair)
//     pair_observations (S×S int64)    the observations behind it
// The group is optional; read_track_file() keeps it across a read-modify-write.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace trackassoc {

namespace h5 {
class Group;
}

struct RegistrationRecord {
  int32_t reference_sensor = 0;                  // a /sensors id
  std::vector<int32_t> sensor;                   // S, /sensors order
  std::vector<std::string> parameters;           // k names
  std::vector<double> estimate, standard_error;  // S×k, sensor-major
  std::vector<double> covariance;                // S×k×k, sensor-major; empty: not recorded
  std::vector<double> covariance_scale;          // S×S
  std::vector<int64_t> pair_observations;        // S×S
  bool applied = false;
  int32_t rounds = 0, wald_dof = 0;
  double wald = 0.0;
  double effect = std::numeric_limits<double>::quiet_NaN();  // step 3b's largest δ_s (NaN: not tested)
  int64_t observations = 0;
  std::string association;  // the /associations group
  // The association named reference_sensor (--reference-sensor, a sensor the user trusts); false:
  // the stage chose it. Stored in `options` (its reference_sensor >= 0), read from there.
  bool reference_named = false;
  std::string options_json = "{}";  // the stage's options (RegistrationStageOptions::to_json)
};

// Throws InputError (naming `file` and the dataset) when the record's shapes do not match S sensors.
void check_registration(const std::string& file, const RegistrationRecord& r, std::size_t sensors);
void write_registration(const h5::Group& root, const std::optional<RegistrationRecord>& r);
std::optional<RegistrationRecord> read_registration(const h5::Group& root, const std::string& file);

}  // namespace trackassoc
