// The flags of the association pipeline (`associate`, `run`): sensors, alignment, gate, cost,
// sparse path and the solver's --options JSON, resolved into PipelineOptions
// (engine/pipeline/pipeline.hpp).
#pragma once

#include <string>
#include <vector>

#include "engine/cli/common.hpp"
#include "engine/pipeline/pipeline.hpp"
#include "io/json_input.hpp"
#include "io/memory_budget.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc::cli {

// Options of the association pipeline, shared by `associate` and `run`.
struct PipelineFlags {
  PipelineOptions options;
  std::string cost_form = "all-pairs";
  std::string gate_method = "calibrated", alignment = "two-sided";
  double correlated = -1.0;  // < 0: independent errors (not user-reachable: --correlated is in [0, 1))
  std::string solver_options = "{}";
  bool sparse = false;  // engine/pipeline/sparse_pipeline.hpp instead of the dense tensor
  std::string common_span = "union";
  std::string link_cost = "per-independent-scan";
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
      ->check(enum_choices<GateMethod>())
      ->capture_default_str();
  cmd->add_option("--alignment", f.alignment,
                  "two-sided (nearest report before or after a common time) or forward (latest report "
                  "predicted forward, seed 000)")
      ->check(enum_choices<AlignmentMethod>())
      ->capture_default_str();
  cmd->add_option("--cost-form", f.cost_form,
                  "all-pairs (every pair of sensors in a tuple) or chain (b=λij+λjk, seed 000 Eq. 3; it "
                  "separates into two LAPs, docs/design.md §4.3)")
      ->check(enum_choices<CostForm>())
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
  cmd->add_option("--extent-sigma", f.options.alignment.extent_sigma,
                  "Reference-point σ [m] per axis added to every pair's position covariance: the offset "
                  "between the points of an extended target that two sensors track, or a residual "
                  "registration bias (0 = point targets)")
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
                  "S-D link cost of a gated-in pair: per-independent-scan, (λ − G(n))/f, the evidence "
                  "growing with the common scans (seed 004's λ − χ²(n·D) with the chi2-sum gate), or "
                  "per-scan, (λ − G(n))/n, the mean per common scan")
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

}  // namespace trackassoc::cli
