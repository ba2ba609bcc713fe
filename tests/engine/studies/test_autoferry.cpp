// Autoferry reader (io/autoferry.hpp) and study (engine/studies/autoferry/autoferry.hpp): the parsers on JSON
// the tests write, the labelling rule and the pair score on hand-made tables, and the real data set (skipped
// with a message when ../shared/datasets/autoferry is absent).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>

#include "engine/studies/autoferry/autoferry.hpp"
#include "io/autoferry.hpp"
#include "io/track_file.hpp"
#include "kernels/core/error.hpp"
#include "tests/support/cli_runner.hpp"

namespace trackassoc {
namespace {

const std::string kData = std::string(TRACKASSOC_SHARED_DIR) + "/datasets/autoferry";

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(AutoferryReader, ParsesTheThreeMeasurementShapesAndBearings) {
  const std::string text = R"([
    {"sensorID": 2, "measurements": [], "ownshipPosition": [10, 20], "time": 1000.5,
     "measurement": [[1, 2, 3], [4, 5, 6]]},
    {"sensorID": 1, "measurements": [], "ownshipPosition": [11, 21], "time": 1001.0, "measurement": [7, 8]},
    {"sensorID": 1, "measurements": [], "ownshipPosition": [12, 22], "time": 1001.5, "measurement": []},
    {"sensorID": 3, "measurements": [], "ownshipPosition": [12, 22], "time": 1001.5, "measurement": -2.5},
    {"sensorID": 4, "measurements": [], "ownshipPosition": [12, 22], "time": 1001.6, "measurement": [0.1, 0.2]}])";
  double t0 = 0;
  const auto scans = parse_autoferry_detections(text, "d.json", t0);
  EXPECT_EQ(t0, 1000.5);
  ASSERT_EQ(scans.size(), 5u);
  EXPECT_EQ(scans[0].sensor, 2);
  EXPECT_EQ(scans[0].t, 0.0);
  EXPECT_EQ(scans[0].north, (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(scans[0].east, (std::vector<double>{4, 5, 6}));
  EXPECT_EQ(scans[1].north, (std::vector<double>{7}));
  EXPECT_EQ(scans[1].east, (std::vector<double>{8}));
  EXPECT_EQ(scans[1].t, 0.5);
  EXPECT_EQ(scans[1].ownship[1], 21.0);
  EXPECT_TRUE(scans[2].north.empty());
  EXPECT_EQ(scans[3].bearing, (std::vector<double>{-2.5}));
  EXPECT_EQ(scans[4].bearing, (std::vector<double>{0.1, 0.2}));
}

TEST(AutoferryReader, BadEntriesNameFileEntryAndField) {
  double t0 = 0;
  auto parse = [&](const std::string& t) { return [&, t] { parse_autoferry_detections(t, "d.json", t0); }; };
  std::string e =
      error_of(parse(R"([{"sensorID": 7, "ownshipPosition": [0, 0], "time": 1, "measurement": []}])"));
  EXPECT_NE(e.find("d.json: entry 0, field 'sensorID'"), std::string::npos) << e;
  e = error_of(parse(R"([{"sensorID": 1, "ownshipPosition": [0, 0], "time": 2, "measurement": []},
                         {"sensorID": 1, "ownshipPosition": [0, 0], "time": 1, "measurement": []}])"));
  EXPECT_NE(e.find("entry 1, field 'time'"), std::string::npos) << e;
  EXPECT_NE(e.find("backwards"), std::string::npos) << e;
  e = error_of(
      parse(R"([{"sensorID": 2, "ownshipPosition": [0, 0], "time": 1, "measurement": [[1, 2], [3]]}])"));
  EXPECT_NE(e.find("field 'measurement'"), std::string::npos) << e;
  e = error_of(parse(R"([{"sensorID": 2, "ownshipPosition": [0], "time": 1, "measurement": []}])"));
  EXPECT_NE(e.find("field 'ownshipPosition'"), std::string::npos) << e;
  e = error_of(parse(R"([{"sensorID": 2, "ownshipPosition": [0, 0], "measurement": []}])"));
  EXPECT_NE(e.find("field 'time': missing"), std::string::npos) << e;
  e = error_of(parse(R"([{"sensorID": 2, "ownshipPosition": [0, "a"], "time": 1, "measurement": []}])"));
  EXPECT_NE(e.find("ownshipPosition'[1]"), std::string::npos) << e;
  e = error_of([] { read_autoferry_scenario("/nonexistent", 2); });
  EXPECT_NE(e.find("/nonexistent/scenario2/scenario2_detections.json"), std::string::npos) << e;
  e = error_of([] { read_autoferry_scenario("/nonexistent", 7); });
  EXPECT_NE(e.find("--scenario"), std::string::npos) << e;
}

// Vessel 1's fixes at t0+0, +1, +3 at north 0, 2, 8 (east 0): velocities by central differences
// (2-0)/1 = 2 (one-sided), (8-0)/3 = 8/3, (8-2)/2 = 3 (one-sided); the repeated fix is one row.
TEST(AutoferryReader, TruthDeduplicatedWithCentralDifferenceVelocity) {
  const std::string text = R"([
    [{"targetID": 1, "position": [0, 0, 0], "time": 100}, {"targetID": 2, "position": [5, 5, 0], "time": 100}],
    [{"targetID": 1, "position": [0, 0, 0], "time": 100}, {"targetID": 1, "position": [2, 0, 0], "time": 101}],
    [{"targetID": 1, "position": [8, 0, 0], "time": 103}]])";
  const TruthTable t = parse_autoferry_truth(text, "g.json", 100.0);
  ASSERT_EQ(t.size(), 4u);
  EXPECT_EQ(t.target, (std::vector<int32_t>{1, 1, 1, 2}));
  EXPECT_EQ(t.t, (std::vector<double>{0, 1, 3, 0}));
  EXPECT_DOUBLE_EQ(t.state[2][0], 2.0);
  EXPECT_DOUBLE_EQ(t.state[2][1], 8.0 / 3.0);
  EXPECT_DOUBLE_EQ(t.state[2][2], 3.0);
  EXPECT_EQ(t.state[2][3], 0.0);  // one fix
  const std::string e =
      error_of([] { parse_autoferry_truth(R"([[{"targetID": 1, "time": 1}]])", "g.json", 0); });
  EXPECT_NE(e.find("g.json: entry 0, field 'position'"), std::string::npos) << e;
}

