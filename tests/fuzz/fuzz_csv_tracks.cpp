// libFuzzer target: import_csv_tracks (io/csv_tracks.hpp) on arbitrary bytes. The first byte
// chooses the options (delimiter, geodetic or Cartesian columns, velocity and σ columns or not,
// a sensor list); the rest is the CSV text. InputError is the expected outcome for bad input; a
// crash, a sanitizer report, another exception or a hang is a bug. What imports must be a valid
// schema v1 file (the writer's checks, io/track_validation.hpp), and export csv → import csv
// must give the same /tracks bit for bit.
// Build and run: scripts/fuzz.sh fuzz_csv_tracks (seed corpus tests/fuzz/corpus/fuzz_csv_tracks/).
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "io/csv_tracks.hpp"
#include "io/track_validation.hpp"
#include "kernels/core/error.hpp"

namespace {

trackassoc::CsvImportOptions options_from(uint8_t choice) {
  trackassoc::CsvImportOptions o;
  const char delimiters[] = {',', ';', '\t', ','};
  o.delimiter = delimiters[choice & 3];
  auto& c = o.columns;
  c.time = "t";
  c.sensor = "sensor";
  c.track = "track";
  if (choice & 4) {
    c.lat = "lat";
    c.lon = "lon";
    if (choice & 8) c.alt = "alt";
  } else {
    c.x = "x";
    c.y = "y";
    if (choice & 8) c.z = "z";
  }
  if (choice & 16) {
    c.vx = "vx";
    c.vy = "vy";
    if (choice & 8) c.vz = "vz";
  }
  if (choice & 32) c.sigma = {{"x", "sx"}, {"y", "sy"}};
  if (choice & 64) c.truth = "truth";
  if (choice & 128) o.sensors = {0, 1, 2};
  o.sigma_position = trackassoc::parse_per_sensor_value("5,1:20", "--sigma-pos");
  o.sigma_velocity = trackassoc::parse_per_sensor_value("2", "--sigma-vel");
  o.period = trackassoc::parse_per_sensor_value("0:1", "--period");
  return o;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const trackassoc::CsvImportOptions o = options_from(data[0]);
  std::istringstream in(std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
  trackassoc::TrackFile file;
  try {
    file = trackassoc::import_csv_tracks(in, "<fuzz>", o);
  } catch (const trackassoc::InputError&) {
    return 0;
  }
  try {
    trackassoc::track_validation::check_sensors("<fuzz>", file.sensors);
    trackassoc::track_validation::check_tracks("<fuzz>", file.tracks, file.sensors);
    trackassoc::track_validation::check_recording_info("<fuzz>", file.recording);
    std::ostringstream out;
    trackassoc::export_csv_tracks(file, out);
    trackassoc::CsvImportOptions back;
    back.columns = trackassoc::csv_export_mapping(file.tracks.layout);
    back.sensors = o.sensors;
    back.period = trackassoc::parse_per_sensor_value("1", "--period");
    std::istringstream again(out.str());
    const trackassoc::TrackFile copy = trackassoc::import_csv_tracks(again, "<round trip>", back);
    if (copy.tracks.t != file.tracks.t || copy.tracks.state != file.tracks.state ||
        copy.tracks.cov != file.tracks.cov || copy.tracks.sensor != file.tracks.sensor ||
        copy.tracks.track != file.tracks.track || copy.tracks.truth != file.tracks.truth)
      __builtin_trap();
  } catch (const trackassoc::InputError&) {
    __builtin_trap();  // what was imported must be a valid file, and export csv must read back
  }
  return 0;
}
