// Reader of the Autoferry maritime sensor fusion benchmark (NTNU milliAmpere, Trondheim 2021, CC0;
// Helgesen et al., "Heterogeneous multi-sensor tracking for an autonomous surface vehicle in a
// littoral environment", Ocean Engineering 252, 2022). Format: README.upstream.md of the data set.
//
// A scenario folder `scenarioN/` holds scenarioN_detections.json and scenarioN_groundTruth.json:
//   detections: an array of scans {sensorID (1 lidar, 2 radar, 3 IR, 4 EO), ownshipPosition
//     [north, east] in the Piren NED frame [m], time [Unix s], measurement}; measurement is, for
//     lidar/radar, a 2×M matrix [[n_1..n_M], [e_1..e_M]] of plots relative to the ownship in
//     NED axes (MATLAB writes M = 1 as [n, e] and M = 0 as []), and for EO/IR 1×M bearings [rad]
//     (a number when M = 1);
//   ground truth: one array per detection entry of {targetID, position [n, e, d] in Piren NED,
//     time [Unix s]} (GNSS, repeated from entry to entry).
// Here everything is taken into the Piren NED frame: x = north, y = east [m], lidar/radar plots by
// adding the ownship position (the plots are in NED axes centred on the ownship, so no rotation).
// Times are seconds since the scenario's first detection entry (t0_unix kept). The truth becomes
// one row per distinct (target, time) with velocity by central differences of the GNSS fixes
// (one-sided at the ends, 0 for a target with one fix).
// Validation: a missing file, invalid JSON, a missing or mistyped field, a sensorID outside 1..4,
// a non-finite number, a matrix of the wrong shape, or a sensor's time going backwards is an
// InputError naming the file, the entry (0-based) and the field.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/core/types.hpp"

namespace trackassoc {

inline constexpr int32_t kAutoferryLidar = 1, kAutoferryRadar = 2, kAutoferryIR = 3, kAutoferryEO = 4;
// The 9 scenarios of the data set.
inline constexpr std::array<int, 9> kAutoferryScenarios{2, 3, 4, 5, 6, 13, 16, 17, 22};
// The Piren NED origin (README.upstream.md): latitude, longitude [deg], height [m].
inline constexpr std::array<double, 3> kPirenOrigin{63.4389029083, 10.39908278, 39.923};

struct AutoferryScan {
  int32_t sensor = 0;               // 1 lidar, 2 radar, 3 IR, 4 EO
  double t = 0.0;                   // [s] since the first entry
  std::array<double, 2> ownship{};  // north, east in Piren NED [m]
  std::vector<double> north, east;  // lidar/radar plots relative to the ownship (NED axes) [m]
  std::vector<double> bearing;      // EO/IR bearings [rad]
};

struct AutoferryScenario {
  int number = 0;
  double t0_unix = 0.0;              // Unix time of the first detection entry
  std::vector<AutoferryScan> scans;  // file order
  TruthTable truth;                  // target (1 Havfruen, 2 Gunnerus or the jet boat), t, x=n, y=e, vx, vy
};

// The folder of scenario `number` under the data set root (ROOT/scenarioN).
std::string autoferry_scenario_dir(const std::string& root, int number);

// Reads scenario `number` from `root` (the folder holding scenario2/, ...). Throws InputError.
AutoferryScenario read_autoferry_scenario(const std::string& root, int number);
// The two files read_autoferry_scenario reads: detections, ground truth.
std::array<std::string, 2> autoferry_input_files(const std::string& root, int number);

// The parsers behind it, on JSON text (`source` names the file in messages).
std::vector<AutoferryScan> parse_autoferry_detections(const std::string& text, const std::string& source,
                                                      double& t0_unix);
TruthTable parse_autoferry_truth(const std::string& text, const std::string& source, double t0_unix);

}  // namespace trackassoc