// Truth: vessel 1 at (0, 0) and vessel 2 at (100, 0) over t in [0, 10], stationary.
// Track (1, 0): 10 rows at (10, 0): within 25 m of vessel 1 on 10/10 -> 1.
// Track (1, 1): rows at (50, 0) x2 and (100, 5) x8: 8/10 = 0.8 near vessel 2 -> 2 (fraction >= 0.8).
// Track (2, 0): (100, 5) x7 and (50, 0) x3: 0.7 -> -1.
// Track (2, 1): (0, 0) at t = 9, 10, 11, 12, 13: t > 10 is outside the truth span: 2/5 -> -1.
TEST(AutoferryScoring, LabelRule) {
  TruthTable truth(StateLayout::kXY_VXVY);
  for (int v = 1; v <= 2; ++v)
    for (double t : {0.0, 10.0}) {
      truth.target.push_back(v);
      truth.t.push_back(t);
      truth.state[0].push_back(v == 1 ? 0 : 100);
      truth.state[1].push_back(0);
      truth.state[2].push_back(0);
      truth.state[3].push_back(0);
    }
  TrackTable tr(StateLayout::kXY_VXVY);
  const Eigen::Matrix4d P = Eigen::Matrix4d::Identity();
  auto row = [&](int s, int k, double t, double x, double y) {
    tr.push_back(s, k, t, Eigen::Vector4d(x, y, 0, 0), P, -1);
  };
  for (int i = 0; i < 10; ++i) row(1, 0, i, 10, 0);
  for (int i = 0; i < 10; ++i) i < 2 ? row(1, 1, i, 50, 0) : row(1, 1, i, 100, 5);
  for (int i = 0; i < 10; ++i) i < 7 ? row(2, 0, i, 100, 5) : row(2, 0, i, 50, 0);
  for (int i = 9; i < 14; ++i) row(2, 1, i, 0, 0);
  const auto labels = label_local_tracks(tr, truth, 25.0, 0.8);
  ASSERT_EQ(labels.size(), 4u);
  EXPECT_EQ(labels[0].label, 1);
  EXPECT_EQ(labels[1].label, 2);
  EXPECT_EQ(labels[2].label, -1);
  EXPECT_EQ(labels[3].label, -1);
  EXPECT_EQ(labels[3].t_first, 9.0);
  EXPECT_EQ(labels[3].t_last, 13.0);
  EXPECT_EQ(label_local_tracks(tr, truth, 25.0, 0.7)[2].label, 2);  // 0.7 >= 0.7
}

