// `trackassoc associate --sparse` and `run --sparse` end to end: the sparse path writes the same
// /associations/<name>/ tuples as the dense path on small scenarios whose gated components are all
// balanced (engine/pipeline/sparse_pipeline.hpp: the dense tensor's and the sparse padding's treatment of
// unequal counts differ otherwise; then both must still output every local track once), a dense run over
// --memory-budget is refused before any work with a pointer to --sparse, and bad combinations are
// rejected with exit status 2 and no output file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <vector>

#include "engine/pipeline/sparse_pipeline.hpp"
#include "io/track_file.hpp"
#include "tests/support/cli_runner.hpp"

namespace trackassoc {
namespace {

using testing_support::CliFixture;

const AssociationRecord& only_association(const TrackFile& f) {
  EXPECT_EQ(f.associations.size(), 1u);
  return f.associations.front();
}

class AssociateSparseCli : public CliFixture {};

// True when every connected component of the gated candidate graph holds as many tracks of each
// of the three sensors (the condition under which sparse == dense, engine/pipeline/sparse_pipeline.hpp).
bool all_components_balanced(const std::string& file) {
  const SparseAssociationProblem p = build_sparse_association_problem(read_track_file(file), {});
  for (int32_t c = 0; c < p.components.count; ++c) {
    const auto n = component_track_counts(p, c);
    if (n[0] != n[1] || n[1] != n[2]) return false;
  }
  return true;
}

void expect_each_track_once(const AssociationRecord& r) {
  std::set<std::pair<int, int32_t>> seen;
  for (std::size_t k = 0; k < r.num_tuples(); ++k)
    for (int c = 0; c < r.num_sensors; ++c)
      if (const int32_t t = r.tuples[k * r.num_sensors + c]; t >= 0) {
        EXPECT_TRUE(seen.emplace(c, t).second);
      }
}

TEST_F(AssociateSparseCli, SparseAndDenseGiveTheSameAssociation) {
  // The embedded seed 000 scenarios (10 and 20 targets, three radars), three seeds each, two solvers.
  int compared = 0, unbalanced = 0;
  for (const std::string scenario : {"seed000", "seed000_20"})
    for (const std::string seed : {"1", "2", "3"}) {
      const std::string sim = path("sim_" + scenario + seed + ".h5");
      ASSERT_EQ(run("simulate --scenario " + scenario + " --seed " + seed + " --output " + sim).status, 0);
      const bool balanced = all_components_balanced(sim);
      for (const std::string solver : {"pairwise", "exact"}) {
        const std::string dense = path("dense.h5"), sparse = path("sparse.h5");
        // (the default path's family-wise veto off: --sparse holds every pair outside the gate as
        // forbidding, docs/design.md §4.3)
        const auto d = run("associate --no-family-wise-veto --input " + sim + " --output " + dense +
                           " --solver " + solver);
        ASSERT_EQ(d.status, 0) << d.err;
        const auto s =
            run("associate --sparse --input " + sim + " --output " + sparse + " --solver " + solver);
        ASSERT_EQ(s.status, 0) << s.err;
        EXPECT_NE(s.out.find("components"), std::string::npos) << s.out;
        const TrackFile a = read_track_file(dense), b = read_track_file(sparse);
        const AssociationRecord &ra = only_association(a), &rb = only_association(b);
        EXPECT_EQ(ra.name, solver);
        EXPECT_EQ(rb.name, solver);
        EXPECT_EQ(rb.solver, ra.solver);
        EXPECT_EQ(rb.num_sensors, ra.num_sensors);
        EXPECT_TRUE(nlohmann::json::parse(rb.options_json).at("pipeline").value("sparse", false))
            << rb.options_json;
        expect_each_track_once(ra);
        expect_each_track_once(rb);
        if (balanced) {
          EXPECT_EQ(tuple_set(rb), tuple_set(ra)) << scenario << " seed " << seed << " " << solver;
          ++compared;
        } else {
          ++unbalanced;
        }
      }
    }
  EXPECT_GE(compared, 6) << unbalanced << " runs had unbalanced components";
  RecordProperty("compared", compared);
  RecordProperty("unbalanced", unbalanced);
}

TEST_F(AssociateSparseCli, DenseOverTheMemoryBudgetPointsToSparse) {
  // seed 000 with 250 targets for 4 s (3 scans): a 250x250x250 dense tensor of floats is 62.5 MB,
  // while the file's tables (2 250 track reports of 144 bytes, 324 KB), the common time grid and
  // what the program holds beside them once it reads (the HDF5 library's caches: a few MiB) fit a
  // budget of 32 MiB, the global --memory-budget that every reader and stage also checks.
  std::ifstream in(std::string(TRACKASSOC_SOURCE_DIR) + "/data/scenarios/seed000.json");
  nlohmann::json scenario = nlohmann::json::parse(in);
  scenario["duration"] = 4.0;
  scenario["random_targets"]["count"] = 250;
  const std::string json = write("many.json", scenario.dump());
  const std::string sim = path("sim.h5"), out = path("out.h5");
  ASSERT_EQ(run("simulate --scenario " + json + " --output " + sim).status, 0);
  auto r = run("associate --input " + sim + " --output " + out + " --3d --memory-budget 32");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--sparse"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("250x250x250"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  // The same budget is no obstacle to the sparse path (components of a few tracks).
  r = run("associate --sparse --input " + sim + " --output " + out + " --memory-budget 32");
  ASSERT_EQ(r.status, 0) << r.err;
  // Its answer is the dense path's on the same file (the documented equality: every gated component
  // of this file is balanced), computed here without the budget: the same tuples (80 targets, 3
  // radars, P_D = 1: at least 80, each track in one) and the same objective, itself the sum of the
  // tuples' costs when no solver tuple was split at decoding (every tuple has its 3 tracks).
  ASSERT_TRUE(all_components_balanced(sim));
  const std::string dense = path("dense.h5");
  r = run("associate --3d --input " + sim + " --output " + dense);
  ASSERT_EQ(r.status, 0) << r.err;
  const TrackFile sparse_file = read_track_file(out), dense_file = read_track_file(dense);
  const AssociationRecord &rs = only_association(sparse_file), &rd = only_association(dense_file);
  EXPECT_EQ(rs.solver, rd.solver);
  ASSERT_GE(rs.num_tuples(), 250u);
  EXPECT_EQ(rs.num_tuples(), rd.num_tuples());
  expect_each_track_once(rs);
  EXPECT_EQ(tuple_set(rs), tuple_set(rd));
  double sum = 0.0;
  for (double c : rs.cost) sum += c;
  if (rs.num_tuples() == 250u) {
    EXPECT_NEAR(rs.objective, sum, 1e-5 * std::abs(sum));
  }
  EXPECT_NEAR(rs.objective, rd.objective, 1e-5 * std::abs(rd.objective));
  // `run` shares the flags.
  r = run("run --scenario " + json + " --output " + path("run.h5") + " --solvers greedy --memory-budget 32");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--sparse"), std::string::npos) << r.err;
  r = run("run --sparse --scenario " + json + " --output " + path("run.h5") +
          " --solvers greedy,pairwise --memory-budget 32");
  EXPECT_EQ(r.status, 0) << r.err;
  const TrackFile f = read_track_file(path("run.h5"));
  EXPECT_EQ(f.associations.size(), 2u);
}

TEST_F(AssociateSparseCli, BadCombinationsAreRejected) {
  const std::string sim = path("sim.h5"), out = path("out.h5");
  ASSERT_EQ(run("simulate --output " + sim).status, 0);
  auto r = run("associate --sparse --solver fuzzy --input " + sim + " --output " + out);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--sparse"), std::string::npos) << r.err;
  r = run("associate --input " + sim + " --output " + out + " --memory-budget -5");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--memory-budget"), std::string::npos) << r.err;
  // The sparse path needs a gate (its candidates are the gated pairs).
  r = run("associate --sparse --gate 1 --input " + sim + " --output " + out);
  EXPECT_EQ(r.status, 2);
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace trackassoc
