// AssociationSummary's reports (engine/pipeline/associator.hpp): on a hand-made file whose
// components, gated pairs, tuples and unassociated tracks are known from its construction, the
// brief and full reports state those numbers; the record's options attribute holds the same counts
// as the typed summary; and no file of the association path parses options_json back.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "engine/pipeline/associator.hpp"
#include "engine/report/text_table.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

using Eigen::Matrix4d;
using Eigen::Vector4d;

// Three sensors (ids 0, 1, 2) report three targets 50 km apart every second over 0-20 s, each
// exactly at the truth; sensor 2 also holds a fourth track 500 km away from everything. So the
// gated pair graph has 3 components of 3 tracks (one per target, 3 gated pairs each) and the lone
// track's: 4 components, 9 gated pairs, 4 tuples, and only sensor 2's lone track unassociated.
TrackFile three_targets_and_a_stray() {
  TrackFile f;
  f.sensors.resize(3);
  for (int s = 0; s < 3; ++s) f.sensors[s].id = s;
  f.recording.sensors_unknown = "position";
  f.tracks = TrackTable(StateLayout::kXY_VXVY);
  const Matrix4d P = Vector4d(400.0, 400.0, 25.0, 25.0).asDiagonal();
  for (int i = 0; i <= 20; ++i) {
    const double t = i;
    for (int target = 0; target < 3; ++target) {
      const Vector4d x(50000.0 * target + 100.0 * t, 2000.0 - 50.0 * t, 100.0, -50.0);
      for (int s = 0; s < 3; ++s) f.tracks.push_back(s, 10 + target, t, x, P, target);
    }
    f.tracks.push_back(2, 99, t, Vector4d(500000.0, 500000.0 + 10.0 * t, 0.0, 10.0), P, 3);
  }
  return f;
}

TEST(AssociationSummary, ReportsStateTheHandCountedNumbersOfTheDefaultPath) {
  const TrackFile file = three_targets_and_a_stray();
  const AssociationOutcome out = make_associator(AssociatorOptions{})->associate(file);
  const AssociationSummary& s = out.summary;
  EXPECT_EQ(s.path, AssociationPath::kSparseSD);
  EXPECT_EQ(s.components, 4);
  EXPECT_EQ(s.gated_pairs, 9);
  EXPECT_EQ(s.tuples, 4);
  EXPECT_EQ(s.fallback_components, 0);
  EXPECT_EQ(s.unassociated, (std::vector<int64_t>{0, 0, 1}));
  const std::string brief = s.BriefReport(), full = s.FullReport();
  EXPECT_EQ(brief.find('\n'), std::string::npos) << brief;
  EXPECT_EQ(
      brief.rfind("associated the tracks of 3 sensors (sparse S-D, 4 components) with 'lr+ls': objective " +
                      report::fmt(out.record.objective) + ", 4 tuples (" + out.record.termination + "), ",
                  0),
      0u)
      << brief;
  // The full report: the brief line first, then the stages with the counts, then the rest.
  ASSERT_EQ(full.rfind(brief + "\n", 0), 0u) << full;
  // Each component is one tuple or two singletons, so lr+ls proves it optimal: gap 0.
  EXPECT_NE(full.find("gated 9, fallback components 0, largest component gap 0.00 %, segments joined 0 (to 0 "
                      "targets; duplicates 0)\n"),
            std::string::npos)
      << full;
  for (const char* stage : {" alignment ", " candidates ", " statistics ", " components ", " solve ",
                            " segments ", " stitching "})
    EXPECT_NE(full.find(stage), std::string::npos) << stage << " in " << full;
  // Exact reports: the registration (reference: sensor 2, the most tracks) is not significant.
  EXPECT_NE(full.find("registration (reference sensor 2, "), std::string::npos) << full;
  EXPECT_NE(full.find("not significant, reports left as recorded\n"), std::string::npos) << full;
  const std::string last = "unassociated local tracks: sensor 0 0, sensor 1 0, sensor 2 1\n";
  ASSERT_GE(full.size(), last.size());
  EXPECT_EQ(full.substr(full.size() - last.size()), last) << full;
  // The split line appears once a caller sets the split summary (split_recorded_keys).
  AssociationSummary split = s;
  split.split = {5, 2};
  EXPECT_NE(split.FullReport().find("split 2 recycled track number(s) into new local tracks (5 gaps tested;"),
            std::string::npos);
}