// Lidar tracks 0 (vessel 1, [0, 60]), 1 (vessel 2, [0, 60]), 2 (-1, [0, 60]), 3 (vessel 1, [55, 60]);
// radar 0 (vessel 1, [0, 60]), 1 (vessel 2, [0, 60]), 2 (-1, [0, 60]).
// True pairs (overlap >= 10 s): (r0, l0), (r1, l1) = 2 ((r0, l3) overlaps 5 s only).
// Tuples (lidar, radar): (0, 0) correct, (1, 2) false, (2, -1) no pair, (3, 1) overlaps 5 s: not
// counted. predicted = 2, correct = 1 -> precision 1/2, recall 1/2.
TEST(AutoferryScoring, RadarLidarPairs) {
  TrackFile file;
  file.sensors.resize(2);
  file.sensors[0].id = kAutoferryLidar;
  file.sensors[1].id = kAutoferryRadar;
  std::vector<TrackLabel> labels = {{1, 0, 1, 0, 60, 1},  {1, 1, 2, 0, 60, 1}, {1, 2, -1, 0, 60, 1},
                                    {1, 3, 1, 55, 60, 1}, {2, 0, 1, 0, 60, 1}, {2, 1, 2, 0, 60, 1},
                                    {2, 2, -1, 0, 60, 1}};
  AssociationRecord rec;
  rec.num_sensors = 2;
  rec.tuples = {0, 0, 1, 2, 2, -1, 3, 1};
  PairScore p = score_radar_lidar_pairs(file, rec, labels, 10.0);
  EXPECT_EQ(p.true_pairs, 2);
  EXPECT_EQ(p.predicted, 2);
  EXPECT_EQ(p.correct, 1);
  EXPECT_EQ(p.unlabelled_predicted, 0);
  EXPECT_DOUBLE_EQ(p.precision(), 0.5);
  EXPECT_DOUBLE_EQ(p.recall(), 0.5);
  // (0, 0) is vessel 1's correct pair; (1, 2) is false for vessel 2 (radar 2 is unlabelled).
  EXPECT_EQ(p.correct_by_vessel, (std::map<int32_t, int64_t>{{1, 1}}));
  EXPECT_EQ(p.false_by_vessel, (std::map<int32_t, int64_t>{{2, 1}}));
  // Breaks: lidar has vessel 1 twice (tracks 0, 3) and vessel 2 once -> 1; radar none.
  EXPECT_EQ(track_breaks(labels, kAutoferryLidar), 1);
  EXPECT_EQ(track_breaks(labels, kAutoferryRadar), 0);
  // (2, 2): both unlabelled -> predicted but left out of precision.
  rec.tuples = {0, 0, 1, 1, 2, 2};
  p = score_radar_lidar_pairs(file, rec, labels, 10.0);
  EXPECT_EQ(p.predicted, 3);
  EXPECT_EQ(p.unlabelled_predicted, 1);
  EXPECT_EQ(p.correct, 2);
  EXPECT_DOUBLE_EQ(p.precision(), 1.0);
  EXPECT_DOUBLE_EQ(p.recall(), 1.0);
}

TEST(AutoferryData, Scenario2CountsAndFrame) {
  if (!std::filesystem::exists(kData + "/scenario2")) GTEST_SKIP() << "Autoferry data absent: " << kData;
  const AutoferryScenario sc = read_autoferry_scenario(kData, 2);
  // Counted independently with Python's json module: 1907 entries; lidar 234 scans / 412 plots,
  // radar 70 scans / 437 plots.
  EXPECT_EQ(sc.scans.size(), 1907u);
  int64_t scans[5] = {}, plots[5] = {};
  for (const auto& s : sc.scans) ++scans[s.sensor], plots[s.sensor] += static_cast<int64_t>(s.north.size());
  EXPECT_EQ(scans[1], 234);
  EXPECT_EQ(scans[2], 70);
  EXPECT_EQ(plots[1], 412);
  EXPECT_EQ(plots[2], 437);
  // The first truth fixes of the file: vessel 1 at (84.6351, -354.7960) at t0 + 0.0306 s.
  EXPECT_EQ(sc.truth.target.front(), 1);
  EXPECT_NEAR(sc.truth.state[0].front(), 84.635100992121835, 1e-9);
  EXPECT_NEAR(sc.truth.state[1].front(), -354.7959646839322, 1e-9);
  const TrackFile f = autoferry_track_file(sc, AutoferryOptions{});
  EXPECT_EQ(f.recording.frame, "NED");
  ASSERT_EQ(f.sensors.size(), 2u);
  EXPECT_NEAR(f.sensors[0].period, 0.504, 0.01);  // lidar
  EXPECT_NEAR(f.sensors[1].period, 1.679, 0.01);  // radar
  ASSERT_GT(f.tracks.size(), 0u);
  // Every local track spans >= min_track_duration_s (10 s); its truth label is one value.
  std::map<std::pair<int32_t, int32_t>, std::array<double, 3>> span;  // first t, last t, label
  for (std::size_t i = 0; i < f.tracks.size(); ++i) {
    auto [it, fresh] =
        span.emplace(std::make_pair(f.tracks.sensor[i], f.tracks.track[i]),
                     std::array<double, 3>{f.tracks.t[i], f.tracks.t[i], double(f.tracks.truth[i])});
    it->second[0] = std::min(it->second[0], f.tracks.t[i]);
    it->second[1] = std::max(it->second[1], f.tracks.t[i]);
    EXPECT_EQ(it->second[2], double(f.tracks.truth[i]));
  }
  for (const auto& [key, s] : span) EXPECT_GE(s[1] - s[0], 10.0) << key.first << ":" << key.second;
}

