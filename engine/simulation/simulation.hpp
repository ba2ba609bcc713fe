// Scenario simulation and local tracking (docs/design.md §4.1).
//
// Targets move in 2-D or 3-D; each sensor measures range and bearing (and elevation) with
// Gaussian errors at its own period and offset, may miss detections, and adds clutter. Each
// sensor then runs its own filter bank to produce local tracks with converted-measurement
// covariances. Local track numbers are shuffled per sensor; truth ids are kept in the table.
// Random streams are keyed by (seed, run, sensor/target), so results do not depend on threads.
#pragma once

#include <cstdint>

#include "kernels/core/scenario.hpp"
#include "kernels/core/types.hpp"

namespace trackassoc {

struct SimulationResult {
  TruthTable truth;
  Measurements measurements;
  TrackTable tracks;
};

// Simulates Monte Carlo run `run` of `scenario` with master seed `seed`.
SimulationResult simulate(const Scenario& scenario, uint64_t seed, int run = 0);

}  // namespace trackassoc
