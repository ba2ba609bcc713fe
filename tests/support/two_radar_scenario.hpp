// A small hand-made scenario shared by the simulator's tests (test_simulation_errors.cpp,
// test_sensor_trackers.cpp): two targets on straight lines, two radars 60-100 km away with periods
// 2 s and 3 s, 60 s.
#pragma once

#include <numbers>
#include <string>

#include "kernels/core/scenario.hpp"

namespace trackassoc {

inline Scenario two_radar_scenario(const std::string& name) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  Scenario sc;
  sc.name = name;
  sc.duration = 60.0;
  TargetSpec a, b;
  a.id = 0;
  a.initial_state = {0, 0, 0, 200, 0, 0};
  b.id = 1;
  b.initial_state = {5000, 8000, 0, -100, 150, 0};
  sc.targets = {a, b};
  const double pos[2][2] = {{-60e3, 10e3}, {40e3, -90e3}};
  for (int s = 0; s < 2; ++s) {
    Sensor x;
    x.id = s;
    x.position = {pos[s][0], pos[s][1], 0};
    x.sigma_range = 50.0;
    x.sigma_bearing = 0.2 * kDeg;
    x.period = 2.0 + s;
    x.offset = 0.5;
    sc.sensors.push_back(x);
  }
  return sc;
}

}  // namespace trackassoc
