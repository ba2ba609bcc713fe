// The association interface (engine/pipeline/associator.hpp): the default path's tuples are the
// file's targets (scored against its truth); the other paths give the tuples and costs of their
// pipelines called directly; the unassociated tracks of a hand-made record are the ones worked out
// by hand; the factory picks the paths `associate` picked (engine/cli/cmd_associate.cpp's rules).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include "engine/pipeline/associator.hpp"
#include "engine/pipeline/fuzzy_pipeline.hpp"
#include "engine/pipeline/pipeline_sd.hpp"
#include "engine/pipeline/siamese_track_file.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "io/siamese_model_file.hpp"
#include "kernels/core/error.hpp"
#include "tests/support/cli_runner.hpp"
#include "tests/support/io_test_files.hpp"

namespace trackassoc {
namespace {

// Four asynchronous 3-D sensors, the first 5 targets of the seed 004 scenario, 80 s.
const TrackFile& four_sensor_file() {
  static const TrackFile file = [] {
    Scenario sc = load_scenario("seed004");
    sc.targets.resize(5);
    sc.duration = 80.0;
    return simulation_to_track_file(sc, simulate(sc, 1, 0));
  }();
  return file;
}

void expect_same_tuples(const AssociationRecord& got, const AssociationRecord& want) {
  EXPECT_EQ(got.num_sensors, want.num_sensors);
  EXPECT_EQ(got.tuples, want.tuples);
  EXPECT_EQ(got.cost, want.cost);
  EXPECT_EQ(got.objective, want.objective);
  EXPECT_EQ(got.solver, want.solver);
  EXPECT_EQ(got.options_json, want.options_json);
}

// The truth target of each (sensor id, local track) of the file, from /tracks/truth; a track whose
// reports name two targets fails the test.
std::map<std::pair<int32_t, int32_t>, int32_t> track_truth(const TrackFile& file) {
  std::map<std::pair<int32_t, int32_t>, int32_t> out;
  for (std::size_t r = 0; r < file.tracks.size(); ++r) {
    const auto [it, fresh] =
        out.emplace(std::pair{file.tracks.sensor[r], file.tracks.track[r]}, file.tracks.truth[r]);
    EXPECT_TRUE(fresh || it->second == file.tracks.truth[r]) << "track of two targets at row " << r;
  }
  return out;
}

// The unassociated tracks worked out from the record directly: the tracks of `ids` in /tracks
// minus those in a tuple of two or more.
std::map<int32_t, std::set<int32_t>> lonely(const TrackFile& file, const std::vector<int32_t>& ids,
                                            const AssociationRecord& rec) {
  std::map<int32_t, std::set<int32_t>> out;
  for (int32_t id : ids) out[id];
  for (std::size_t r = 0; r < file.tracks.size(); ++r)
    if (out.count(file.tracks.sensor[r])) out[file.tracks.sensor[r]].insert(file.tracks.track[r]);
  for (std::size_t k = 0; k < rec.num_tuples(); ++k) {
    int members = 0;
    for (int32_t c = 0; c < rec.num_sensors; ++c) members += rec.tuples[k * rec.num_sensors + c] >= 0;
    if (members < 2) continue;
    for (int32_t c = 0; c < rec.num_sensors; ++c)
      if (out.count(file.sensors[c].id)) out[file.sensors[c].id].erase(rec.tuples[k * rec.num_sensors + c]);
  }
  return out;
}

void expect_unassociated(const TrackFile& file, const AssociationOutcome& out) {
  const auto want = lonely(file, out.summary.sensor_ids, out.record);
  ASSERT_EQ(out.unassociated.size(), out.summary.sensor_ids.size());
  for (std::size_t i = 0; i < out.unassociated.size(); ++i) {
    EXPECT_EQ(out.unassociated[i].sensor_id, out.summary.sensor_ids[i]);
    const std::set<int32_t> got(out.unassociated[i].tracks.begin(), out.unassociated[i].tracks.end());
    EXPECT_EQ(got, want.at(out.summary.sensor_ids[i]));
  }
}

AssociatorOptions request(const std::string& solver) {
  AssociatorOptions o;
  o.solver = solver;
  o.seed = 7;
  return o;
}

TEST(Associator, SparseSDTuplesAreTheFilesTargets) {
  const TrackFile& file = four_sensor_file();
  const auto a = make_associator(request("lr+ls"));
  ASSERT_EQ(a->path(), AssociationPath::kSparseSD);
  const AssociationOutcome out = a->associate(file);
  // Scored against the file's truth, worked out by hand from its construction: the 5 targets are
  // each tracked by all 4 sensors, so the answer is 5 tuples of 4 tracks, each tuple one target's
  // tracks, every target in exactly one tuple.
  const auto truth = track_truth(file);
  ASSERT_EQ(out.record.num_sensors, 4);
  ASSERT_EQ(out.record.num_tuples(), 5u);
  std::set<int32_t> targets;
  for (std::size_t k = 0; k < out.record.num_tuples(); ++k) {
    std::set<int32_t> members;
    for (int32_t c = 0; c < 4; ++c) {
      const int32_t t = out.record.tuples[k * 4 + c];
      ASSERT_GE(t, 0) << "tuple " << k << " misses sensor " << c;
      members.insert(truth.at({file.sensors[c].id, t}));
    }
    EXPECT_EQ(members.size(), 1u) << "tuple " << k << " mixes targets";
    targets.insert(*members.begin());
  }
  EXPECT_EQ(targets.size(), 5u);
  // The objective is the sum of the tuples' costs (stored as floats: 1e-5 relative).
  double sum = 0.0;
  for (double c : out.record.cost) sum += c;
  EXPECT_NEAR(out.record.objective, sum, 1e-5 * std::abs(sum));
  EXPECT_EQ(out.summary.sensor_ids, (std::vector<int32_t>{file.sensors[0].id, file.sensors[1].id,
                                                          file.sensors[2].id, file.sensors[3].id}));
  EXPECT_GE(out.summary.components, 1);
  // alignment, candidates, statistics, components, solve, segments, the registration stage's own
  // time (engine/pipeline/registration_stage.hpp), then stitching, in the order they ran: this file
  // has no registration errors, so the estimate is not applied (the tuples above are the recorded
  // ones); its tracks all coexist, so no fragment is stitched. Each stage's peak memory is the
  // process's at its end, so it never decreases along the list.
  EXPECT_EQ(out.summary.stages.size(), 8u);
  EXPECT_EQ(out.summary.stages[6].name, "registration");
  EXPECT_EQ(out.summary.stitching.stitches, 0);
  EXPECT_EQ(out.summary.stages.back().name, "stitching");
  for (std::size_t i = 1; i < out.summary.stages.size(); ++i)
    EXPECT_GE(out.summary.stages[i].peak_rss_mib, out.summary.stages[i - 1].peak_rss_mib) << i;
  ASSERT_TRUE(out.registration.has_value());
  EXPECT_FALSE(out.registration->applied);
  expect_unassociated(file, out);
}

// --sensors selects sensors without changing the method (issue 28): naming all three sensors of a
// three-sensor file gives the default's association, not the 3-D tensor's.
TEST(Associator, NamingEverySensorKeepsTheDefaultPath) {
  Scenario sc = load_scenario("seed004");  // four_sensor_file's scenario on its first three sensors
  sc.targets.resize(5);
  sc.sensors.resize(3);
  sc.duration = 80.0;
  const TrackFile file = simulation_to_track_file(sc, simulate(sc, 1, 0));
  const AssociationOutcome by_default = make_associator(request("lr+ls"))->associate(file);
  AssociatorOptions o = request("lr+ls");
  o.pipeline.sensors = {file.sensors[0].id, file.sensors[1].id, file.sensors[2].id};
  const auto a = make_associator(o);
  ASSERT_EQ(a->path(), AssociationPath::kSparseSD);
  const AssociationOutcome named = a->associate(file);
  EXPECT_EQ(named.record.num_sensors, 3);
  EXPECT_EQ(named.record.tuples, by_default.record.tuples);
  EXPECT_EQ(named.record.cost, by_default.record.cost);
  EXPECT_EQ(named.record.objective, by_default.record.objective);
  // The 5 targets seen by all three sensors: 5 tuples of 3 tracks, whose S-D cost (a sum of link
  // costs λ − G(n) ≤ 0 inside the gate) is negative; the 3-D tensor's objective is a sum of λ ≥ 0.
  EXPECT_EQ(named.record.num_tuples(), 5u);
  EXPECT_LT(named.record.objective, 0.0);
}

TEST(Associator, DenseSDIsSolveSDAssociation) {
  const TrackFile& file = four_sensor_file();
  AssociatorOptions o = request("lr");
  o.sd = true;
  const auto a = make_associator(o);
  ASSERT_EQ(a->path(), AssociationPath::kDenseSD);
  const AssociationOutcome out = a->associate(file);
  const SDProblem p = build_sd_problem(file, PipelineOptions{});
  expect_same_tuples(out.record,
                     solve_sd_association(p, "lr", nlohmann::json::object(), 7, PipelineOptions{}));
  EXPECT_EQ(out.summary.track_counts.size(), 4u);
  EXPECT_EQ(out.summary.track_counts[0], p.aligned[0].n_tracks());
  expect_unassociated(file, out);
}

TEST(Associator, DenseAndSparse3DAreTheirPipelines) {
  const TrackFile& file = four_sensor_file();
  PipelineOptions po;
  po.sensors = {file.sensors[0].id, file.sensors[1].id, file.sensors[3].id};
  for (bool sparse : {false, true}) {
    SCOPED_TRACE(sparse ? "sparse" : "dense");
    AssociatorOptions o = request("greedy");
    o.pipeline = po;
    o.sparse = sparse;
    const auto a = make_associator(o);
    ASSERT_EQ(a->path(), sparse ? AssociationPath::kSparse3D : AssociationPath::kDense3D);
    const AssociationOutcome out = a->associate(file);
    AssociationRecord want;
    if (sparse) {
      SparsePipelineOptions sp;
      sp.pipeline = po;
      want = solve_sparse_association(build_sparse_association_problem(file, sp), "greedy",
                                      nlohmann::json::object(), 7, sp);
    } else {
      want =
          solve_association(build_association_problem(file, po), "greedy", nlohmann::json::object(), 7, po);
    }
    expect_same_tuples(out.record, want);
    EXPECT_EQ(out.summary.sensor_ids, po.sensors);
    PreparedThreeSensorProblem prepared;  // run's form: one problem shared by every solver
    if (sparse) {
      SparsePipelineOptions sp;
      sp.pipeline = po;
      prepared.sparse =
          std::make_shared<SparseAssociationProblem>(build_sparse_association_problem(file, sp));
    } else {
      prepared.dense = std::make_shared<AssociationProblem>(build_association_problem(file, po));
    }
    const auto shared = make_three_sensor_associator(o, prepared);
    EXPECT_EQ(shared->path(), a->path());
    expect_same_tuples(shared->associate(file).record, want);
    expect_unassociated(file, out);
  }
}

TEST(Associator, FusionCentreIsRunFuzzyPipelineWithItsSystemTracks) {
  const TrackFile& file = four_sensor_file();
  for (const std::string solver : {"fuzzy", "ftaa"}) {
    SCOPED_TRACE(solver);
    AssociatorOptions o = request(solver);
    o.name = "fc";
    const auto a = make_associator(o);
    ASSERT_EQ(a->path(), AssociationPath::kFusionCentre);
    const AssociationOutcome out = a->associate(file);
    const FuzzyPipelineResult want = run_fuzzy_pipeline(
        file.tracks, file.sensors,
        fuzzy_pipeline_options(parse_enum<FusionMethod>(solver, "--solver"), nlohmann::json::object()), "fc",
        file.measurements ? &*file.measurements : nullptr);
    expect_same_tuples(out.record, want.association);
    ASSERT_TRUE(out.system_tracks.has_value());
    EXPECT_EQ(out.system_tracks->name, "fc");
    EXPECT_EQ(out.system_tracks->track, want.system_tracks.track);
    EXPECT_EQ(out.summary.system_tracks, want.fusion.num_system_tracks);
    expect_unassociated(file, out);
    TrackFile stored = file;
    store_outcome(stored, out);
    store_outcome(stored, out);  // replaces, never duplicates
    EXPECT_EQ(stored.associations.size(), file.associations.size() + 1);
    EXPECT_EQ(stored.system_tracks.size(), file.system_tracks.size() + 1);
  }
}

TEST(Associator, SiameseIsAssociateSiameseTracks) {
  Scenario sc = load_scenario("seed003");
  const TrackFile file = simulation_to_track_file(sc, simulate(sc, 1, 0));
  AssociatorOptions o = request("siamese");
  o.siamese_model = TRACKASSOC_SOURCE_DIR "/data/models/siamese_seed003.h5";
  const auto a = make_associator(o);
  ASSERT_EQ(a->path(), AssociationPath::kSiamese);
  const AssociationOutcome out = a->associate(file);
  const LoadedSiameseModel model = read_siamese_model(o.siamese_model);
  const SiameseTrackFileResult want = associate_siamese_tracks(
      file, model.model, siamese_track_file_options(nlohmann::json::object()), "siamese");
  expect_same_tuples(out.record, want.record);
  EXPECT_EQ(out.record.seed, 7u);
  EXPECT_EQ(out.summary.sensor_ids, (std::vector<int32_t>{0, 1}));
  expect_unassociated(file, out);
}

// Three sensors (ids 10, 20, 30): tracks 1, 2, 3 of sensor 10, 5 and 6 of sensor 20, 7 of
// sensor 30. Tuples (1, 5, −), (2, −, −), (−, 6, 7): track 2 is alone in its tuple and track 3
// in none, so sensor 10 leaves {2, 3} unassociated and sensors 20 and 30 none.
TEST(Associator, UnassociatedTracksOfAHandMadeRecord) {
  TrackFile file;
  for (int32_t id : {10, 20, 30}) {
    Sensor s;
    s.id = id;
    file.sensors.push_back(s);
  }
  file.tracks = TrackTable(StateLayout::kXY_VXVY);
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(4);
  const Eigen::MatrixXd P = Eigen::MatrixXd::Identity(4, 4);
  for (auto [sensor, track] : std::vector<std::pair<int32_t, int32_t>>{
           {10, 1}, {10, 2}, {10, 3}, {20, 5}, {20, 6}, {30, 7}, {10, 3}})
    file.tracks.push_back(sensor, track, 0.0, x, P, -1);
  AssociationRecord rec;
  rec.num_sensors = 3;
  rec.tuples = {1, 5, -1, 2, -1, -1, -1, 6, 7};
  rec.cost = {0, 0, 0};
  const auto u = unassociated_tracks(file, {30, 10, 20}, rec);
  ASSERT_EQ(u.size(), 3u);
  EXPECT_EQ(u[0].sensor_id, 30);
  EXPECT_TRUE(u[0].tracks.empty());
  EXPECT_EQ(u[1].sensor_id, 10);
  EXPECT_EQ(u[1].tracks, (std::vector<int32_t>{2, 3}));
  EXPECT_EQ(u[2].sensor_id, 20);
  EXPECT_TRUE(u[2].tracks.empty());
  rec.tuples = {1, 5, -1, 2, -1, -1, -1, -1, 7};  // 6 and 7 split: both become unassociated
  const auto v = unassociated_tracks(file, {20, 30}, rec);
  EXPECT_EQ(v[0].tracks, (std::vector<int32_t>{6}));
  EXPECT_EQ(v[1].tracks, (std::vector<int32_t>{7}));
  EXPECT_THROW(unassociated_tracks(file, {40}, rec), InputError);
}

AssociationPath path_of(const std::string& solver, bool sd, bool three_d, bool sparse,
                        std::vector<int32_t> sensors = {}) {
  AssociatorOptions o = request(solver);
  o.sd = sd;
  o.three_d = three_d;
  o.sparse = sparse;
  o.pipeline.sensors = std::move(sensors);
  return choose_association_path(o);
}

std::string error_of(const std::string& solver, bool sd, bool three_d, bool sparse) {
  try {
    path_of(solver, sd, three_d, sparse);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// --common-process-noise on a recorded file (recorded_3s: asynchronous radars, lag-widened
// alignment): its recursion reads each track as a CV filter updated at every common time, which
// these are not, so C = P_a + P_b − P_ab − P_ba stops being positive definite; the error names the
// pair and the time and says what to use instead.
TEST(Associator, TheCommonProcessNoiseRecursionOnRecordedTracksIsRefusedWithTheWayOut) {
  const Scenario sc = load_scenario("recorded_3s");
  const TrackFile f = simulation_to_track_file(sc, simulate(sc, 1, 0));
  AssociatorOptions o;
  o.pipeline.statistic.common_process_noise = 3.0;
  try {
    make_associator(o)->associate(f);
    FAIL() << "a cross-covariance above P_a + P_b was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("is not positive definite for sensor"), std::string::npos) << what;
    EXPECT_NE(what.find("--correlated RHO"), std::string::npos) << what;
  }
  o.pipeline.statistic.common_process_noise = 0.0;  // the correlated form on the same file
  o.pipeline.statistic.correlated = true;
  o.pipeline.statistic.cross_correlation = 0.3;
  EXPECT_GT(make_associator(o)->associate(f).record.num_tuples(), 0u);
}

// The rules pick stages; the path is the implementation of a combination, and each path runs
// exactly the stages it is the implementation of.
TEST(Associator, TheRulesPickStagesAndEachPathRunsItsOwn) {
  using P = AssociationPath;
  for (P path : {P::kSparseSD, P::kDenseSD, P::kDense3D, P::kSparse3D, P::kFusionCentre, P::kSiamese})
    EXPECT_EQ(plan_of(path).path(), path);
  AssociatorOptions o = request("lr+ls");
  o.pipeline.sensors = {1, 2, 3};  // three --sensors: the default stages, not the 3-D tensor
  AssociationPlan plan = choose_association_plan(o);
  EXPECT_EQ(plan.sensors, SensorRule::kTwoOrMore);
  EXPECT_EQ(plan.pairs, PairSourceStage::kCandidateIndex);
  EXPECT_EQ(plan.partition, PartitionStage::kConnectedComponents);
  EXPECT_EQ(plan.solver, ComponentSolverStage::kSDTensor);
  o.three_d = true;  // --3d: the three-sensor tensor over all pairs, the whole problem
  plan = choose_association_plan(o);
  EXPECT_EQ(plan.sensors, SensorRule::kThree);
  EXPECT_EQ(plan.pairs, PairSourceStage::kAllPairs);
  EXPECT_EQ(plan.partition, PartitionStage::kWholeProblem);
  EXPECT_EQ(plan.solver, ComponentSolverStage::kTensor3D);
  o.three_d = false;
  o.sd = true;  // --sd: the S-D tensor over all pairs
  plan = choose_association_plan(o);
  EXPECT_EQ(plan.pairs, PairSourceStage::kAllPairs);
  EXPECT_EQ(plan.solver, ComponentSolverStage::kSDTensor);
  EXPECT_EQ(plan.describe(),
            "every sensor (or --sensors) -> all pairs -> the whole problem -> S-D tensor with dummies");
  o.sd = false;
  o.solver = "greedy";
  o.sparse = true;  // --sparse: the 3-D tensor over the index's components
  plan = choose_association_plan(o);
  EXPECT_EQ(plan.pairs, PairSourceStage::kCandidateIndex);
  EXPECT_EQ(plan.partition, PartitionStage::kConnectedComponents);
  EXPECT_EQ(plan.solver, ComponentSolverStage::kTensor3D);
}

TEST(Associator, FactoryChoosesThePathsOfAssociate) {
  using P = AssociationPath;
  EXPECT_EQ(path_of("lr+ls", false, false, false), P::kSparseSD);
  EXPECT_EQ(path_of("exact", false, false, false, {1, 2, 3, 4}), P::kSparseSD);
  EXPECT_EQ(path_of("lr", false, false, false, {1, 2}), P::kSparseSD);
  EXPECT_EQ(path_of("lr+ls", false, false, false, {1, 2, 3}), P::kSparseSD);  // --sensors: not the method
  EXPECT_EQ(path_of("lr+ls", false, true, false, {1, 2, 3}), P::kDense3D);
  EXPECT_EQ(path_of("exact", false, true, false), P::kDense3D);
  EXPECT_EQ(path_of("greedy", false, false, false), P::kDense3D);
  EXPECT_EQ(path_of("greedy", false, false, true), P::kSparse3D);
  EXPECT_EQ(path_of("lr", true, false, false), P::kDenseSD);
  EXPECT_EQ(path_of("chnn-pseudo", false, false, false), P::kDenseSD);
  EXPECT_EQ(path_of("lr+ls", false, true, false, {1, 2, 3, 4}), P::kDenseSD);  // > 3 sensors: S-D
  EXPECT_EQ(path_of("fuzzy", false, false, false), P::kFusionCentre);
  EXPECT_EQ(path_of("ftaa", true, false, false), P::kFusionCentre);
  EXPECT_EQ(path_of("siamese", false, false, false), P::kSiamese);
  EXPECT_EQ(path_of("siamese", false, false, false, {0, 1}), P::kSiamese);  // was sent to dense S-D, refused
  EXPECT_EQ(error_of("lr", true, false, true),
            "--sd, --3d and --sparse choose different pipelines: give at most one");
  EXPECT_EQ(error_of("fuzzy", false, false, true),
            "--sparse: applies to the 3-D assignment solvers, not to 'fuzzy'");
  EXPECT_NE(error_of("greedy", true, false, false).find("is not an S-D solver"), std::string::npos);
  EXPECT_NE(error_of("no-such-solver", false, false, false).find("no-such-solver"), std::string::npos);
  AssociatorOptions o = request("siamese");
  o.siamese_model = "/nonexistent/model.h5";
  EXPECT_THROW(make_associator(o), InputError);  // the model is read by the factory
}

// `associate` prints the unassociated tracks per sensor: the counts worked out from its output
// file's tuples and /tracks.
class AssociatorCli : public testing_support::CliFixture {};

TEST_F(AssociatorCli, PrintsTheUnassociatedTracksOfEachSensor) {
  ASSERT_EQ(run("simulate --scenario recorded_3s --output " + path("sim.h5")).status, 0);
  for (const std::string flags : {"", "--solver greedy --3d", "--solver fuzzy"}) {
    SCOPED_TRACE(flags);
    const auto r =
        run("associate --input " + path("sim.h5") + " --output " + path("a.h5") + " --name x " + flags);
    ASSERT_EQ(r.status, 0) << r.err;
    const TrackFile out = read_track_file(path("a.h5"));
    const auto rec = std::find_if(out.associations.begin(), out.associations.end(),
                                  [](const AssociationRecord& a) { return a.name == "x"; });
    ASSERT_NE(rec, out.associations.end());
    std::vector<int32_t> ids;
    for (const auto& s : out.sensors) ids.push_back(s.id);
    std::ostringstream want;
    want << "unassociated local tracks:";
    std::size_t total = 0;
    const auto alone = lonely(out, ids, *rec);
    for (std::size_t i = 0; i < ids.size(); ++i) {
      want << (i ? ", " : " ") << "sensor " << ids[i] << " " << alone.at(ids[i]).size();
      total += alone.at(ids[i]).size();
    }
    EXPECT_NE(r.out.find(want.str() + "\n"), std::string::npos) << r.out;
    EXPECT_GT(total, 0u);  // recorded_3s has partial and false tracks: some are left alone
    // /associations/x/unassociated holds the same tracks as (sensor id, track) rows.
    ASSERT_EQ(rec->unassociated.size(), 2 * total);
    for (std::size_t r2 = 0; r2 < total; ++r2) {
      const int32_t sensor = rec->unassociated[2 * r2], track = rec->unassociated[2 * r2 + 1];
      ASSERT_TRUE(alone.count(sensor)) << sensor;
      const auto& tracks = alone.at(sensor);
      EXPECT_TRUE(tracks.count(track)) << sensor << " " << track;
    }
  }
}

// The reader validates /associations/<name>/unassociated: a sensor id not in /sensors, or a track
// that sensor never reported, is an InputError naming the dataset and row; the writer refuses the
// same record before anything is written.
TEST_F(AssociatorCli, ReaderRejectsAnUnassociatedRowOfAnUnknownSensorOrTrack) {
  ASSERT_EQ(run("simulate --scenario recorded_3s --output " + path("sim.h5")).status, 0);
  ASSERT_EQ(run("associate --input " + path("sim.h5") + " --output " + path("a.h5") + " --name x").status, 0);
  const TrackFile file = read_track_file(path("a.h5"));
  const auto& rec = file.associations.back();
  ASSERT_EQ(rec.name, "x");
  ASSERT_GE(rec.unassociated.size(), 2u);
  for (const auto& [row1, want] : std::vector<std::pair<std::array<int32_t, 2>, std::string>>{
           {{999, 0}, "column 0: expected a sensor id of /sensors, found 999"},
           {{rec.unassociated[0], 1 << 30}, "in /tracks/track, found 1073741824"}}) {
    SCOPED_TRACE(want);
    const std::vector<int32_t> rows{rec.unassociated[0], rec.unassociated[1], row1[0], row1[1]};
    TrackFile bad = file;
    bad.associations.back().unassociated = rows;
    EXPECT_THROW(write_track_file(path("refused.h5"), bad), InputError);
    EXPECT_FALSE(std::filesystem::exists(path("refused.h5")));
    std::filesystem::copy_file(path("a.h5"), path("bad.h5"),
                               std::filesystem::copy_options::overwrite_existing);
    test::damage_file(path("bad.h5"), [&](hid_t f) {
      test::put_dataset(f, "/associations/x/unassociated", H5T_STD_I32LE, H5T_NATIVE_INT32, {2, 2},
                        rows.data());
    });
    const std::string e = test::read_error(path("bad.h5"));
    EXPECT_NE(e.find("/associations/x/unassociated: row 1: "), std::string::npos) << e;
    EXPECT_NE(e.find(want), std::string::npos) << e;
  }
}

}  // namespace
}  // namespace trackassoc
