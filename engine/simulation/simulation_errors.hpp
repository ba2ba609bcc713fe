// What a real sensor adds to its reports beyond noise (docs/design.md §4.10): the model of
// Scenario::sensor_errors (kernels/core/scenario.hpp), one SensorErrors per sensor.
//
// Registration errors act on the plots (engine/simulation/simulation.cpp, simulate_sensor):
//   a plot reported at time t (the sensor's scan time) is of the target's true position at
//   t − clock_offset, seen from the true site position + site_offset; then
//     range     = ρ + range_bias + σ_r·n_r,
//     bearing   = θ + azimuth_bias + σ_θ·n_θ,
//     elevation = φ + elevation_bias + σ_φ·n_φ  (3-D),
//   with (ρ, θ, φ) the true polar coordinates from the true site. The local tracker converts the
//   plots about the surveyed site (/sensors/position), as a real one does: so the site offset is
//   a translation of every report, the range bias a shift along the line of sight, the azimuth
//   bias a rotation about the surveyed site, and the clock offset a shift along the velocity.
//   The truth of the injected errors is the scenario JSON (the file's root attribute "scenario").
// Reported tracks (apply_sensor_errors, after the recording model):
//   covariance_scale  every reported covariance of the sensor is multiplied by it (the estimates
//                     are the tracker's own);
//   swap_distance     local tracks of the sensor whose targets come closer than this swap targets
//                     at their closest approach t_c: the rows of the two keys after t_c exchange
//                     their track numbers (so each key follows one target, then the other). Only
//                     approaches with at least kSwapMargin rows of both tracks before and after
//                     t_c count; pairs are taken in order of t_c, and each track swaps at most once;
//   recycle_after     track numbers are given anew in order of the tracks' first reports: a track
//                     takes the smallest number whose last track ended at least recycle_after
//                     earlier, else a new one (what a radar that recycles its numbers does). A key
//                     may so hold two tracks of different targets, a gap and a jump apart.
// None of this draws a random number, and all zero (scale 1) leaves the output unchanged.
#pragma once

#include <vector>

#include "engine/simulation/simulation_truth.hpp"
#include "kernels/core/scenario.hpp"
#include "kernels/core/types.hpp"

namespace trackassoc {

inline constexpr int kSwapMargin = 3;

// Sensor s's errors (the defaults when the scenario has none).
const SensorErrors& sensor_errors_of(const Scenario& scenario, std::size_t s);

// Throws InputError unless sensor_errors is empty or has one entry per sensor with valid values.
void validate_sensor_errors(const Scenario& scenario);

// The sensor as it really is: its position moved by the site offset.
Sensor true_site(const Sensor& surveyed, const SensorErrors& errors);

// Covariance scale, swaps, recycled numbers, in that order; `targets` give the truth of the swaps.
void apply_sensor_errors(const Scenario& scenario, const std::vector<TargetTrajectory>& targets,
                         TrackTable& tracks);

}  // namespace trackassoc
