// Shared pieces of the `trackassoc` subcommands: the options every command has (--seed,
// --threads), the thread-count scope, and the registration hooks of each command file.
#pragma once

#include <oneapi/tbb/global_control.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "io/atomic_file.hpp"

namespace trackassoc::cli {

// The range of a numeric option (issue 15). Every numeric option of the CLI declares its range
// with one of these: --help shows it ("in [0, 1)") and CLI11 refuses a value outside it before the
// command runs, as a usage error (exit 2, "--NAME: expected a value in [0, 1), got -0.5"). NaN and
// ±inf lie outside every range; an integer option still refuses "2.5" by CLI11's conversion.
inline CLI::Validator in_range(double lo, double hi, bool lo_open = false, bool hi_open = false) {
  auto text = [](double v) {
    if (std::isinf(v)) return std::string(v > 0 ? "inf" : "-inf");
    std::ostringstream s;
    s << v;
    return s.str();
  };
  const std::string range =
      std::string(lo_open ? "(" : "[") + text(lo) + ", " + text(hi) + (hi_open || std::isinf(hi) ? ")" : "]");
  return CLI::Validator(
      [=](std::string& input) -> std::string {
        double v = 0;
        const bool number = CLI::detail::lexical_cast(input, v) && std::isfinite(v);
        const bool inside = number && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
        return inside ? std::string() : "expected a value in " + range + ", got " + input;
      },
      "in " + range);
}
inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline CLI::Validator at_least(double lo) { return in_range(lo, kInf); }     // [lo, inf)
inline CLI::Validator above(double lo) { return in_range(lo, kInf, true); }  // (lo, inf)

// --seed: a decimal integer in [0, 2^64-1]. CLI11 itself reads a uint64_t with strtoull, which
// wraps "-1" to 2^64-1, saturates "1e30"-sized digit strings and reads "010" as octal.
inline CLI::Validator seed_range() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        const std::string why = "expected a decimal integer in [0, 18446744073709551615], got " + input;
        if (input.empty() || input.find_first_not_of("0123456789") != std::string::npos) return why;
        errno = 0;
        (void)std::strtoull(input.c_str(), nullptr, 10);
        if (errno == ERANGE) return why;
        input.erase(0, std::min(input.find_first_not_of('0'), input.size() - 1));  // "010" is ten
        return std::string();
      },
      "in [0, 2^64-1]");
}

struct CommonOptions {
  uint64_t seed = 1;
  int threads = 0;  // 0 = all hardware threads
};

// Adds --seed and --threads to a subcommand.
inline void add_common_options(CLI::App* cmd, CommonOptions& common) {
  cmd->add_option("--seed", common.seed, "Random seed; results are bit-identical for any --threads")
      ->transform(seed_range())  // transform: it may rewrite "010" as "10"
      ->capture_default_str();
  cmd->add_option("--threads", common.threads, "Worker threads (0 = all cores)")
      ->check(in_range(0, 1 << 16))
      ->capture_default_str();
}

// Limits oneTBB to `threads` workers for the lifetime of the object (DESIGN §2, Threads).
class ThreadScope {
 public:
  explicit ThreadScope(int threads) {
    if (threads > 0)
      control_ = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                       static_cast<std::size_t>(threads));
  }

 private:
  std::unique_ptr<tbb::global_control> control_;
};

// Adds --output,-o, the one name of every command's output file (or folder).
inline CLI::Option* add_output_option(CLI::App* cmd, std::string& output, const std::string& help) {
  return cmd->add_option("--output,-o", output, help);
}

// Where an `experiment` study writes: its result (--output, a file unless `output_is_folder`) and
// its plots (--plots, a file unless `plots_is_folder`; null when the study draws none), both
// members of the study's shared arguments.
struct StudyPaths {
  std::string* output = nullptr;
  std::string output_help = "HDF5 output";
  bool output_is_folder = false;
  std::string* plots = nullptr;
  std::string plots_help{};
  bool plots_is_folder = false;
};

