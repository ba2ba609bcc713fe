// Recorded track files in CSV, to and from schema v1 (io/track_file.hpp, docs/design.md §3 and §4.8).
//
// Import (`trackassoc import csv`): one row per report, a header row naming the columns, and a
// mapping from the fields of /tracks to column names (exact, case-sensitive). The file is read
// line by line (streamed: memory is the /tracks columns, not the text), every mapped field is
// parsed with std::from_chars, and every bad value is reported with its line (1-based, the header
// is line 1) and its column name:
//   - a field that is not a number, NaN or ±inf, an empty or missing field, an extra field;
//   - an id that is not an integer (sensor, track >= 0, truth >= -1), a latitude outside
//     [-90, 90] or a longitude outside [-180, 360], a σ <= 0, a covariance that is not positive
//     definite (Cholesky, io/track_validation.hpp);
//   - a time before the previous report of the same (sensor, track) (time going backwards), or
//     equal to it (a duplicate (sensor, track, t));
//   - a sensor that is not in the list the user gave (CsvImportOptions::sensors).
// A line longer than kMaxCsvLineBytes (1 MiB) is refused naming its number, before it is held
// whole; a NUL byte or a UTF-16 byte-order mark is refused as "not UTF-8 text (UTF-16? save as
// UTF-8 CSV)". Every preview of the file's text in a message is escaped (printable_text).
// Nothing is returned when there is an error: an InputError lists up to `max_errors` of them
// ("FILE: line 5, column 'x': expected a number, found 'abc'; ...").
//
// Position: x, y[, z] as given (metres in the user's frame), or geodetic lat, lon[, alt]
// (degrees, degrees, metres above the WGS-84 ellipsoid) converted to east, north[, up] of the
// local tangent plane (ENU, kernels/core/geodetic.hpp) at the origin the user gives, or at the first
// report of the file; the frame and its origin are stored in RecordingInfo. Without alt, the
// layout is 2-D (east, north; every height = the origin's).
// Velocity: columns vx, vy[, vz] (m/s, in the position's frame: east, north, up for geodetic
// input), or, when none is mapped, estimated per local track by the three-point Lagrange
// derivative over the track's reports sorted by time (non-uniform spacing; exact for constant
// acceleration), one-sided two-point differences at the track's first and last report, and 0 for a
// track of one report.
// Covariance: D(D+1)/2 packed upper-triangle columns in state-layout order (docs/design.md §3); or a
// diagonal from σ columns per component and, for a component without one, the per-sensor σ flags
// (sigma_position for x, y, z and sigma_velocity for vx, vy, vz). The σ assumed per sensor are
// stated in RecordingInfo::import_json ("assumed_sigma").
// Sensors: every sensor id of the file (ascending) or the given list (in its order) becomes a
// /sensors row. Its period is the given one or the median of the intervals between consecutive
// reports of its tracks, rounded to 1 µs; the fields a track file does not carry (position, σ of
// the measurements, offset, p_detect, clutter rate) are placeholders (0, p_detect 1), named in
// RecordingInfo::sensors_unknown.
// Cost: O(rows) to read, O(rows log rows) for the velocity estimate and the writer's checks.
//
// Export (`trackassoc export csv`): the /tracks table, header "sensor,track,t,<state
// layout>,cov_<r>_<c> ...,truth", numbers in the shortest text that reads back to the same
// double (std::to_chars), so that export then import gives the same /tracks bit for bit.
#pragma once

#include <array>
#include <cstdint>
#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "io/track_file.hpp"

