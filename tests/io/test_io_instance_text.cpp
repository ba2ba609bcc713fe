// The 3-D assignment instance text reader (io/instance_text.hpp) on real benchmark files, checked
// against values read off the files by hand and against a brute-force optimum, and on each kind
// of malformed input.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <numeric>

#include "io/instance_text.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

const std::string kData = std::string(TRACKASSOC_SOURCE_DIR) + "/data/3dap/";

// Minimum over all pairs of permutations (j = p(i), k = q(i)): the axial 3-D assignment optimum.
double brute_force_optimum(const CostTensor3& b) {
  std::vector<int> p(b.n1), q(b.n1);
  std::iota(p.begin(), p.end(), 0);
  double best = 1e300;
  do {
    std::iota(q.begin(), q.end(), 0);
    do {
      double s = 0;
      for (int i = 0; i < b.n1; ++i) s += b.at(i, p[i], q[i]);
      best = std::min(best, s);
    } while (std::next_permutation(q.begin(), q.end()));
  } while (std::next_permutation(p.begin(), p.end()));
  return best;
}

std::string error_of(const std::string& text, std::size_t max_elements = std::size_t{1} << 28) {
  try {
    parse_3dap_instance(text, "t.txt", max_elements);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(InstanceText, DecompLibAp3_5_1MatchesHandReadValuesAndKnownOptimum) {
  const CostTensor3 b = read_3dap_instance(kData + "ap3.5.1.txt");
  ASSERT_EQ(b.n1, 5);
  ASSERT_EQ(b.n2, 5);
  ASSERT_EQ(b.n3, 5);
  ASSERT_EQ(b.size(), 125u);
  // First lines of the file: 18 15 14 ..., last lines: ... 3 6.
  EXPECT_EQ(b.at(0, 0, 0), 18.f);
  EXPECT_EQ(b.at(0, 0, 1), 15.f);
  EXPECT_EQ(b.at(0, 0, 2), 14.f);
  EXPECT_EQ(b.at(4, 4, 3), 3.f);
  EXPECT_EQ(b.at(4, 4, 4), 6.f);

  const auto optima = read_known_optima(kData + "ap3.opt");
  ASSERT_EQ(optima.size(), 60u);
  EXPECT_EQ(optima.at("ap3.5.1"), 29.0);
  EXPECT_EQ(optima.at("ap3.10.1"), 55.0);  // "ap3.10.1  55": two spaces in the file

  // The .sol tuple, 1-based in the file, sums to the optimum under "first index slowest".
  const Solution3File sol = read_3dap_solution(kData + "ap3.5.1.sol");
  EXPECT_EQ(sol.optimum, 29.0);
  ASSERT_EQ(sol.tuples.size(), 5u);
  EXPECT_EQ(sol.tuples[0], (Tuple3{0, 1, 3}));
  EXPECT_EQ(sol.tuples[4], (Tuple3{4, 3, 1}));
  EXPECT_TRUE(is_valid_assignment(b, sol.tuples));
  EXPECT_EQ(assignment_cost(b, sol.tuples), 29.0);
  EXPECT_EQ(brute_force_optimum(b), 29.0);
}

TEST(InstanceText, BalasSaltzmanBs4_1MatchesHandReadValuesAndKnownOptimum) {
  const CostTensor3 b = read_3dap_instance(kData + "bs.4.1.txt");
  ASSERT_EQ(b.n1, 4);
  EXPECT_EQ(b.at(0, 0, 0), 51.f);
  EXPECT_EQ(b.at(0, 0, 1), 17.f);
  EXPECT_EQ(b.at(3, 3, 2), 57.f);
  EXPECT_EQ(b.at(3, 3, 3), 11.f);
  const auto optima = read_known_optima(kData + "bs.opt");
  EXPECT_EQ(optima.at("bs.4.1"), 46.0);
  EXPECT_EQ(brute_force_optimum(b), 46.0);
}

TEST(InstanceText, AcceptsRectangularRealCostsAndAnyWhitespace) {
  const CostTensor3 b = parse_3dap_instance("3\r\n1 2 3\r\n1.5 -2 3e1\t4\n5 6.25");
  EXPECT_EQ(b.n1, 1);
  EXPECT_EQ(b.n2, 2);
  EXPECT_EQ(b.n3, 3);
  EXPECT_EQ(b.at(0, 0, 0), 1.5f);
  EXPECT_EQ(b.at(0, 0, 1), -2.f);
  EXPECT_EQ(b.at(0, 0, 2), 30.f);
  EXPECT_EQ(b.at(0, 1, 2), 6.25f);
  const CostTensor3 one = parse_3dap_instance("3 1 1 1 7");  // a dimension of size 1 and n = 1
  EXPECT_EQ(one.at(0, 0, 0), 7.f);
}

TEST(InstanceText, RejectsEachMalformedInputWithAClearMessage) {
  auto has = [](const std::string& msg, const std::string& part) {
    return msg.find(part) != std::string::npos && msg.find("t.txt") != std::string::npos;
  };
  EXPECT_PRED2(has, error_of(""), "empty");
  EXPECT_PRED2(has, error_of("  \n\t "), "empty");
  EXPECT_PRED2(has, error_of("4\n2 2 2 2\n"), "only 3-D");
  EXPECT_PRED2(has, error_of("2\n2 2\n1 2 3 4"), "only 3-D");
  EXPECT_PRED2(has, error_of("x\n"), "number of dimensions");
  EXPECT_PRED2(has, error_of("3\n2 -2 2\n"), "n2 must be a positive integer");
  EXPECT_PRED2(has, error_of("3\n2 0 2\n"), "n2 must be positive");
  EXPECT_PRED2(has, error_of("3\n2 2.5 2\n"), "n2");
  EXPECT_PRED2(has, error_of("3\n2 2\n"), "n3");
  EXPECT_PRED2(has, error_of("3\n99999999999 2 2\n"), "too large");
  EXPECT_PRED2(has, error_of("3\n2 2 2\n1 2 3 4 5 6 7"), "too few costs: expected 8");
  EXPECT_PRED2(has, error_of("3\n2 2 2\n1 2 3 4 5 6 7 8 9"), "too many numbers");
  EXPECT_PRED2(has, error_of("3\n1 1 2\n1 abc"), "cost #2 is not a number");
  EXPECT_PRED2(has, error_of("3\n1 1 2\n1 2x"), "not a number");
  EXPECT_PRED2(has, error_of("3\n1 1 2\n1 nan"), "finite");
  EXPECT_PRED2(has, error_of("3\n1 1 2\n1 inf"), "finite");
  EXPECT_PRED2(has, error_of("3\n1 1 2\n1 1e300"), "finite");
  EXPECT_PRED2(has, error_of(std::string("3\n1 1 2\n1 \x01\xff", 11)), "not a number");
  EXPECT_PRED2(has, error_of("3\n100 100 100\n", 1000), "more than the allowed 1000 elements");
  // A huge product must not overflow into a small number.
  EXPECT_PRED2(has, error_of("3\n2147483647 2147483647 2147483647\n"), "more than the allowed");
  EXPECT_PRED2(has, error_of("3\n2 2 2\n1 2 3\n4 5 six"), "line 4");
}

TEST(InstanceText, RejectsMissingFilesAndBadSideFiles) {
  EXPECT_THROW(read_3dap_instance(kData + "no-such-instance.txt"), InputError);
  EXPECT_THROW(read_known_optima(kData + "ap3.5.1.txt"), InputError);  // "3" alone: not 'name value'
  EXPECT_THROW(read_3dap_solution(kData + "ap3.opt"), InputError);     // no OPT line
}

// Every public instance in shared/: it parses, its size matches its name, and each DecompLib .sol
// assignment is valid and costs exactly the optimum listed in ap3.opt.
TEST(InstanceText, EverySharedBenchmarkInstanceParsesAndItsSolutionCostsTheKnownOptimum) {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(TRACKASSOC_SHARED_DIR) / "benchmarks" / "3dap";
  if (!fs::is_directory(root)) GTEST_SKIP() << "no " << root;
  int instances = 0, solutions = 0;
  for (const char* set : {"decomplib", "balas-saltzman"}) {
    const auto optima =
        read_known_optima((root / set / (std::string(set)[0] == 'd' ? "ap3.opt" : "bs.opt")).string());
    for (const auto& [name, optimum] : optima) {
      const fs::path txt = root / set / (name + ".txt");
      const CostTensor3 b = read_3dap_instance(txt.string());
      const int n = std::stoi(name.substr(name.find('.') + 1));  // "ap3.10.1" -> 10, "bs.4.1" -> 4
      EXPECT_EQ(b.n1, n) << name;
      EXPECT_EQ(b.n2, n) << name;
      EXPECT_EQ(b.n3, n) << name;
      ++instances;
      const fs::path sol_path = root / set / (name + ".sol");
      if (!fs::exists(sol_path)) continue;
      const Solution3File sol = read_3dap_solution(sol_path.string());
      EXPECT_EQ(sol.optimum, optimum) << name;
      EXPECT_TRUE(is_valid_assignment(b, sol.tuples)) << name;
      EXPECT_EQ(assignment_cost(b, sol.tuples), optimum) << name;
      ++solutions;
    }
  }
  EXPECT_EQ(instances, 120);
  EXPECT_EQ(solutions, 60);
}

}  // namespace
}  // namespace trackassoc