// The one ending of every `experiment` study (engine/cli/cmd_experiment*.cpp): adds --output,-o,
// --plots and --no-plots (when the study plots), --seed and --threads; the callback limits the
// threads, checks the output paths before any work (io/atomic_file.hpp) and calls
// run(progress, plots): progress is std::cerr when it is a terminal (else null), plots is false
// under --no-plots. `Args` holds `CommonOptions common`.
template <class Args, class Run>
void finish_study_command(CLI::App* cmd, const std::shared_ptr<Args>& args, const StudyPaths& paths,
                          Run run) {
  add_output_option(cmd, *paths.output, paths.output_help)->capture_default_str();
  auto no_plots = std::make_shared<bool>(false);
  if (paths.plots) {
    cmd->add_option("--plots", *paths.plots, paths.plots_help)->capture_default_str();
    cmd->add_flag("--no-plots", *no_plots, "Draw no plots");
  }
  add_common_options(cmd, args->common);
  cmd->callback([args, paths, no_plots, run] {
    ThreadScope threads(args->common.threads);
    std::vector<OutputPath> outputs;  // checked before any work
    if (!paths.output_is_folder) outputs.push_back({*paths.output, "--output"});
    if (paths.plots && !paths.plots_is_folder && !*no_plots) outputs.push_back({*paths.plots, "--plots"});
    check_output_paths(outputs);
    run(isatty(STDERR_FILENO) ? &std::cerr : nullptr, paths.plots && !*no_plots);
  });
}

// The studies whose Options hold `output`, `plot` (an SVG path, "" = none) and `seed` (seed000,
// seed004, schedules, recorded): finish_study_command, then `run(options, progress)` prints the
// table and writes the files, and the command says what was written.
template <class Options>
struct ExperimentArgs {
  Options o;
  CommonOptions common;
};

template <class Options, class Run>
void finish_experiment_command(CLI::App* cmd, const std::shared_ptr<ExperimentArgs<Options>>& args,
                               const std::string& plot_help, Run run) {
  finish_study_command(cmd, args,
                       {.output = &args->o.output, .plots = &args->o.plot, .plots_help = plot_help},
                       [args, run](std::ostream* progress, bool plots) {
                         if (!plots) args->o.plot.clear();
                         args->o.seed = args->common.seed;
                         run(args->o, progress);
                         std::cout << "\nwrote " << args->o.output
                                   << (args->o.plot.empty() ? "" : " and " + args->o.plot) << "\n";
                       });
}

// Each command file engine/cli/cmd_*.cpp defines one of these; main.cpp calls them all.

}  // namespace trackassoc::cli

#include "engine/hopfield_json.hpp"
#include "engine/pipeline.hpp"
#include "io/json_input.hpp"
#include "io/memory_budget.hpp"
#include "kernels/error.hpp"

