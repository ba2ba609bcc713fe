// trackassoc import csv --input t.csv --mapping m.json --output F.h5: a recorded track file from
// CSV into schema v1; trackassoc export csv --input F.h5 --output t.csv: the /tracks table back
// to CSV (io/csv_tracks.hpp has the rules).
#include <fstream>
#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/pipeline/result_tables.hpp"
#include "io/csv_tracks.hpp"

namespace trackassoc::cli {

void register_import(CLI::App& app) {
  struct Args {
    CommonOptions common;
    std::string input, output, mapping, delimiter = ",", origin, sigma_pos, sigma_vel, period;
    std::vector<std::string> columns;
    std::vector<int32_t> sensors;
    std::size_t max_errors = 20;
  };
  auto args = std::make_shared<Args>();
  auto* import = app.add_subcommand("import", "Import a recorded track file into schema v1 (HDF5)");
  import->require_subcommand(1);
  auto* cmd = import->add_subcommand(
      "csv",
      "A CSV track file (one row per report, a header row, columns named by --mapping/--column) to "
      "schema v1. Geodetic lat/lon[/alt] (WGS-84, degrees) becomes ENU [m] around --origin or the first "
      "report (/tracks attrs frame, frame_origin_*). Without velocity columns, the velocity is estimated "
      "per track by the three-point derivative (non-uniform times; one-sided at the ends, 0 for one "
      "report). Covariance from packed upper-triangle columns (cov), σ columns (sigma.x ...) or the "
      "--sigma-pos/--sigma-vel flags (stated in /tracks attr import). Each bad value is named by line "
      "and column; exit 2 and nothing written. A line may hold at most 1 MiB (" +
          std::to_string(kMaxCsvLineBytes) + " bytes); a longer one is refused naming its number.");
  cmd->add_option("--input,-i", args->input, "CSV file")->required();
  cmd->add_option("--output,-o", args->output, "Output HDF5 file")->required();
  cmd->add_option(
      "--mapping,-m", args->mapping,
      "Mapping JSON: {\"time\": COL, \"sensor\": COL, \"track\": COL, \"x\"/\"y\"[/\"z\"] or "
      "\"lat\"/\"lon\"[/\"alt\"], optional \"vx\"/\"vy\"[/\"vz\"], \"cov\": [packed upper triangle "
      "in state order], \"sigma\": {\"x\": COL, ...}, \"truth\": COL}");
  cmd->add_option("--column,-c", args->columns,
                  "KEY=COLUMN, over the mapping (repeatable): time=t, x=east, cov=c0,c1,..., sigma.vx=svx");
  cmd->add_option("--delimiter", args->delimiter, "Field delimiter: ',', ';' or tab")->capture_default_str();
  cmd->add_option("--origin", args->origin,
                  "ENU origin LAT,LON[,ALT] (degrees, WGS-84; metres) for geodetic input (default: the first "
                  "report)");
  cmd->add_option(
      "--sigma-pos", args->sigma_pos,
      "Position σ [m] where the file has no covariance: V for every sensor, or S:V,S:V, or V,S:V");
  cmd->add_option("--sigma-vel", args->sigma_vel,
                  "Velocity σ [m/s] where the file has none (as --sigma-pos)");
  cmd->add_option("--period", args->period,
                  "Scan period [s] per sensor (as --sigma-pos; default: the median interval between a "
                  "sensor's reports, to 1 µs)");
  cmd->add_option("--sensors", args->sensors,
                  "The sensor ids of the recording, in /sensors order; a row of another sensor is an error "
                  "(default: every id of the file, ascending)");
  cmd->add_option("--max-errors", args->max_errors, "Bad values listed in the message")
      ->check(in_range(1, 1e6))
      ->capture_default_str();
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    check_output_paths({{args->output, "--output"}},
                       {{args->input, "--input"}, {args->mapping, "--mapping"}});
    check_input_file(args->input, "--input", "CSV track file");
    CsvImportOptions o;
    if (!args->mapping.empty()) o.columns = read_csv_mapping_file(args->mapping, "--mapping");
    for (const std::string& c : args->columns) set_csv_mapping_entry(o.columns, c);
    o.delimiter = parse_csv_delimiter(args->delimiter, "--delimiter");
    if (!args->origin.empty()) o.origin = parse_geodetic_origin(args->origin, "--origin");
    if (!args->sigma_pos.empty()) o.sigma_position = parse_per_sensor_value(args->sigma_pos, "--sigma-pos");
    if (!args->sigma_vel.empty()) o.sigma_velocity = parse_per_sensor_value(args->sigma_vel, "--sigma-vel");
    if (!args->period.empty()) o.period = parse_per_sensor_value(args->period, "--period");
    o.sensors = args->sensors;
    o.max_errors = args->max_errors;
    CsvImportSummary summary;
    const TrackFile file = import_csv_tracks_file(args->input, o, &summary);
    write_track_file(args->output, file);
    std::cout << "imported " << summary.rows << " reports of " << summary.tracks << " tracks from "
              << file.sensors.size() << " sensors (" << layout_name(file.tracks.layout)
              << (file.recording.frame.empty() ? "" : ", " + file.recording.frame) << "; velocity "
              << summary.velocity << "; covariance " << summary.covariance << ") -> " << args->output << "\n";
  });
}