TEST(AssociationSummary, TheStoredOptionsHoldTheSummarysCounts) {
  const TrackFile file = three_targets_and_a_stray();
  const AssociationOutcome out = make_associator(AssociatorOptions{})->associate(file);
  const nlohmann::json stored = nlohmann::json::parse(out.record.options_json);
  EXPECT_EQ(stored.at("components").get<int32_t>(), out.summary.components);
  EXPECT_EQ(stored.at("gated_pairs").get<int64_t>(), out.summary.gated_pairs);
  EXPECT_EQ(stored.at("candidate_pairs").get<int64_t>(), out.summary.candidate_pairs);
  EXPECT_EQ(stored.at("fallback_components").get<int64_t>(), out.summary.fallback_components);
  ASSERT_TRUE(out.summary.segments.has_value());
  EXPECT_EQ(stored.at("segments_joined").get<int32_t>(), out.summary.segments->joined);
  EXPECT_FALSE(stored.contains("empty_sensors"));  // every sensor has tracks
}

// Sensor 1's velocities alternate ±5 m/s about the truth on x, as independent errors do and a
// filter's never would: the whiteness ratio of its second differences (kernels/statistics/
// report_whiteness.hpp) is |e|² = 20² over tr(P_v,2 + 4 P_v,1 + P_v,0) = 6·25·2 = 300, relative to
// med(χ²₂)/2 = ln 2: 400/(300 ln 2) = 1.92 ≥ 0.6, so its reports are aligned without the lag terms,
// and the report and the stored options say so. The other sensors' exact reports give 0.
TEST(AssociationSummary, ReportsWithIndependentErrorsAreNamed) {
  TrackFile file = three_targets_and_a_stray();
  for (std::size_t r = 0; r < file.tracks.size(); ++r)
    if (file.tracks.sensor[r] == 1)
      file.tracks.state[2][r] += static_cast<int>(file.tracks.t[r]) % 2 ? 5.0 : -5.0;
  const AssociationOutcome out = make_associator(AssociatorOptions{})->associate(file);
  ASSERT_EQ(out.summary.unfiltered_sensors.size(), 1u);
  EXPECT_EQ(out.summary.unfiltered_sensors[0].sensor, 1);
  EXPECT_NEAR(out.summary.unfiltered_sensors[0].whiteness, 400.0 / (300.0 * std::log(2.0)), 1e-6);
  EXPECT_NE(out.summary.FullReport().find("reports with independent errors (not a filter's output: no "
                                          "manoeuvre-lag widening): sensor 1 (whiteness 1.92)\n"),
            std::string::npos)
      << out.summary.FullReport();
  const nlohmann::json stored = nlohmann::json::parse(out.record.options_json);
  EXPECT_EQ(stored.at("unfiltered_sensors"), nlohmann::json::array({1}));
  EXPECT_EQ(out.summary.tuples, 4);  // the positions are exact: the same association
  // The unmodified file: no sensor named, nothing stored.
  const AssociationOutcome clean =
      make_associator(AssociatorOptions{})->associate(three_targets_and_a_stray());
  EXPECT_TRUE(clean.summary.unfiltered_sensors.empty());
  EXPECT_EQ(clean.summary.FullReport().find("independent errors"), std::string::npos);
  EXPECT_FALSE(nlohmann::json::parse(clean.record.options_json).contains("unfiltered_sensors"));
}

TEST(AssociationSummary, TheDense3DReportCountsTheTracksOfEachSensor) {
  AssociatorOptions o;
  o.solver = "greedy";
  o.three_d = true;
  const AssociationOutcome out = make_associator(o)->associate(three_targets_and_a_stray());
  const std::string brief = out.summary.BriefReport();
  // 3, 3 and 4 local tracks; the three targets' tuples and the stray alone.
  EXPECT_EQ(brief.rfind("associated 3x3x4 tracks with 'greedy': objective ", 0), 0u) << brief;
  EXPECT_NE(brief.find(", 4 tuples ("), std::string::npos) << brief;
  // A dense path is one component, the whole problem; its pair source is every pair of two
  // sensors' tracks: 3·3 + 3·4 + 3·4 = 33, of which the three targets' 3 pairs each are gated.
  const AssociationSummary& s = out.summary;
  EXPECT_EQ(s.components, 1);
  EXPECT_EQ(s.candidate_pairs, 33);
  EXPECT_EQ(s.gated_pairs, 9);
  std::vector<std::string> names;
  for (const StageReport& st : s.stages) names.push_back(st.name);
  EXPECT_EQ(names, (std::vector<std::string>{"alignment", "statistics", "tensor", "solve"}));
  // The record's time is the path's: every stage's.
  double total = 0.0;
  for (const StageReport& st : s.stages) total += st.seconds;
  EXPECT_NEAR(out.record.runtime_s, total, 1e-12);
  const std::string full = s.FullReport();
  ASSERT_EQ(full.rfind(brief + "\npipeline: three sensors -> all pairs -> the whole problem -> 3-D tensor\n"
                               "stages: alignment ",
                       0),
            0u)
      << full;
  EXPECT_NE(full.find("; solve "), std::string::npos) << full;
  EXPECT_NE(full.find(" ms; candidate pairs 33, gated 9\npeak memory (resident, at the end of each stage): "
                      "alignment "),
            std::string::npos)
      << full;
  EXPECT_NE(full.find("\nunassociated local tracks: sensor 0 0, sensor 1 0, sensor 2 1\n"), std::string::npos)
      << full;
}