namespace trackassoc {

// Which CSV column holds each field of /tracks; "" = not in the file. The mapping JSON has the
// same keys: {"time": "t", "sensor": "radar", "track": "id", "x": "east", "y": "north",
// "cov": ["c00", ...], "sigma": {"x": "sx", "vx": "svx"}, "truth": "target"}.
struct CsvColumnMapping {
  std::string time, sensor, track, truth;
  std::string x, y, z;                       // Cartesian position [m]
  std::string lat, lon, alt;                 // geodetic position [deg, deg, m]
  std::string vx, vy, vz;                    // velocity [m/s]
  std::vector<std::string> cov;              // packed upper triangle, D(D+1)/2 names
  std::map<std::string, std::string> sigma;  // state component ("x", ..., "vz") -> σ column
  bool geodetic() const { return !lat.empty() || !lon.empty() || !alt.empty(); }
  bool three_d() const { return !z.empty() || !alt.empty(); }
  friend bool operator==(const CsvColumnMapping&, const CsvColumnMapping&) = default;
};

// The mapping JSON (keys as CsvColumnMapping). Unknown keys, values of the wrong type and
// duplicate keys are InputErrors naming the key; `source` names the file in messages.
CsvColumnMapping parse_csv_mapping(const std::string& json_text, const std::string& source);
std::string csv_mapping_to_json(const CsvColumnMapping& m);
// `KEY=COLUMN` (a --column flag) into `m`; cov takes a comma-separated list, sigma.KEY a σ column.
void set_csv_mapping_entry(CsvColumnMapping& m, const std::string& key_equals_column);

// A value given for every sensor and/or per sensor: "5", "1:5,2:20" or "10,1:5" (10 for the
// others). Per-sensor wins over the default.
struct PerSensorValue {
  std::optional<double> all;
  std::map<int32_t, double> by_sensor;
  std::optional<double> for_sensor(int32_t id) const;
  bool empty() const { return !all && by_sensor.empty(); }
};
// Parses the text of flag `flag`; every value must be > 0 and finite.
PerSensorValue parse_per_sensor_value(const std::string& text, const std::string& flag);

struct CsvImportOptions {
  CsvColumnMapping columns;
  char delimiter = ',';                         // ',', ';' or '\t'
  std::optional<std::array<double, 3>> origin;  // lat [deg], lon [deg], alt [m]; default the first report
  PerSensorValue sigma_position;                // [m], for the position components without σ
  PerSensorValue sigma_velocity;                // [m/s], for the velocity components without σ
  PerSensorValue period;                        // [s]; default estimated from the reports
  std::vector<int32_t> sensors;                 // the known sensor ids; empty = every id in the file
  std::size_t max_errors = 20;                  // errors listed in the message (all are counted)
  // Throws InputError naming the bad field: required columns (time, sensor, track, a position),
  // x,y[,z] or lat,lon[,alt] not both, vx,vy[,vz] all or none, cov with D(D+1)/2 names and not
  // with sigma, sigma keys that are state components, delimiter, origin, duplicate sensors.
  void validate() const;
};

// The longest CSV line `import csv` reads [bytes] (a header of 1000 columns of 30 characters is 31 KB).
inline constexpr std::size_t kMaxCsvLineBytes = std::size_t{1} << 20;

struct CsvImportSummary {
  std::size_t rows = 0, tracks = 0;
  std::string velocity;    // "columns" or "estimated (three-point derivative)"
  std::string covariance;  // "columns", "sigma columns", "sigma columns and assumed", "assumed"
};

// Reads a CSV from `in`; `source` names it in messages. Throws InputError on any bad value or
// mapping (nothing is returned).
TrackFile import_csv_tracks(std::istream& in, const std::string& source, const CsvImportOptions& options,
                            CsvImportSummary* summary = nullptr);
// The same from a file (an InputError if it cannot be read).
TrackFile import_csv_tracks_file(const std::string& path, const CsvImportOptions& options,
                                 CsvImportSummary* summary = nullptr);

// The /tracks table of `file` as CSV; the mapping that reads it back.
void export_csv_tracks(const TrackFile& file, std::ostream& out, char delimiter = ',');
CsvColumnMapping csv_export_mapping(StateLayout layout);
// export_csv_tracks to `path`, atomically (io/atomic_file.hpp).
void write_csv_tracks(const std::string& path, const TrackFile& file, char delimiter = ',');

// The mapping JSON file `path` (named by option `flag` in messages).
CsvColumnMapping read_csv_mapping_file(const std::string& path, const std::string& flag);
// "LAT,LON[,ALT]" (degrees, degrees, metres; ALT default 0) of option `flag`.
std::array<double, 3> parse_geodetic_origin(const std::string& text, const std::string& flag);

// "," ";" "tab" (or a literal tab) to the delimiter character; an InputError naming `flag` otherwise.
char parse_csv_delimiter(const std::string& text, const std::string& flag);

// A sensor's scan period from the intervals between consecutive reports of its tracks: their
// median, rounded to 1 µs (recorded times rarely carry more; the rounding makes 4 s from 1.7 + 4k
// exact again); 0 when there is none. Reorders `intervals`. (`import csv`, the Python module.)
double median_interval(std::vector<double>& intervals);

}  // namespace trackassoc