void register_export(CLI::App& app) {
  struct Args {
    CommonOptions common;
    std::string input, output, mapping_output, delimiter = ",", what = "tracks", name;
  };
  auto args = std::make_shared<Args>();
  auto* exp = app.add_subcommand("export", "Export the tracks or results of a schema v1 file");
  exp->require_subcommand(1);
  auto* cmd = exp->add_subcommand(
      "csv",
      "A table of the file as CSV, one row per fact, numbers in the shortest text that reads back exactly "
      "(pandas.read_csv, MATLAB readtable). --what tracks (default): /tracks, sensor, track, t, the state "
      "columns, the packed upper-triangle covariance cov_R_C, truth, so `import csv` with --mapping-output's "
      "mapping gives the same /tracks; associations: target, tuple, sensor, track, source_track, cost, one "
      "row per member of a tuple; unassociated: sensor, track, source_track, first_t, last_t, reports, the "
      "local tracks in no tuple of two or more; fused: /fused/NAME, tuple, t, state, cov_R_C, sources, "
      "truth; registration: /registration, one row per sensor, one column per dataset (NAME_0.. for S x k, "
      "NAME_0_0.. for S x k x k)");
  cmd->add_option("--input,-i", args->input, "HDF5 file (schema v1)")->required();
  cmd->add_option("--output,-o", args->output, "Output CSV file")->required();
  cmd->add_option("--what", args->what, "The table: " + enum_name_list<ResultTable>())
      ->check(enum_choices<ResultTable>())
      ->capture_default_str();
  cmd->add_option("--name", args->name,
                  "--what associations|unassociated|fused: the /associations or /fused group (default: the "
                  "file's only one)");
  cmd->add_option("--mapping-output", args->mapping_output,
                  "--what tracks: also write the mapping JSON for `import csv`");
  cmd->add_option("--delimiter", args->delimiter, "Field delimiter: ',', ';' or tab")->capture_default_str();
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    const ResultTable what = parse_enum<ResultTable>(args->what, "--what");
    if (what != ResultTable::kTracks && !args->mapping_output.empty())
      throw InputError("--mapping-output: the import mapping is of --what tracks only");
    check_output_paths({{args->output, "--output"}, {args->mapping_output, "--mapping-output"}},
                       {{args->input, "--input"}});
    const char delimiter = parse_csv_delimiter(args->delimiter, "--delimiter");
    const TrackFile file = read_track_file(args->input);
    const ResultTableSummary s =
        write_result_table(args->output, args->input, file, what, args->name, delimiter);
    if (!args->mapping_output.empty())
      write_atomically(args->mapping_output, [&](const std::string& tmp) {
        std::ofstream(tmp) << csv_mapping_to_json(csv_export_mapping(file.tracks.layout)) << "\n";
      });
    std::cout << "exported " << s.rows << (what == ResultTable::kTracks ? " reports" : " rows") << " of "
              << s.group << " -> " << args->output
              << (args->mapping_output.empty() ? "" : " (mapping " + args->mapping_output + ")") << "\n";
    for (const std::string& skipped : s.skipped)
      std::cout << "  not exported: /registration/" << skipped << "\n";
  });
}

}  // namespace trackassoc::cli
