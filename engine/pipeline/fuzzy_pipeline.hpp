// The seed 001 fusion-centre pipeline (docs/design.md §4.6): local tracks → packets → sequential fuzzy
// association (kernels/fuzzy/fuzzy_association.hpp) or the FTAA baseline (kernels/fuzzy/ftaa.hpp) → system
// tracks, the local-to-system mapping and an /associations/<name>/ record.
//
// Packets. The paper's packets carry one plot of a local track (seed 001 §2: position, track
// number, time, reliability). Two sources:
//   - track (default): each /tracks row's position estimate (x, y), for recorded track sets;
//   - plot: the measurement each /tracks row was updated with (the /measurements row of the same
//     sensor, time and target), converted to Cartesian (kernels/filters/kalman_converted.hpp). Needs
//     /measurements and /tracks/truth; a row whose target was not detected at that scan has no
//     new plot and sends no packet.
// `packet_period` > 0 thins each local track to one packet per period (the first row, then the
// first row at least a period after the last kept one): local nodes that track at the scan rate
// but report at a slower rate.
//
// Tuples (AssociationRecord, one column per /sensors entry). Each local track is mapped to the
// system track that received most of its packets (ties: the lower system track number). A tuple
// per system track holds, for each sensor, the local track mapped to it; when several local
// tracks of one sensor map to the same system track, the one with the most packets is kept and the
// others become tuples of their own (counted in `sensor_conflicts` and the record's termination
// text). Local tracks that never formed a temporary track are tuples of one. So every local track
// appears in exactly one tuple, as in engine/pipeline/pipeline.hpp. Tuple cost: 1 − the mean association
// degree μ of the packets of its system track (fuzzy; 0 for FTAA, which has no per-packet degree).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/solvers/option_fields.hpp"
#include "io/track_file.hpp"
#include "kernels/fuzzy/ftaa.hpp"
#include "kernels/fuzzy/fuzzy_association.hpp"

namespace trackassoc {

enum class FusionMethod { kFuzzy, kFtaa };
inline constexpr EnumName<FusionMethod> kFusionMethodNames[]{{FusionMethod::kFuzzy, "fuzzy"},
                                                             {FusionMethod::kFtaa, "ftaa"}};
constexpr std::span<const EnumName<FusionMethod>> enum_names(FusionMethod) { return kFusionMethodNames; }
enum class PacketSource { kTrack, kPlot };
inline constexpr EnumName<PacketSource> kPacketSourceNames[]{{PacketSource::kTrack, "track"},
                                                             {PacketSource::kPlot, "plot"}};
constexpr std::span<const EnumName<PacketSource>> enum_names(PacketSource) { return kPacketSourceNames; }

struct FuzzyPipelineOptions {
  FusionMethod method = FusionMethod::kFuzzy;
  double packet_period = 0.0;  // [s]; 0 = every /tracks row is a packet
  PacketSource packet_source = PacketSource::kTrack;
  FuzzyAssociationOptions fuzzy;
  FtaaOptions ftaa;
  void validate() const;
  nlohmann::json to_json() const;
};

// Options from a JSON object (the CLI's --options). Keys (all optional): packet_period,
// packets ("track" | "plot"), gate,
// u_max_position, u_max_speed, u_max_heading, synthesis, weights, q, and for fuzzy: weighting,
// min_degree, track_timeout, smoother {gains: "kalata"|"fixed", alpha, beta, process_noise,
// measurement_noise}; for ftaa: threshold, association_quality, separation_quality, track_timeout.
// Unknown keys are an InputError naming the key.
FuzzyPipelineOptions fuzzy_pipeline_options(FusionMethod method, const nlohmann::json& options);
// The keys of each method, declared once (engine/solvers/option_fields.hpp): read, write (to_json), help.
const OptionFields<FuzzyPipelineOptions>& fuzzy_pipeline_option_fields(FusionMethod method);

// Packets built from a track table, in table row order.
struct PacketTable {
  std::vector<int32_t> sensor;  // index into the sensor list
  std::vector<int32_t> local;   // dense local track index
  std::vector<double> t, x, y;
  std::vector<int32_t> truth;                         // /tracks/truth of the row
  std::vector<int32_t> local_sensor_id, local_track;  // per dense local track: /sensors id, /tracks/track
  std::size_t size() const { return t.size(); }
  std::size_t num_local() const { return local_track.size(); }
  PacketSpans spans() const { return {sensor, local, t, x, y}; }
};
// `measurements` is needed (non-null) for PacketSource::kPlot.
PacketTable make_packets(const TrackTable& tracks, const std::vector<Sensor>& sensors, double packet_period,
                         PacketSource source = PacketSource::kTrack,
                         const Measurements* measurements = nullptr);

struct FuzzyPipelineResult {
  PacketTable packets;
  FusionOutput fusion;  // per packet
  SystemTrackRecord system_tracks;
  AssociationRecord association;
  int32_t sensor_conflicts = 0;  // local tracks dropped from a tuple (see the header comment)
};

// Runs the method over `tracks`. `name` names the /associations and /system_tracks groups.
FuzzyPipelineResult run_fuzzy_pipeline(const TrackTable& tracks, const std::vector<Sensor>& sensors,
                                       const FuzzyPipelineOptions& options, const std::string& name,
                                       const Measurements* measurements = nullptr);

// Convenience for `associate`: runs on a file and appends/replaces the two records in it.
FuzzyPipelineResult associate_fuzzy(TrackFile& file, const FuzzyPipelineOptions& options,
                                    const std::string& name);

}  // namespace trackassoc
