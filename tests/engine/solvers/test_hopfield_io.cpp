// The Hopfield per-restart table in the track file (/associations/<name>/restarts/, issue 5 item 4):
// written by the association pipeline, read back by io/, equal to the restarts of an independent
// solve of the same tensor; inconsistent tables are rejected by the writer and the reader.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "engine/pipeline/pipeline.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "engine/solvers/hopfield_json.hpp"
#include "io/track_file.hpp"
#include "kernels/core/error.hpp"
#include "kernels/hopfield/hopfield.hpp"
#include "tests/support/io_test_files.hpp"

namespace trackassoc {
namespace {

using test::TempDir;

TrackFile seed000_file(int32_t targets) {
  Scenario sc = load_scenario("seed000");
  sc.random_targets.count = targets;
  return simulation_to_track_file(sc, simulate(sc, 5, 0));
}

TEST(HopfieldTrackFile, RestartTableRoundTripsAndMatchesAnIndependentSolve) {
  TempDir dir;
  TrackFile file = seed000_file(8);
  const PipelineOptions po;
  const AssociationProblem p = build_association_problem(file, po);
  for (const char* solver : {"hopfield", "hopfield-paper", "chnn"}) {
    const nlohmann::json options{{"restarts", 5}, {"trace", true}};
    AssociationRecord rec = solve_association(p, solver, options, 3, po);
    ASSERT_EQ(rec.restarts.size(), 5u) << solver;
    file.associations.push_back(rec);

    // The same tensor solved directly: the table rows are its restarts, in order.
    bool polish = false;
    const HopfieldResult r = solve_hopfield(p.tensor, hopfield_options_from_json(solver, options, polish), 3);
    ASSERT_EQ(r.restarts.size(), 5u);
    int32_t valid = 0;
    for (std::size_t i = 0; i < 5; ++i) {
      EXPECT_EQ(rec.restarts.restart[i], static_cast<int32_t>(i));
      EXPECT_EQ(rec.restarts.valid_raw[i], r.restarts[i].raw_feasible ? 1 : 0);
      EXPECT_EQ(rec.restarts.sweeps[i], r.restarts[i].sweeps);
      EXPECT_EQ(rec.restarts.mean_field_steps[i], r.restarts[i].mean_field_steps);
      EXPECT_EQ(rec.restarts.energy[i], r.restarts[i].energy);
      EXPECT_EQ(rec.restarts.objective[i], r.restarts[i].objective);
      EXPECT_EQ(rec.restarts.repaired_objective[i], r.restarts[i].repaired_objective);
      EXPECT_GE(rec.restarts.sweeps[i], 1);
      // repair then (no) polish: the final cost is the repaired cost
      EXPECT_EQ(rec.restarts.objective[i], rec.restarts.repaired_objective[i]);
      valid += rec.restarts.valid_raw[i];
      // the energy trace row of this restart ends at the recorded sweeps
      const float* row = rec.energy.data() + i * rec.energy_cols;
      const auto len = std::find_if(row, row + rec.energy_cols, [](float e) { return std::isnan(e); }) - row;
      EXPECT_EQ(len, rec.restarts.sweeps[i]) << solver;
    }
    EXPECT_DOUBLE_EQ(valid / 5.0, r.raw_validity_rate) << solver;
    // the record's objective is the best restart's (the pipeline re-costs the same tuples)
    EXPECT_EQ(r.solution.summary.objective,
              *std::min_element(rec.restarts.objective.begin(), rec.restarts.objective.end()))
        << solver;
  }
  // A solver without restarts writes no table.
  file.associations.push_back(solve_association(p, "greedy", nlohmann::json::object(), 3, po));
  EXPECT_EQ(file.associations.back().restarts.size(), 0u);

  const std::string path = dir.file("run.h5");
  write_track_file(path, file);
  const TrackFile back = read_track_file(path);
  ASSERT_EQ(back.associations.size(), file.associations.size());
  for (std::size_t a = 0; a < file.associations.size(); ++a) {
    EXPECT_TRUE(back.associations[a].restarts == file.associations[a].restarts) << file.associations[a].name;
  }
}

TEST(HopfieldTrackFile, InconsistentRestartTablesAreInputErrors) {
  TempDir dir;
  TrackFile file = seed000_file(6);
  const PipelineOptions po;
  const AssociationProblem p = build_association_problem(file, po);
  file.associations.push_back(solve_association(p, "hopfield", nlohmann::json{{"restarts", 3}}, 1, po));
  const std::string good = dir.file("good.h5");
  write_track_file(good, file);

  // The writer refuses a table with a short column and leaves no file.
  TrackFile bad = file;
  bad.associations[0].restarts.energy.pop_back();
  const std::string bad_path = dir.file("bad.h5");
  try {
    write_track_file(bad_path, bad);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/associations/hopfield/restarts"), std::string::npos) << e.what();
  }
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"good.h5"});

  // The reader names the damaged dataset.
  test::damage_file(good, [](hid_t f) {
    const double two[2] = {1.0, 2.0};
    test::put_dataset(f, "/associations/hopfield/restarts/objective", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {2},
                      two);
  });
  const std::string err = test::read_error(good);
  EXPECT_NE(err.find("/associations/hopfield/restarts/objective"), std::string::npos) << err;
  test::damage_file(good, [](hid_t f) {
    const double three[3] = {1.0, 2.0, 3.0};
    test::put_dataset(f, "/associations/hopfield/restarts/objective", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {3},
                      three);
    const int32_t bad_flag[3] = {0, 2, 1};
    test::put_dataset(f, "/associations/hopfield/restarts/valid_raw", H5T_STD_I32LE, H5T_NATIVE_INT32, {3},
                      bad_flag);
  });
  const std::string err2 = test::read_error(good);
  EXPECT_NE(err2.find("/associations/hopfield/restarts/valid_raw"), std::string::npos) << err2;
}

}  // namespace
}  // namespace trackassoc
