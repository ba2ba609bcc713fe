// Registered reports (docs/design.md §4.10): a file's reports corrected by a registration estimate,
// and the estimate a /registration record holds. The registration stage of the association
// (engine/pipeline/registration_stage.hpp, step 4) corrects with them, and so does `fuse`
// (engine/fusion/track_fuser.hpp) with the record the association wrote. The model and its
// Jacobian J_s are kernels/registration/registration.hpp's; the record, io/registration_file.hpp's.
#pragma once

#include <string>

#include "io/registration_file.hpp"
#include "io/track_file.hpp"
#include "kernels/registration/registration.hpp"

namespace trackassoc {

// The frame the corrected reports are put in. The registration is relative: only the sensors'
// biases against each other are observable.
enum class RegistrationFrame {
  kReference,  // the reference sensor's (its reports unchanged): what the association compares
  // The sensors' information-weighted average: each report x of sensor s is moved by
  // J_s(x)·b_s − (Σ_u W_u)⁻¹ Σ_u W_u J_u(x)·b_u, W_u the information of one plot of sensor u at x
  // (σ_range along its line of sight, range·σ_bearing across; the reference's b is 0), and its
  // velocity rotated back by Δθ_s − mean Δθ. This is the frame the fusion of the reports as
  // recorded lives in: radars seeing a target from different sites fix its position by their
  // ranges, so their large cross-range (azimuth) offsets weigh little there. In the reference
  // sensor's frame instead, the reference's own azimuth bias is imposed on every sensor: on
  // recorded_bias the fused RMSE goes from 277-301 m (as recorded) to 1288-1516 m (reference
  // frame) and 750-826 m (unweighted mean). What `fuse` estimates in.
  kCentroid,
};

// `file` with every report of every sensor corrected by `estimate` and its position covariance
// widened by the estimate's uncertainty (see the header), in `frame`.
TrackFile registered_file(const TrackFile& file, const RegistrationEstimate& estimate,
                          const RegistrationOptions& model,
                          RegistrationFrame frame = RegistrationFrame::kReference);

// The estimate and model a /registration record holds, as the stage used them: rows in /sensors
// order (matched by id), the model read off the parameter names, each sensor's covariance block
// (diag(se²) when the record has none), so registered_file(file, estimate, model) repeats the
// stage's correction (`fuse` corrects with it). InputError (naming `path`, the dataset, expected
// and found) when the record does not fit the file: a /sensors id without a row, a reference
// outside /sensors, parameters no model of the stage has in the file's dimension.
struct RecordedRegistration {
  RegistrationEstimate estimate;
  RegistrationOptions model;
};
RecordedRegistration recorded_registration(const TrackFile& file, const std::string& path,
                                           const RegistrationRecord& record);

}  // namespace trackassoc
