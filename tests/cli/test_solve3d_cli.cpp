// `trackassoc solve3d` end to end: known optima through the CLI, the JSON contract (valid
// assignment, recomputed cost = objective), HDF5 tensor input, and rejection of bad instances.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "engine/solvers/hopfield_json.hpp"
#include "io/cost_tensor_file.hpp"
#include "io/instance_text.hpp"
#include "tests/support/cli_runner.hpp"
#include "tests/support/solver_test_support.hpp"

namespace trackassoc {
namespace {

using namespace testing_support;

class Solve3d : public CliFixture {
 protected:
  // Runs solve3d --json and checks the JSON contract against the instance.
  nlohmann::json solve_json(const std::string& instance, const std::string& solver, const CostTensor3& b) {
    const CliResult r = run("solve3d --instance " + instance + " --solver " + solver + " --json --threads 2");
    EXPECT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    for (const char* key :
         {"objective", "lower_bound", "gap", "feasible", "runtime_s", "termination", "assignment"})
      EXPECT_TRUE(j.contains(key)) << key;
    std::vector<Tuple3> t;
    for (const auto& x : j.at("assignment"))
      t.push_back({x.at(0).get<int32_t>(), x.at(1).get<int32_t>(), x.at(2).get<int32_t>()});
    EXPECT_TRUE(is_valid_assignment(b, t));
    EXPECT_DOUBLE_EQ(assignment_cost(b, t), j.at("objective").get<double>());
    EXPECT_TRUE(j.at("feasible").get<bool>());
    return j;
  }
};

TEST_F(Solve3d, EverySolverOnAKnownInstance) {
  const std::string file = balas_saltzman("bs.10.3.txt");
  const CostTensor3 b = read_3dap_instance(file);
  const double optimum = read_known_optima(balas_saltzman("bs.opt")).at("bs.10.3");
  const auto exact = solve_json(file, "exact", b);
  EXPECT_EQ(exact.at("objective").get<double>(), optimum);
  EXPECT_EQ(exact.at("lower_bound").get<double>(), optimum);
  EXPECT_EQ(exact.at("termination").get<std::string>(), "optimal");
  for (const std::string solver : {"lr", "lr+ls", "greedy", "pairwise", "greedy+ls", "pairwise+ls"}) {
    SCOPED_TRACE(solver);
    const auto j = solve_json(file, solver, b);
    EXPECT_GE(j.at("objective").get<double>(), optimum);
    if (solver.starts_with("lr")) {
      EXPECT_LE(j.at("lower_bound").get<double>(), optimum);
    }
  }
}

// The JSON of a Hopfield solve carries its sweeps and message (raw validity, best restart), the
// same as the library's solve with the same options and seed.
TEST_F(Solve3d, HopfieldJsonCarriesSweepsAndRawValidity) {
  const std::string file = balas_saltzman("bs.10.3.txt");
  const CostTensor3 b = read_3dap_instance(file);
  const CliResult r = run("solve3d -i " + file + " --solver hopfield --restarts 4 --seed 3 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const Solution3 expected = solve_hopfield_json("hopfield", b, nlohmann::json{{"restarts", 4}}, 3);
  EXPECT_EQ(j.at("message").get<std::string>(), expected.summary.message);
  EXPECT_NE(expected.summary.message.find("raw validity"), std::string::npos) << expected.summary.message;
  EXPECT_EQ(j.at("sweeps").get<int64_t>(), expected.summary.sweeps);
  EXPECT_GE(j.at("sweeps").get<int64_t>(), 1);
  EXPECT_EQ(j.at("objective").get<double>(), expected.summary.objective);
}

TEST_F(Solve3d, HumanReadableOutput) {
  const CliResult r = run("solve3d -i " + decomplib("ap3.10.2.txt") + " --solver lr+ls");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("objective   30"), std::string::npos) << r.out;  // ap3.10.2: optimum 30
  EXPECT_NE(r.out.find("lower bound"), std::string::npos);
}

TEST_F(Solve3d, Hdf5CostTensorWithUnequalSizesAndDummies) {
  CostTensor3 b(3, 4, 2);
  for (std::size_t e = 0; e < b.cost.size(); ++e) b.cost[e] = static_cast<float>((e * 7) % 11);
  write_cost_tensor_hdf5(path("t.h5"), b);
  const auto j = solve_json(path("t.h5"), "exact", b);
  EXPECT_NEAR(j.at("objective").get<double>(), brute_force_optimum(b), 1e-6);
  EXPECT_EQ(j.at("assignment").size(), 2u);
  b.miss_cost = 3.f;
  write_cost_tensor_hdf5(path("m.h5"), b);
  EXPECT_EQ(read_cost_tensor_hdf5(path("m.h5")).miss_cost, 3.f);
  const auto m = solve_json(path("m.h5"), "exact", b);
  EXPECT_NEAR(m.at("objective").get<double>(), brute_force_optimum(b), 1e-6);
}

TEST_F(Solve3d, TimeLimitIsPassedAndReported) {
  const CliResult r =
      run("solve3d -i " + balas_saltzman("bs.8.2.txt") + " --solver exact --time-limit 5 --json");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out).at("objective").get<double>(), 32.0);  // bs.8.2 optimum
  const CliResult g = run("solve3d -i " + balas_saltzman("bs.8.2.txt") + " --solver greedy --time-limit 5");
  EXPECT_EQ(g.status, 2);
}

TEST_F(Solve3d, BadInstancesAreRejectedWithOneLine) {
  const std::vector<std::pair<std::string, std::string>> bad{
      {"empty.txt", ""},
      {"garbage.txt", "hello world\n"},
      {"dims.txt", "4\n2 2 2 2\n"},
      {"negative.txt", "3\n2 -2 2\n1 2 3 4\n"},
      {"short.txt", "3\n2 2 2\n1 2 3 4 5 6 7\n"},
      {"nan.txt", "3\n1 1 2\n1 nan\n"},
      {"text_cost.txt", "3\n1 1 2\n1 x\n"},
  };
  for (const auto& [name, text] : bad) {
    SCOPED_TRACE(name);
    const CliResult r = run("solve3d --instance " + write(name, text) + " --solver lr");
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(name), std::string::npos) << r.err;  // names the file
    EXPECT_TRUE(r.out.empty());
  }
  EXPECT_EQ(run("solve3d --instance " + path("missing.txt")).status, 2);
  EXPECT_EQ(run("solve3d --instance " + balas_saltzman("bs.4.1.txt") + " --solver nope").status, 2);
  EXPECT_EQ(run("solve3d --instance " + balas_saltzman("bs.4.1.txt") + " --options '{\"theta\": 5}'").status,
            2);
  EXPECT_EQ(
      run("solve3d --instance " + balas_saltzman("bs.4.1.txt") + " --solver lr --options '{\"bogus\": 1}'")
          .status,
      2);
  // HDF5: a truncated file and a NaN entry.
  const std::string trunc = write("trunc.h5", std::string("\211HDF\r\n\032\n", 8) + "xx");
  EXPECT_EQ(run("solve3d --instance " + trunc).status, 2);
  CostTensor3 nan(2, 2, 2, 1.f);
  nan.cost[5] = std::nanf("");
  // write_cost_tensor_hdf5 stores what it is given; the reader must refuse it.
  write_cost_tensor_hdf5(path("nan.h5"), nan);
  const CliResult r = run("solve3d --instance " + path("nan.h5"));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("/cost[1, 0, 1]"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace trackassoc