using testing_support::CliFixture;
using testing_support::run_cli;

TEST_F(CliFixture, ImportAutoferryBadInputExits2AndWritesNothing) {
  const auto out = dir_ / "a.h5";
  auto r = run_cli("import autoferry --data " + dir_.string() + " --scenario 7 -o " + out.string(), dir_);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--scenario"), std::string::npos) << r.err;
  std::filesystem::create_directories(dir_ / "scenario2");
  std::ofstream(dir_ / "scenario2" / "scenario2_detections.json")
      << R"([{"sensorID": 2, "ownshipPosition": [0, 0], "time": 1, "measurement": [[1], [2, 3]]}])";
  r = run_cli("import autoferry --data " + dir_.string() + " --scenario 2 -o " + out.string(), dir_);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("scenario2_detections.json: entry 0, field 'measurement'"), std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST_F(CliFixture, ImportAndExperimentAutoferryOnTheDataSet) {
  if (!std::filesystem::exists(kData + "/scenario2")) GTEST_SKIP() << "Autoferry data absent: " << kData;
  const auto out = dir_ / "s2.h5";
  auto r = run_cli("import autoferry --data " + kData + " --scenario 2 -o " + out.string(), dir_);
  ASSERT_EQ(r.status, 0) << r.err;
  const TrackFile f = read_track_file(out.string());
  const TrackFile expected = autoferry_track_file(read_autoferry_scenario(kData, 2), AutoferryOptions{});
  EXPECT_EQ(f.recording.frame, "NED");
  ASSERT_TRUE(f.recording.frame_origin.has_value());
  EXPECT_EQ((*f.recording.frame_origin)[0], kPirenOrigin[0]);
  EXPECT_EQ(f.tracks.t, expected.tracks.t);
  EXPECT_EQ(f.tracks.truth, expected.tracks.truth);
  ASSERT_TRUE(f.truth.has_value());
  EXPECT_EQ(f.truth->size(), expected.truth->size());

  // The experiment prints the totals of run_autoferry_experiment and writes one file per scenario
  // with the default association.
  r = run_cli("experiment autoferry --data " + kData + " -o " + (dir_ / "exp").string(), dir_);
  ASSERT_EQ(r.status, 0) << r.err;
  const AutoferryExperimentResult e = run_autoferry_experiment(kData, AutoferryOptions{}, "");
  const std::size_t all = r.out.find("\nall ");
  ASSERT_NE(all, std::string::npos) << r.out;
  std::istringstream line(r.out.substr(all + 5));
  int64_t true_pairs = 0, predicted = 0, correct = 0, unlabelled = 0;
  std::string breaks;
  line >> breaks >> true_pairs >> predicted >> correct >> unlabelled;
  EXPECT_EQ(true_pairs, e.total.true_pairs);
  EXPECT_EQ(predicted, e.total.predicted);
  EXPECT_EQ(correct, e.total.correct);
  EXPECT_EQ(unlabelled, e.total.unlabelled_predicted);
  // Its time (issue 17: the whole set in <= 10 s) is bench/bench_recorded.cpp's BM_AutoferryExperiment.
  // Issue 17's goal over the 9 scenarios, scored against the GNSS truth: radar–lidar pair
  // precision >= 95 % and recall >= 90 % (measured: 95.7 % and 100 %, docs/autoferry.md).
  EXPECT_GE(e.total.precision(), 0.95);
  EXPECT_GE(e.total.recall(), 0.90);
  for (const int n : kAutoferryScenarios) {
    const TrackFile s = read_track_file((dir_ / "exp" / ("scenario" + std::to_string(n) + ".h5")).string());
    ASSERT_EQ(s.associations.size(), 1u) << n;
    EXPECT_EQ(s.associations[0].num_sensors, 2) << n;
  }
}

}  // namespace
}  // namespace trackassoc
