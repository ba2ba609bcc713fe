// The seed 001 pipeline (engine/pipeline/fuzzy_pipeline.hpp): packets from a track table (thinning),
// tuples and mapping from the per-packet decisions (including a sensor's broken track), the
// /system_tracks HDF5 round trip, and option parsing.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <set>

#include "engine/pipeline/fuzzy_pipeline.hpp"
#include "kernels/core/error.hpp"
#include "tests/support/fuzzy_test_scenes.hpp"

using namespace trackassoc;

namespace {

// A track file from a test scene: sensors with ids 10..13, local track numbers shuffled
// (number = 7 − target), and, when `break_track`, sensor 11's track of target 0 renumbered 99
// from t ≥ 100 (a broken local track).
TrackFile scene_file(const test_scenes::Scene& sc, bool break_track = false) {
  TrackFile f;
  for (int s = 0; s < 4; ++s) {
    Sensor sensor;
    sensor.id = 10 + s;
    sensor.reliability = sc.reliability[s];
    sensor.period = 4.0;
    sensor.offset = s;
    f.sensors.push_back(sensor);
  }
  const Eigen::MatrixXd P = Eigen::MatrixXd::Identity(4, 4) * 100.0;
  for (std::size_t i = 0; i < sc.size(); ++i) {
    Eigen::VectorXd x(4);
    x << sc.x[i], sc.y[i], 0.0, 0.0;
    int32_t number = 7 - sc.target[i];
    if (break_track && sc.sensor[i] == 1 && sc.target[i] == 0 && sc.t[i] >= 100) number = 99;
    f.tracks.push_back(10 + sc.sensor[i], number, sc.t[i], x, P, sc.target[i]);
  }
  return f;
}

}  // namespace

TEST(FuzzyPipeline, TuplesGroupEachTargetsTracks) {
  const auto sc = test_scenes::make_scene(11, 0, {{0, 0, 250, 0}, {0, 5000, 250, 0}}, 120.0);
  TrackFile f = scene_file(sc);
  for (auto method : {FusionMethod::kFuzzy, FusionMethod::kFtaa}) {
    const auto opts = fuzzy_pipeline_options(method, nlohmann::json::object());
    const auto res = run_fuzzy_pipeline(f.tracks, f.sensors, opts, enum_name(method));
    ASSERT_EQ(res.association.num_tuples(), 2u) << enum_name(method);
    std::set<std::vector<int32_t>> tuples;
    for (std::size_t k = 0; k < 2; ++k)
      tuples.insert(std::vector<int32_t>(res.association.tuples.begin() + 4 * k,
                                         res.association.tuples.begin() + 4 * k + 4));
    EXPECT_EQ(tuples, (std::set<std::vector<int32_t>>{{7, 7, 7, 7}, {6, 6, 6, 6}}));
    EXPECT_EQ(res.sensor_conflicts, 0);
    // Mapping: every (local, system) pair once, packets summing to the decisions.
    int64_t packets = 0;
    for (int32_t c : res.system_tracks.map_packets) packets += c;
    EXPECT_EQ(packets, static_cast<int64_t>(res.system_tracks.size()));
    // FTAA's component numbers change when tracks merge, so a local track maps to several.
    if (method == FusionMethod::kFuzzy) {
      EXPECT_EQ(res.system_tracks.mapping_size(), 8u);
    }
    if (method == FusionMethod::kFtaa) {
      EXPECT_GT(res.system_tracks.mapping_size(), 8u);
    }
  }
}

TEST(FuzzyPipeline, BrokenTrackIsAConflictAndEveryLocalTrackAppearsOnce) {
  const auto sc = test_scenes::make_scene(12, 0, {{0, 0, 250, 0}}, 210.0);
  TrackFile f = scene_file(sc, /*break_track=*/true);
  const auto res = run_fuzzy_pipeline(f.tracks, f.sensors, FuzzyPipelineOptions{}, "fuzzy");
  EXPECT_EQ(res.sensor_conflicts, 1);
  // Sensor 11 track 7 holds t = 1..97 (24 temporary tracks), track 99 t = 101..209 (27): 99 wins.
  ASSERT_EQ(res.association.num_tuples(), 2u);
  EXPECT_EQ(std::vector<int32_t>(res.association.tuples.begin(), res.association.tuples.begin() + 4),
            (std::vector<int32_t>{7, 99, 7, 7}));
  EXPECT_EQ(std::vector<int32_t>(res.association.tuples.begin() + 4, res.association.tuples.end()),
            (std::vector<int32_t>{-1, 7, -1, -1}));
  EXPECT_NE(res.association.termination.find("kept the one with most packets"), std::string::npos);
}

