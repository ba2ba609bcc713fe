// trackassoc solve3d --instance FILE --solver NAME [--json] [--time-limit S] [--options JSON]
//                   [--schedule S --restarts R --polish]   (Hopfield solvers)
// Solves one 3-D assignment instance: the text format of benchmarks/3dap (docs/design.md §3) or an HDF5
// cost tensor (io/cost_tensor_file.hpp), and prints the objective, bound, gap and assignment.
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>

#include "engine/cli/association_flags.hpp"
#include "engine/cli/common.hpp"
#include "engine/cli/hopfield_flags.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "io/atomic_file.hpp"
#include "io/cost_tensor_file.hpp"
#include "io/instance_text.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc::cli {
namespace {

// HDF5 files start with the 8-byte signature \211HDF\r\n\032\n (at offset 0 for our writers).
bool looks_like_hdf5(const std::string& path) {
  check_input_file(path, "--instance", "an instance file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the instance file");
  char sig[8] = {};
  in.read(sig, 8);
  return in.gcount() == 8 && std::string(sig, 8) == std::string("\211HDF\r\n\032\n", 8);
}

nlohmann::json number_or_null(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

}  // namespace

void register_solve3d(CLI::App& app) {
  struct Args {
    CommonOptions common;
    std::string instance, solver = "lr+ls", options = "{}";
    bool json = false;
    double time_limit = 0.0;
    HopfieldFlags hopfield;  // merged into --options
  };
  auto args = std::make_shared<Args>();
  std::string solver_help = "Solver:";
  for (const auto& e : solver_registry()) solver_help += " " + e.name;
  auto* cmd = app.add_subcommand(
      "solve3d",
      "Solve one 3-D assignment instance. Input: the text format of benchmarks/3dap (line 1: S = 3; line 2: "
      "n1 n2 n3; then n1*n2*n3 costs, first index slowest), or an HDF5 file with a dataset /cost of shape "
      "n1 x n2 x n3 (any numeric type; optional attribute /cost miss_cost = cost per missing index, default "
      "inf)");
  cmd->add_option("--instance,-i", args->instance, "Instance file (text or HDF5, detected by content)")
      ->required();
  cmd->add_option("--solver", args->solver, solver_help)->capture_default_str();
  cmd->add_flag(
      "--json", args->json,
      "Print one JSON object: objective, lower_bound, gap, abs_gap, feasible, runtime_s, termination, "
      "iterations, assignment (list of 0-based [i, j, k]; -1 = no index of that dimension)");
  std::vector<std::string> timed;  // the 3-D solvers whose capabilities include a time limit
  for (const auto& e : solver_registry())
    if (e.capabilities.time_limit) timed.push_back(e.name);
  cmd->add_option("--time-limit", args->time_limit,
                  "Time limit in seconds for " + list_names(timed) + " (0 = solver default)")
      ->check(at_least(0));
  cmd->add_option("--options", args->options,
                  "Solver options as a JSON object, e.g. '{\"step_rule\": \"deflected\"}'")
      ->capture_default_str();
  add_hopfield_flags(cmd, args->hopfield, false);
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    const SolverEntry& solver = find_solver(args->solver);
    nlohmann::json options = parse_solver_options(args->options);
    merge_hopfield_flags(args->hopfield, solver.name, options);
    if (args->time_limit > 0.0) {
      if (!solver.capabilities.time_limit)
        throw InputError("--time-limit: solver '" + solver.name + "' is one-pass and takes no time limit");
      if (options.is_null()) options = nlohmann::json::object();
      options["time_limit_s"] = args->time_limit;
    }
    const CostTensor3 tensor = looks_like_hdf5(args->instance) ? read_cost_tensor_hdf5(args->instance)
                                                               : read_3dap_instance(args->instance);
    const auto t0 = std::chrono::steady_clock::now();
    const Solution3 s = solver.solve(tensor, options, args->common.seed);
    const double runtime = seconds_since(t0);
    const SolverSummary& m = s.summary;
    if (args->json) {
      nlohmann::json out;
      out["instance"] = args->instance;
      out["solver"] = solver.name;
      out["n"] = {tensor.n1, tensor.n2, tensor.n3};
      out["objective"] = number_or_null(m.objective);
      out["lower_bound"] = number_or_null(m.lower_bound);
      out["gap"] = number_or_null(m.gap);
      out["abs_gap"] = number_or_null(m.abs_gap);
      out["feasible"] = m.feasible;
      out["runtime_s"] = runtime;
      out["termination"] = termination_name(m.termination);
      out["iterations"] = m.iterations;
      out["sweeps"] = m.sweeps;
      out["message"] = m.message;  // e.g. a Hopfield solve's raw validity and best restart
      nlohmann::json tuples = nlohmann::json::array();
      for (const Tuple3& t : s.tuples) tuples.push_back({t[0], t[1], t[2]});
      out["assignment"] = std::move(tuples);
      std::cout << out.dump() << "\n";
      return;
    }
    std::cout << "instance    " << args->instance << " (" << tensor.n1 << "x" << tensor.n2 << "x" << tensor.n3
              << ")\n"
              << "solver      " << solver.name << "\n"
              << "objective   " << m.objective << "\n";
    if (!std::isnan(m.lower_bound))
      std::cout << "lower bound " << m.lower_bound << "\n"
                << "gap         " << m.abs_gap << " (" << 100.0 * m.gap << " %)\n";
    std::cout << "feasible    " << (m.feasible ? "yes" : "no") << "\n"
              << "termination " << termination_name(m.termination) << "\n"
              << "iterations  " << m.iterations << "\n"
              << "runtime     " << runtime << " s\n";
    if (!m.message.empty()) std::cout << "note        " << m.message << "\n";
  });
}

}  // namespace trackassoc::cli
