// System tracks of a sequential fusion centre (seed 001 fuzzy association, FTAA), schema v1
// extension. One group per association run, named like its /associations/<name>/ group:
//
//   /system_tracks/<name>/          attrs method ("fuzzy" | "ftaa"), options (JSON), state_layout
//                                   ("x,y,vx,vy")
//     track   (N int32)             system track number of each fused estimate
//     t       (N float64)           time of the packet that produced it [s]
//     state   (N×4 float64)         fused state after that packet, row-major
//     mapping/                      the local-to-system mapping, one row per (local track, system
//       sensor, local_track,        track) pair that received packets: the /sensors id, the
//       system_track, packets       /tracks/track number, the system track, the packet count
//       (M int32 each)
//
// Rows are in the order the fusion centre processed them (time order). Readers need no C++: h5py
// reads every dataset directly. The group is optional; read_track_file() keeps it across a
// read-modify-write (io/track_file.hpp TrackFile::system_tracks).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/core/types.hpp"

namespace trackassoc {

namespace h5 {
class Group;
}

struct SystemTrackRecord {
  std::string name;    // group name under /system_tracks
  std::string method;  // "fuzzy" or "ftaa"
  std::string options_json = "{}";
  std::vector<int32_t> track;
  std::vector<double> t;
  std::array<std::vector<double>, 4> state;  // x, y, vx, vy columns
  std::vector<int32_t> map_sensor, map_local_track, map_system_track, map_packets;
  std::size_t size() const { return t.size(); }
  std::size_t mapping_size() const { return map_sensor.size(); }
};

// Checks lengths, finiteness, and that mapping sensors are /sensors ids. Throws InputError naming
// `file`, the dataset and the row.
void check_system_tracks(const std::string& file, const SystemTrackRecord& r,
                         const std::vector<Sensor>& sensors);

// Writes /system_tracks/<name>/ for every record under `root` (nothing when `records` is empty).
void write_system_tracks(const h5::Group& root, const std::vector<SystemTrackRecord>& records);

// Reads every /system_tracks/<name>/ group (empty when /system_tracks is absent).
std::vector<SystemTrackRecord> read_system_tracks(const h5::Group& root);

}  // namespace trackassoc