namespace trackassoc::cli {

// Options of the association pipeline, shared by `associate` and `run`.
struct PipelineFlags {
  PipelineOptions options;
  std::string cost_form = "all-pairs";
  std::string gate_method = "calibrated", alignment = "two-sided";
  double correlated = -1.0;  // < 0: independent errors (not user-reachable: --correlated is in [0, 1))
  std::string solver_options = "{}";
  bool sparse = false;  // engine/sparse_pipeline.hpp instead of the dense tensor
  std::string common_span = "union";
  std::string link_cost = "per-scan";
};

inline void add_pipeline_options(CLI::App* cmd, PipelineFlags& f) {
  cmd->add_option("--sensors", f.options.sensors,
                  "The /sensors ids to associate (default: every sensor of the file); a 3-D solver takes "
                  "exactly three, and refuses a file of more without them")
      ->expected(2, 16);
  cmd->add_option("--gate", f.options.statistic.gate_probability,
                  "Gate probability: the share of true pairs the gate keeps (1 disables gating; the "
                  "default and S-D pipelines need < 1, the gate being the cost of not linking)")
      ->check(in_range(0, 1, true))
      ->capture_default_str();
  cmd->add_option("--gate-method", f.gate_method,
                  "calibrated (capped scan terms, f·χ²(n·D/f), holds 0.99 on filtered tracks) or chi2-sum "
                  "(λ ≤ χ²(n·D), seed 000 as printed; rejects 12-22 % of true pairs on recorded data)")
      ->check(CLI::IsMember({"calibrated", "chi2-sum"}))
      ->capture_default_str();
  cmd->add_option("--alignment", f.alignment,
                  "two-sided (nearest report before or after a common time) or forward (latest report "
                  "predicted forward, seed 000)")
      ->check(CLI::IsMember({"two-sided", "forward"}))
      ->capture_default_str();
  cmd->add_option("--cost-form", f.cost_form,
                  "all-pairs (every pair of sensors in a tuple) or chain (b=λij+λjk, seed 000 Eq. 3; it "
                  "separates into two LAPs, DESIGN §4.3)")
      ->check(CLI::IsMember({"chain", "all-pairs"}))
      ->capture_default_str();
  cmd->add_option("--correlated", f.correlated,
                  "Use the correlated-error statistic (Bar-Shalom–Campo) with cross-correlation RHO")
      ->check(in_range(0, 1, false, true));
  cmd->add_option("--common-period", f.options.common_period,
                  "Step of the common time grid [s] (0 = the largest scan period)")
      ->check(at_least(0))
      ->capture_default_str();
  cmd->add_option("--process-noise", f.options.alignment.process_noise,
                  "White-noise acceleration σ [m/s²] used to predict tracks to common times")
      ->check(at_least(0))
      ->capture_default_str();
  cmd->add_option("--options", f.solver_options, "Solver options as a JSON object, e.g. '{\"restarts\": 8}'")
      ->capture_default_str();
  cmd->add_flag("--sparse", f.sparse,
                "Three-sensor sparse path for the 3-D solvers: gated candidate tuples, connected components "
                "solved in parallel (the default pipeline is sparse already)");
  cmd->add_option("--common-span", f.common_span,
                  "Common times over the union of the sensors' report intervals, or their intersection "
                  "starting one period after the latest first report (seed 000's simulations)")
      ->check(CLI::IsMember({"union", "intersection"}))
      ->capture_default_str();
  cmd->add_option("--link-cost", f.link_cost,
                  "S-D link cost of a gated-in pair: per-scan, (λ − G(n))/n, or per-independent-scan, "
                  "(λ − G(n))/f (seed 004's λ − χ²(n·D) with the chi2-sum gate)")
      ->check(CLI::IsMember({"per-scan", "per-independent-scan"}))
      ->capture_default_str();
  cmd->add_option("--common-process-noise", f.options.statistic.common_process_noise,
                  "Correlated errors from common process noise: the Bar-Shalom–Campo cross-covariance of "
                  "CV Kalman tracks whose targets have white-noise acceleration SIGMA [m/s²] (0 = off)")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
}

// Resolves the string flags into PipelineOptions; throws InputError on bad values.
inline PipelineOptions resolve(PipelineFlags& f) {
  PipelineOptions o = f.options;
  o.cost.form = f.cost_form == "all-pairs" ? CostForm::kAllPairs : CostForm::kChain;
  o.statistic.gate = f.gate_method == "chi2-sum" ? GateMethod::kChiSquareSum : GateMethod::kCalibrated;
  o.alignment.method = f.alignment == "forward" ? AlignmentMethod::kForward : AlignmentMethod::kTwoSided;
  o.span_union = f.common_span == "union";
  o.statistic.link = f.link_cost == "per-scan" ? LinkCost::kPerScan : LinkCost::kPerIndependentScan;
  // The dense tensor's budget: the global --memory-budget (main.cpp) when given, else the smaller
  // of CostTensorOptions' 2 GiB and the default budget; larger track sets need --sparse.
  o.cost.memory_budget_bytes = memory_budget_was_set()
                                   ? memory_budget_bytes()
                                   : std::min(o.cost.memory_budget_bytes, memory_budget_bytes());
  if (f.correlated >= 0.0) {
    o.statistic.correlated = true;
    o.statistic.cross_correlation = f.correlated;
  }
  o.validate();
  return o;
}

// --options text as a JSON object. Bad JSON, and a number the parser cannot hold (1e400: nlohmann's
// out_of_range.406), are input errors naming --options.
inline nlohmann::json parse_solver_options(const std::string& text) {
  auto j = parse_json_input(text, "--options");  // depth limit, duplicate keys (io/json_input.hpp)
  if (!j.is_object())
    throw InputError("--options: expected a JSON object, got '" + text.substr(0, 200) + "'");
  return j;
}

// --schedule, --restarts, --polish and --trace for the Hopfield solvers (hopfield, hopfield-paper,
// chnn), merged into their solver options (engine/hopfield_json.hpp); solve3d, associate and run.
struct HopfieldFlags {
  std::string schedule;
  int restarts = 0;
  bool polish = false, trace = false;
  bool any() const { return !schedule.empty() || restarts > 0 || polish || trace; }
};

// The registry's Hopfield solvers (engine/hopfield_json.hpp presets).
inline constexpr std::array<const char*, 3> kHopfieldSolvers{"hopfield", "hopfield-paper", "chnn"};

inline bool is_hopfield_solver(const std::string& name) {
  return std::find(kHopfieldSolvers.begin(), kHopfieldSolvers.end(), name) != kHopfieldSolvers.end();
}

inline void add_hopfield_flags(CLI::App* cmd, HopfieldFlags& f, bool with_trace) {
  cmd->add_option(
      "--schedule", f.schedule,
      "Hopfield solvers: sync, async or diagonal sweeps (hopfield, hopfield-paper); sync or async "
      "Euler steps (chnn)");
  cmd->add_option("--restarts", f.restarts, "Hopfield solvers: number of restarts")
      ->check(in_range(1, std::numeric_limits<int32_t>::max()));
  cmd->add_flag("--polish", f.polish, "Hopfield solvers: polish every restart by the LAP local search");
  if (with_trace)
    cmd->add_flag(
        "--trace", f.trace,
        "Hopfield solvers: record the energy after every sweep of every restart (/associations/NAME/energy)");
}

// Why Hopfield solver `solver` cannot run `schedule` (its options' own error), or "" if it can.
inline std::string hopfield_schedule_rejection(const std::string& solver, const std::string& schedule) {
  try {
    bool polish = false;
    hopfield_options_from_json(solver, nlohmann::json{{"schedule", schedule}}, polish);
    return "";
  } catch (const InputError& e) {
    return e.what();
  }
}

// Merges the flags into `options` of solver `solver`; an InputError when a flag is given for a
// solver that is not a Hopfield network.
inline void merge_hopfield_flags(const HopfieldFlags& f, const std::string& solver, nlohmann::json& options) {
  if (!f.any()) return;
  if (!is_hopfield_solver(solver))
    throw InputError(
        "--schedule/--restarts/--polish/--trace: only for hopfield, hopfield-paper and chnn, not '" + solver +
        "'");
  if (options.is_null()) options = nlohmann::json::object();
  if (!f.schedule.empty()) options["schedule"] = f.schedule;
  if (f.restarts > 0) options["restarts"] = f.restarts;
  if (f.polish) options["polish"] = true;
  if (f.trace) options["trace"] = true;
}

void register_simulate(CLI::App& app);
void register_associate(CLI::App& app);
void register_evaluate(CLI::App& app);
void register_run(CLI::App& app);
void register_dataset(CLI::App& app);        // cmd_siamese.cpp
void register_train_siamese(CLI::App& app);  // cmd_siamese.cpp
void register_solve3d(CLI::App& app);
void register_filter(CLI::App& app);
void register_import(CLI::App& app);  // cmd_import.cpp
void register_export(CLI::App& app);  // cmd_import.cpp
void register_experiment(CLI::App& app);
void register_autoferry(CLI::App& app);  // cmd_autoferry.cpp: import autoferry, experiment autoferry
// Sub-subcommands of `experiment` (engine/cli/cmd_experiment.cpp calls them).
void register_experiment_seed000(CLI::App& experiment);
void register_experiment_seed004(CLI::App& experiment);
void register_experiment_seed001(CLI::App& experiment);  // cmd_experiment_seed001.cpp
void register_experiment_seed002(CLI::App& experiment);  // cmd_experiment_seed002.cpp
void register_experiment_schedules(CLI::App& experiment);
void register_experiment_scale(CLI::App& experiment);
void register_experiment_recorded(CLI::App& experiment);
void register_experiment_seed003(CLI::App& experiment);  // cmd_siamese_experiment.cpp

}  // namespace trackassoc::cli