// The pair source and the partition are stages: every tensor path sees the same gate, so the same
// 9 gated pairs; the partition is the whole problem (dense) or the 4 components of the gated pair
// graph (the three targets and the stray, sparse).
TEST(AssociationSummary, EveryTensorPathReportsTheSameGatedPairsAndItsPartition) {
  const TrackFile file = three_targets_and_a_stray();
  struct Case {
    const char* what;
    AssociatorOptions o;
    int32_t components;
    int64_t candidate_pairs;
  };
  AssociatorOptions sd, dense, sparse;
  sd.sd = true;
  dense.three_d = true;
  sparse.sparse = true;
  for (const Case& c : {Case{"default", AssociatorOptions{}, 4, -1}, Case{"--sd", sd, 1, 33},
                        Case{"--3d", dense, 1, 33}, Case{"--sparse", sparse, 4, -1}}) {
    const AssociationSummary s = make_associator(c.o)->associate(file).summary;
    EXPECT_EQ(s.components, c.components) << c.what;
    EXPECT_EQ(s.gated_pairs, 9) << c.what;
    // The index finds at least the gated pairs and never the far stray: at most the 9 pairs of the
    // targets (sensor pairs of tracks 50 km apart are outside any scan's bound).
    if (c.candidate_pairs >= 0)
      EXPECT_EQ(s.candidate_pairs, c.candidate_pairs) << c.what;
    else
      EXPECT_EQ(s.candidate_pairs, 9) << c.what;
    EXPECT_TRUE(std::any_of(s.stages.begin(), s.stages.end(), [](const StageReport& st) {
      return st.name == "solve";
    })) << c.what;
  }
}

TEST(AssociationSummary, TheSparsePathOptionsAreAssociatorOptionsFields) {
  // The default path: a target's component of one track per sensor is a sub-tensor of
  // (1 + 1)^3 = 8 entries, the stray's (1 + 1) = 2. Below 8, the three targets' components are
  // solved over their listed tuples (engine/pipeline/sparse_sd_tuples.hpp), the stray's is not;
  // none falls back to LAP merging.
  AssociatorOptions o;
  o.max_component_entries = 7;
  const AssociationSummary listed = make_associator(o)->associate(three_targets_and_a_stray()).summary;
  EXPECT_EQ(listed.listed_components, 3);
  EXPECT_EQ(listed.fallback_components, 0);
  o.max_component_entries = 8;
  EXPECT_EQ(make_associator(o)->associate(three_targets_and_a_stray()).summary.listed_components, 0);
  // --sparse with a finite miss cost (the solvers' dummy index): the same four components.
  o.solver = "greedy";
  o.sparse = true;
  o.miss_cost = 5.0f;
  EXPECT_EQ(make_associator(o)->associate(three_targets_and_a_stray()).summary.components, 4);
  o.radius_scale = 0.5;  // below 1 would lose gated pairs: refused by the request's validation
  EXPECT_THROW(make_associator(o), InputError);
  o.radius_scale = 1.0;
  o.sparse = false;  // the dense tensor has no miss cost: refused, not ignored
  EXPECT_THROW(make_associator(o), InputError);
}

// The association path carries its counts in typed fields: no file of it reads options_json back.
TEST(AssociationSummary, NoFileOfTheAssociationPathParsesTheOptionsAttribute) {
  const std::filesystem::path root = TRACKASSOC_SOURCE_DIR;
  std::vector<std::filesystem::path> files{root / "engine/cli/cmd_associate.cpp",
                                           root / "engine/cli/cmd_run.cpp", root / "engine/python/module.cpp",
                                           root / "engine/jobs/run_job.cpp",
                                           root / "engine/studies/recorded/experiment_recorded.cpp"};
  for (const auto& e : std::filesystem::directory_iterator(root / "engine/pipeline"))
    files.push_back(e.path());
  const std::regex parse(R"(parse\([^;]*options_json)");
  int read = 0;
  for (const auto& path : files) {
    std::ifstream in(path);
    ASSERT_TRUE(in) << path;
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_FALSE(std::regex_search(text.str(), parse)) << path << " parses options_json";
    ++read;
  }
  EXPECT_GT(read, 20);
}

}  // namespace
}  // namespace trackassoc