TEST(FuzzyPipeline, PacketThinning) {
  TrackFile f;
  Sensor s;
  s.id = 3;
  f.sensors.push_back(s);
  const Eigen::MatrixXd P = Eigen::MatrixXd::Identity(4, 4);
  for (int k = 0; k <= 12; ++k) f.tracks.push_back(3, 1, 0.5 + k, Eigen::Vector4d(k, 0, 1, 0), P, 0);
  const PacketTable p = make_packets(f.tracks, f.sensors, 4.0);
  EXPECT_EQ(p.t, (std::vector<double>{0.5, 4.5, 8.5, 12.5}));
  EXPECT_EQ(make_packets(f.tracks, f.sensors, 0.0).size(), 13u);
  f.tracks.sensor[0] = 4;
  EXPECT_THROW(make_packets(f.tracks, f.sensors, 0.0), InputError);
}

TEST(FuzzyPipeline, SystemTracksRoundTripThroughHdf5) {
  const auto sc = test_scenes::make_scene(13, 0, {{0, 0, 250, 0}, {0, 5000, 250, 0}}, 60.0);
  TrackFile f = scene_file(sc);
  associate_fuzzy(f, FuzzyPipelineOptions{}, "fuzzy");
  FuzzyPipelineOptions ftaa;
  ftaa.method = FusionMethod::kFtaa;
  associate_fuzzy(f, ftaa, "ftaa");
  associate_fuzzy(f, FuzzyPipelineOptions{}, "fuzzy");  // replaces, does not duplicate
  ASSERT_EQ(f.system_tracks.size(), 2u);
  const std::string path =
      (std::filesystem::temp_directory_path() / "trackassoc_test_fuzzy_pipeline.h5").string();
  write_track_file(path, f);
  const TrackFile g = read_track_file(path);
  std::remove(path.c_str());
  ASSERT_EQ(g.system_tracks.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    const auto &a = f.system_tracks[k], &b = g.system_tracks[k];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.method, b.method);
    EXPECT_EQ(a.options_json, b.options_json);
    EXPECT_EQ(a.track, b.track);
    EXPECT_EQ(a.t, b.t);
    for (int c = 0; c < 4; ++c) EXPECT_EQ(a.state[c], b.state[c]);
    EXPECT_EQ(a.map_sensor, b.map_sensor);
    EXPECT_EQ(a.map_local_track, b.map_local_track);
    EXPECT_EQ(a.map_system_track, b.map_system_track);
    EXPECT_EQ(a.map_packets, b.map_packets);
  }
  ASSERT_EQ(g.associations.size(), 2u);
  EXPECT_EQ(g.associations[1].tuples, f.associations[1].tuples);
}

TEST(FuzzyPipeline, OptionsFromJson) {
  const auto o = fuzzy_pipeline_options(
      FusionMethod::kFuzzy,
      nlohmann::json::parse(R"({"gate": 500, "synthesis": "min-max-mean", "weighting": "none",
                                 "smoother": {"gains": "fixed", "alpha": 0.4, "beta": 0.1}, "packet_period": 4})"));
  EXPECT_EQ(o.fuzzy.gate, 500.0);
  EXPECT_EQ(o.fuzzy.synthesis.function, SynthesisFunction::kMinMaxMean);
  EXPECT_EQ(o.fuzzy.weighting, ReliabilityWeighting::kNone);
  EXPECT_EQ(o.fuzzy.smoother.gains, AlphaBetaGainMode::kFixed);
  EXPECT_EQ(o.packet_period, 4.0);
  EXPECT_THROW(fuzzy_pipeline_options(FusionMethod::kFuzzy, nlohmann::json::parse(R"({"gaet": 1})")),
               InputError);
  EXPECT_THROW(fuzzy_pipeline_options(FusionMethod::kFuzzy, nlohmann::json::parse(R"({"threshold": 0.5})")),
               InputError);  // an FTAA key
  EXPECT_THROW(
      fuzzy_pipeline_options(FusionMethod::kFtaa, nlohmann::json::parse(R"({"weights": [1, 1, 1]})")),
      InputError);
  EXPECT_THROW(parse_enum<FusionMethod>("hopfield", "--solver"), InputError);
}
