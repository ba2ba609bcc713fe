// The results of a track file as CSV tables (`trackassoc export csv --what ...`, issue 32): one
// row per output fact, a header row, numbers in the shortest text that reads back to the same
// double (std::to_chars, as the /tracks export), for pandas.read_csv and MATLAB's readtable.
//
//   tracks        /tracks (io/csv_tracks.hpp: export_csv_tracks), the default
//   associations  one row per member of a tuple: target, tuple, sensor, track, source_track, cost
//                 (target: /associations/<name>/target, or the tuple's index without one;
//                 source_track: /tracks/source_track of the track's first report when the file
//                 has it, else the track number)
//   unassociated  one row per local track in no tuple of two or more: sensor, track, source_track,
//                 first_t, last_t, reports (the stored /associations/<name>/unassociated rows, or
//                 worked out from the tuples for files written before those)
//   fused         /fused/<name>, one row per fused time: tuple, t, the state columns, cov_R_C, sources, truth
//   registration  /registration, one row per sensor (/sensors order): sensor, then one column per
//                 numeric dataset with one entry per sensor, a 2-D S x k dataset as k columns
//                 NAME_0..NAME_{k-1}, a 3-D S x k x m one (each sensor's covariance) as k·m
//                 columns NAME_j_l; datasets of another first dimension and the group's
//                 attributes are not rows of this table and are left out (listed in the summary)
#pragma once

#include <iosfwd>
#include <span>
#include <string>
#include <vector>

#include "io/track_file.hpp"
#include "kernels/core/enum_names.hpp"

namespace trackassoc {

enum class ResultTable { kTracks, kAssociations, kUnassociated, kFused, kRegistration };
inline constexpr EnumName<ResultTable> kResultTableNames[]{{ResultTable::kTracks, "tracks"},
                                                           {ResultTable::kAssociations, "associations"},
                                                           {ResultTable::kUnassociated, "unassociated"},
                                                           {ResultTable::kFused, "fused"},
                                                           {ResultTable::kRegistration, "registration"}};
constexpr std::span<const EnumName<ResultTable>> enum_names(ResultTable) { return kResultTableNames; }

struct ResultTableSummary {
  std::size_t rows = 0;
  std::string group;                 // the group exported ("/associations/lr+ls", "/tracks", ...)
  std::vector<std::string> skipped;  // registration: datasets left out, with why
};

// Writes table `what` of `file` (read from `path`, which the extra datasets /tracks/source_track
// and /registration are read from) to `out`. `name` picks the /associations or /fused group
// (empty: the file's only one). Throws InputError naming the file and group when it is absent.
ResultTableSummary export_result_table(const std::string& path, const TrackFile& file, ResultTable what,
                                       const std::string& name, std::ostream& out, char delimiter = ',');

// The same, written to `output` atomically.
ResultTableSummary write_result_table(const std::string& output, const std::string& path,
                                      const TrackFile& file, ResultTable what, const std::string& name,
                                      char delimiter = ',');

}  // namespace trackassoc
