#include "engine/pipeline/pipeline_sd.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "engine/pipeline/pair_source.hpp"
#include "engine/pipeline/tuple_cost.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {
namespace {

constexpr float kForbidden = std::numeric_limits<float>::infinity();

// Dense tensor from the links, by the one S-D rule (engine/pipeline/tuple_cost.hpp): the link is
// +inf (kForbidden) for a pair that is not gated in.
void fill_tensor(SDProblem& p, CostForm form) {
  const int32_t S = p.S();
  std::vector<int32_t> n(S);
  for (int32_t s = 0; s < S; ++s) n[s] = p.aligned[s].n_tracks();
  p.tensor = CostTensorSD(n, 0.f);
  fill_sd_tensor(
      p.tensor, form == CostForm::kAllPairs,
      [&](int32_t a, int32_t i, int32_t b, int32_t j) {
        const float l = p.link[static_cast<std::size_t>(a) * S + b][static_cast<std::size_t>(i) * n[b] + j];
        return l == kForbidden ? std::numeric_limits<double>::quiet_NaN() : static_cast<double>(l);
      },
      [&](int32_t a, int32_t i, int32_t b, int32_t j) {
        return p.coexist(p.offset[a] + i, p.offset[b] + j);
      });
}

}  // namespace

const std::vector<std::string>& sd_solver_names() {
  static const std::vector<std::string> names = solver_names_with(&SolverCapabilities::sd);
  return names;
}

void require_sd_solver(const std::string& name) {
  require_solver_among(name, sd_solver_names(), "is not an S-D solver; S-D solvers");
}

SDProblem build_sd_problem(const TrackFile& file, const PipelineOptions& options) {
  options.validate();
  require(options.statistic.gate_probability < 1.0, "--gate",
          "the S-D formulation uses the gate as the cost of not linking two tracks; it needs a gate "
          "probability below 1");
  SDProblem p;
  const auto t0 = std::chrono::steady_clock::now();
  static_cast<AlignedSensors&>(p) = align_sensors(file, options, SensorRule::kTwoOrMore);
  p.stages.push_back(stage_since("alignment", t0));
  const auto t_statistics = std::chrono::steady_clock::now();
  const int32_t S = p.S();
  p.pairs.resize(static_cast<std::size_t>(S) * S);
  p.link.resize(p.pairs.size());
  p.gate.assign(p.pairs.size(), 0.0);
  for (int32_t a = 0; a < S; ++a)
    for (int32_t b = a + 1; b < S; ++b) {
      const std::size_t slot = static_cast<std::size_t>(a) * S + b;
      PairStatistic& st = p.pairs[slot] = all_pairs_statistic(p, a, b, options.statistic);
      // The link cost (λ − G(n))/f of kernels/statistics/association_statistic.hpp: ≤ 0 inside the gate.
      const SequentialGate gate(file.tracks.dim(), options.statistic,
                                static_cast<int32_t>(p.common_times.size()));
      auto& link = p.link[slot];
      link.assign(st.lambda.size(), kForbidden);
      int32_t max_scans = 0;
      for (std::size_t e = 0; e < st.lambda.size(); ++e) {
        const int32_t n = st.scans(e, file.tracks.dim());
        max_scans = std::max(max_scans, n);
        if (!st.in_gate[e] || n <= 0) continue;
        link[e] = static_cast<float>(gate.link_cost(st.lambda[e], n));
      }
      p.gate[slot] = max_scans > 0 ? gate.threshold(max_scans) : 1.0;
    }
  p.stages.push_back(stage_since("statistics", t_statistics));
  const auto t1 = std::chrono::steady_clock::now();
  fill_tensor(p, options.cost.form);
  p.stages.push_back(stage_since("tensor", t1, sizeof(float) * double(p.tensor.cost.size()) / 1048576.0));
  return p;
}

SDProblemView sd_problem_view(const SDProblem& p) {
  SDProblemView v;
  for (const AlignedTracks& a : p.aligned) v.tracks.push_back(a.n_tracks());
  v.pairs = p.pairs;
  v.gate = p.gate;
  v.tensor = &p.tensor;
  return v;
}

SolutionSD solve_sd_tensor(const CostTensorSD& tensor, const std::string& solver,
                           const nlohmann::json& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const SolverEntry* entry = lookup_solver(solver);
  if (!entry || !entry->capabilities.sd_tensor)  // throws
    require_solver_among(solver, solver_names_with(&SolverCapabilities::sd_tensor),
                         "takes no cost tensor alone; tensor S-D solvers");
  SolutionSD sol = entry->solve_sd_tensor(tensor, options);
  sol.summary.wall_time_s = seconds_since(t0);
  return sol;
}

SolutionSD solve_sd(const SDProblem& p, const std::string& solver, const nlohmann::json& options,
                    uint64_t seed) {
  require_sd_solver(solver);
  const SolverEntry& entry = *lookup_solver(solver);
  if (entry.capabilities.sd_tensor) return solve_sd_tensor(p.tensor, solver, options);
  const auto t0 = std::chrono::steady_clock::now();
  SolutionSD sol = entry.solve_sd(sd_problem_view(p), options, seed);
  sol.summary.wall_time_s = seconds_since(t0);
  return sol;
}

void append_tuples(const SDProblem& p, const SolutionSD& sol, AssociationRecord& rec) {
  rec.num_sensors = p.file_sensors;
  const int32_t S = p.S();
  for (std::size_t k = 0; k < sol.tuples.size(); k += S) {
    std::vector<int32_t> row(p.file_sensors, kNoTrack);
    for (int32_t s = 0; s < S; ++s)
      if (sol.tuples[k + s] >= 0) row[p.sensor_columns[s]] = p.aligned[s].track[sol.tuples[k + s]];
    rec.tuples.insert(rec.tuples.end(), row.begin(), row.end());
    rec.cost.push_back(p.tensor.at(std::span<const int32_t>(sol.tuples.data() + k, S)));
  }
}

AssociationRecord solve_sd_association(const SDProblem& p, const std::string& solver,
                                       const nlohmann::json& solver_options, uint64_t seed,
                                       const PipelineOptions& options) {
  const SolutionSD sol = solve_sd(p, solver, solver_options, seed);
  AssociationRecord rec =
      record_from_summary(solver, p.file_sensors, seed, solver_options, options.to_json(), sol.summary,
                          sol.summary.wall_time_s, {{"formulation", "S-D with dummies"}});
  append_tuples(p, sol, rec);
  return rec;
}

}  // namespace trackassoc
