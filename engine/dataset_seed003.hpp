// The seed 003 (TTCSN) simulation and pair data set (seed 003 §3.1).
//
// Paper: a 100 × 100 km area; targets with random initial position, speed 300–600 m/s and heading;
// "every second the target state, heading and speed, changes at random within kinematically
// reasonable bounds"; 50 s of flight; two radars with 100 m / 1° errors and scan periods 4 s and 6 s;
// 10 000 targets; 10 000 positive pairs, 10 000 random negative pairs and 6 695 "close but
// different" negative pairs, shuffled and split 70/30.
//
// What the paper leaves out, and what we chose (all in Seed003Options, written into the file):
// - Manoeuvres: the simulator's MotionModel::kRandomManoeuvre (engine/simulation_truth.hpp) with a
//   1 s manoeuvre period: at every whole second n = 0..49 the heading changes by U(−Δψ, Δψ) and the
//   speed by U(−Δv, Δv), clipped to [300, 600] m/s, and the target flies the constant acceleration
//   that takes it to the new velocity within the second (position and velocity continuous, truth
//   exact at any plot time). Δψ = 0.1 rad (at 600 m/s a mean lateral acceleration of 60 m/s² ≈ 6 g),
//   Δv = 20 m/s (2 g). This fits the paper's "changes every second within kinematic limits".
// - Radars: radar 1 at (0, 0), radar 2 at (100 km, 0), the two southern corners of the area;
//   Gaussian range (σ = 100 m) and bearing (σ = 1°) errors; plots converted to Cartesian (x, y).
// - Asynchrony: each radar sees each target at its own scan phase φ ~ U[0, period), so the plot
//   times are φ + k·period within [0, 50] s: 12–13 plots from radar 1, 8–9 from radar 2.
// - The tracks the network sees are these sequences of converted plots (x, y, t), one per radar per
//   target (no filtering, no time alignment: the point of seed 003).
// - Close negatives: radar-1 track of target i with the radar-2 track of the target j ≠ i whose true
//   trajectory is nearest to i's in mean distance over the 51 whole seconds, when that mean is below
//   close_distance (3 km, about 2.5 σ of the 1° bearing error at 70 km); candidates come from a grid
//   on the positions at t = 25 s. Targets are visited in a random order until 6 695 are found.
// - Random negatives: i uniform, j uniform ≠ i.
// Every random draw comes from CounterRng(seed, target or purpose, stream), so the data set does not
// depend on the thread count.
#pragma once

#include <cstdint>
#include <string>

#include "io/siamese_dataset_file.hpp"

namespace trackassoc {

// How "close" is measured for a close negative (see the header comment).
enum class CloseMeasure { kMeanDistance, kStartDistance };

struct Seed003Options {
  int targets = 10000;
  double area = 100000.0;                                                      // side of the square area [m]
  double speed_min = 300.0, speed_max = 600.0;                                 // [m/s]
  double duration = 50.0;                                                      // [s]
  double max_heading_change = 0.1;                                             // Δψ per second [rad]
  double max_speed_change = 20.0;                                              // Δv per second [m/s]
  double radar1_x = 0.0, radar1_y = 0.0, radar2_x = 100000.0, radar2_y = 0.0;  // [m]
  double sigma_range = 100.0;                                                  // [m]
  double sigma_bearing_deg = 1.0;                                              // [deg]
  double period1 = 4.0, period2 = 6.0;                                         // scan periods [s]
  int positives = 10000;                                                       // ≤ targets
  int random_negatives = 10000;
  int close_negatives = 6695;
  double close_distance = 3000.0;  // [m], distance below which a different target is "close"
  CloseMeasure close_measure = CloseMeasure::kMeanDistance;
  double train_fraction = 0.7;
  uint64_t seed = 3;
  void validate() const;  // throws InputError naming the field
  std::string to_json() const;
};

// The two radars' tracks of `count` targets of Monte Carlo run `run` (one scene of the density
// experiment; count replaces options.targets). target1/target2 give each track's target id; the
// tracks are in target order.
struct Seed003Scene {
  TrackSequences radar1, radar2;
  std::vector<int32_t> target1, target2;
};
Seed003Scene simulate_seed003_scene(const Seed003Options& options, int count, uint64_t run);

// The full pair data set (seed 003 §3.1). Counts shortfalls (fewer close pairs than requested)
// are reported in generator_json ("close_negatives_found").
Seed003Dataset generate_seed003_dataset(const Seed003Options& options);

}  // namespace trackassoc
