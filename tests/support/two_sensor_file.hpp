// A track file of two sensors (ids 0 and 1, period 1 s) and an empty 2-D constant-velocity track
// table, for tests that add their reports by hand.
#pragma once

#include "io/track_file.hpp"

namespace trackassoc::testing_support {

inline TrackFile two_sensor_file() {
  TrackFile f;
  for (int32_t s = 0; s < 2; ++s) {
    Sensor sensor;
    sensor.id = s;
    sensor.period = 1.0;
    f.sensors.push_back(sensor);
  }
  f.tracks = TrackTable(StateLayout::kXY_VXVY);
  return f;
}

}  // namespace trackassoc::testing_support
