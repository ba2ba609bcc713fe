// The Hopfield flags of the CLI (--schedule, --restarts, --polish, --trace; engine/cli/common.hpp)
// on `associate` and `run`: they reach the solver (its options attribute, the restart table and the
// energy trace in the output file), and a flag given to a solver that is not a Hopfield network is
// a one-line error (exit 2) that writes nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "io/track_file.hpp"
#include "kernels/hopfield/hopfield.hpp"
#include "tests/support/cli_runner.hpp"

namespace trackassoc {
namespace {

using testing_support::CliFixture;

class HopfieldCli : public CliFixture {};

// A command refused as bad input: exit status 2, an error naming `needle`, no `output` written.
void expect_refused(const testing_support::CliResult& r, const std::string& needle,
                    const std::string& output) {
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(output)) << output;
}

const AssociationRecord& record(const TrackFile& f, const std::string& name) {
  for (const auto& r : f.associations)
    if (r.name == name) return r;
  throw std::runtime_error("no association " + name);
}

TEST_F(HopfieldCli, AssociateFlagsReachTheSolverAndTheFile) {
  ASSERT_EQ(run("simulate --output " + path("sim.h5")).status, 0);
  const auto r = run("associate --input " + path("sim.h5") + " --output " + path("out.h5") +
                     " --solver hopfield --schedule diagonal --restarts 3 --polish --trace");
  ASSERT_EQ(r.status, 0) << r.err;
  const TrackFile f = read_track_file(path("out.h5"));
  const AssociationRecord& a = record(f, "hopfield");
  const nlohmann::json o = nlohmann::json::parse(a.options_json).at("solver");
  EXPECT_EQ(o.at("schedule"), "diagonal");
  EXPECT_EQ(o.at("restarts"), 3);
  EXPECT_EQ(o.at("polish"), true);
  EXPECT_EQ(a.restarts.restart.size(), 3u);
  EXPECT_EQ(a.energy_rows, 3);  // one energy trace per restart
  EXPECT_GT(a.energy_cols, 0);
}

TEST_F(HopfieldCli, RunAppliesTheFlagsToEveryHopfieldSolver) {
  const auto r =
      run("run --scenario seed000 --solvers hopfield chnn lr --restarts 2 --schedule sync --output " +
          path("run.h5"));
  ASSERT_EQ(r.status, 0) << r.err;
  const TrackFile f = read_track_file(path("run.h5"));
  EXPECT_EQ(record(f, "hopfield").restarts.restart.size(), 2u);
  EXPECT_EQ(nlohmann::json::parse(record(f, "hopfield").options_json).at("solver").at("schedule"), "sync");
  // On chnn, --schedule sync picks sync Euler steps: still the continuous network (no discrete
  // phase after a mean-field start), which runs at least its gain annealing.
  const RestartTable& chnn = record(f, "chnn").restarts;
  EXPECT_EQ(chnn.restart.size(), 2u);
  for (std::size_t r = 0; r < chnn.restart.size(); ++r) {
    EXPECT_EQ(chnn.mean_field_steps[r], 0);
    EXPECT_GE(chnn.sweeps[r], HopfieldOptions{}.gain_anneal_steps);
  }
  EXPECT_EQ(nlohmann::json::parse(record(f, "lr").options_json).at("solver"), nlohmann::json::object());
}

// Without --solvers, --schedule goes to the Hopfield solvers whose network has it; the others keep
// their own schedule and are named on stderr. Named in --solvers, a solver that cannot take it
// is an error that writes nothing.
TEST_F(HopfieldCli, RunGivesTheScheduleToTheNetworksThatHaveIt) {
  const auto r = run("run --scenario seed000 --schedule diagonal --restarts 2 --output " + path("run.h5"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("not a schedule of hopfield-paper, chnn"), std::string::npos) << r.err;
  const TrackFile f = read_track_file(path("run.h5"));
  EXPECT_EQ(nlohmann::json::parse(record(f, "hopfield").options_json).at("solver").at("schedule"),
            "diagonal");
  for (const char* name : {"hopfield-paper", "chnn"}) {
    const nlohmann::json o = nlohmann::json::parse(record(f, name).options_json).at("solver");
    EXPECT_FALSE(o.contains("schedule")) << name;
    EXPECT_EQ(o.at("restarts"), 2) << name;  // the other flags still apply
  }
  expect_refused(
      run("run --scenario seed000 --solvers chnn lr --schedule diagonal --output " + path("bad.h5")),
      "discrete network", path("bad.h5"));
  expect_refused(run("run --scenario seed000 --schedule zigzag --output " + path("none.h5")), "zigzag",
                 path("none.h5"));
}

TEST_F(HopfieldCli, FlagsForOtherSolversAreOneLineErrorsAndWriteNothing) {
  ASSERT_EQ(run("simulate --output " + path("sim.h5")).status, 0);
  expect_refused(run("associate --input " + path("sim.h5") + " --output " + path("out.h5") +
                     " --solver lr --restarts 3"),
                 "only for hopfield, hopfield-paper and chnn, not 'lr'", path("out.h5"));
  expect_refused(run("run --scenario seed000 --solvers lr exact --polish --output " + path("run.h5")),
                 "no Hopfield solver", path("run.h5"));
  expect_refused(run("associate --input " + path("sim.h5") + " --output " + path("out.h5") +
                     " --solver hopfield --schedule zigzag"),
                 "zigzag", path("out.h5"));
}

}  // namespace
}  // namespace trackassoc
