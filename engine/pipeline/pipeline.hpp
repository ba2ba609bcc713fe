// The association pipeline for three sensors (docs/design.md §4.3):
//   local tracks → common times → alignment → pairwise statistics λ → cost tensor → 3-D solver
//   → tuples of local track numbers (/associations/<name>/).
//
// Common times (asynchronous sensors): a uniform grid with step `common_period` (default: the
// largest scan period of the three sensors). By default it spans the union of the sensors' report
// intervals, and each track is moved to a grid time from its nearest report on either side
// (kernels/statistics/association_statistic.hpp, two-sided alignment), so recorded tracks that start late or
// end early are compared wherever they coexist. PipelineOptions::paper() gives the paper's
// setting: the interval where all three sensors report, starting one period after the latest first
// report, each track's latest estimate predicted forward (seed 003 notes that this amplifies errors).
//
// Decoding (engine/pipeline/tuple_decoding.hpp): every local track of the three sensors appears in exactly
// one output tuple. A solver tuple whose chained pairs are not all inside the gate is split into
// its gated-in parts; the tracks a solver left unassigned (unequal counts) are paired greedily by
// gated-in λ, so a target that one sensor missed keeps its pair, and the rest stay alone.
#pragma once

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "engine/pipeline/front_end.hpp"
#include "engine/pipeline/stage_report.hpp"
#include "io/track_file.hpp"
#include "kernels/statistics/association_statistic.hpp"
#include "kernels/statistics/cost_tensor.hpp"

namespace trackassoc {

struct PipelineOptions {
  // The sensors to associate, as /sensors ids; empty = the first three in /sensors order for the
  // 3-D pipeline, every sensor for the S-D pipelines.
  std::vector<int32_t> sensors;
  double common_period = 0.0;  // [s]; 0 = the largest scan period of the three sensors
  // Common times span the union of the sensors' report intervals (default: recorded tracks start
  // and end at different times, and a pair is compared wherever both exist), or, when false, the
  // intersection, starting one period after the latest first report (seed 000's simulations).
  bool span_union = true;
  AlignmentOptions alignment;
  StatisticOptions statistic;
  CostTensorOptions cost{
      CostForm::kAllPairs};  // every pair: all the evidence (chain separates, docs/design.md §4.3)
  void validate() const;
  nlohmann::json to_json() const;
  // The settings of the paper studies (seed 000, seed 004, the Hopfield schedules and the sparse
  // scale study): forward prediction at σ = 1 m/s², the
  // intersection grid, and the χ²(n·D) gate of the summed statistic (Eq. 1–2 as printed).
  static PipelineOptions paper();
};

// Everything the solver stage needs, kept so that several solvers can share one tensor: the front
// end's three aligned sensors (engine/pipeline/front_end.hpp), their pair statistics on every pair
// (the dense pair source) and the tensor of the whole problem, its one component (partition.hpp).
struct AssociationProblem : AlignedSensors {
  PairStatistic s12, s23, s13;
  CostTensor3 tensor;
  std::vector<StageReport> stages;  // alignment, statistics, tensor
};

// Checks, before any statistic is computed, that the dense tensor fits
// options.cost.memory_budget_bytes; otherwise throws an InputError naming the sizes and pointing
// to the sparse path (`--sparse`, engine/pipeline/sparse_pipeline.hpp) and to --memory-budget.
void require_dense_tensor_fits(const TrackFile& file, const PipelineOptions& options);

// Builds the problem from a validated track file. Throws InputError when fewer than three sensors
// exist, a chosen sensor is unknown, or the sensors never report at common times.
AssociationProblem build_association_problem(const TrackFile& file, const PipelineOptions& options);

// (Re)builds p.tensor from p's pair statistics for `cost` (its form: chain or all-pairs), so one
// problem serves both forms without recomputing the statistics.
void set_cost_tensor(AssociationProblem& p, const CostTensorOptions& cost);

// A record for /associations/<solver>/ filled from a solver's summary: name = solver = `solver`,
// the seed, objective, bound, gap, termination and run time, and the options attribute
// {"solver": solver_options, "pipeline": pipeline_json} with `extra` merged in. The caller adds
// the tuples.
AssociationRecord record_from_summary(const std::string& solver, int32_t num_sensors, uint64_t seed,
                                      const nlohmann::json& solver_options,
                                      const nlohmann::json& pipeline_json, const SolverSummary& summary,
                                      double runtime_s,
                                      const nlohmann::json& extra = nlohmann::json::object());

// The options attribute of such a record: {"solver": solver_options (null: {}), "pipeline":
// pipeline_json} with `extra` merged in, dumped (keys sorted).
std::string record_options_json(const nlohmann::json& solver_options, const nlohmann::json& pipeline_json,
                                const nlohmann::json& extra = nlohmann::json::object());

// Runs solver `solver` (engine/solvers/solver_registry.hpp) with `solver_options`, decodes the tuples and
// returns the record for /associations/<name>/.
AssociationRecord solve_association(const AssociationProblem& problem, const std::string& solver,
                                    const nlohmann::json& solver_options, uint64_t seed,
                                    const PipelineOptions& options);

// Appends one output row (local track numbers in /sensors columns, −1 = none) holding the members
// of tuple t, with its cost; nothing when no member is present. Shared by the dense and sparse
// decodings.
void append_output_row(const AlignedSensors& sensors, const Tuple3& t, double cost,
                       std::vector<int32_t>& rows, std::vector<double>& costs);

}  // namespace trackassoc
