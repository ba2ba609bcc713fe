#include "engine/pipeline/sparse_pipeline.hpp"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>

#include "engine/distributed/shard_items.hpp"
#include "engine/pipeline/partition.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/pipeline/tuple_decoding.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {
namespace {

constexpr double kMiB = 1024.0 * 1024.0;

}  // namespace

void SparsePipelineOptions::validate() const {
  pipeline.validate();
  CandidateOptions{pipeline.statistic.gate_probability, radius_scale}.validate();
  require(!std::isnan(miss_cost) && miss_cost >= 0.f, "SparsePipelineOptions.miss_cost",
          "must be >= 0 (+inf: every track assigned), got " + std::to_string(miss_cost));
  require(max_component_entries >= 1, "SparsePipelineOptions.max_component_entries", "must be >= 1");
}

nlohmann::json SparsePipelineOptions::to_json() const {
  nlohmann::json j = pipeline.to_json();
  j["sparse"] = true;
  j["radius_scale"] = radius_scale;
  j["miss_cost"] = std::isinf(miss_cost) ? nlohmann::json("inf") : nlohmann::json(miss_cost);
  j["max_component_entries"] = max_component_entries;
  return j;
}

SparseAssociationProblem build_sparse_association_problem(const TrackFile& file,
                                                          const SparsePipelineOptions& options) {
  options.validate();
  const PipelineOptions& po = options.pipeline;
  // The default path's front half over the three sensors (sparse_sd_pipeline.hpp): the same
  // alignment, candidates, gated pairs and components, and the same memory budget. The 1-3 pairs are
  // needed by the all-pairs cost and, in both forms, by the decoding of partial tuples
  // (engine/pipeline/pipeline.hpp decodes a gated-in 1-3 pair).
  SparseSDOptions front;
  front.pipeline = po;
  front.radius_scale = options.radius_scale;
  front.max_component_entries = options.max_component_entries;
  front.rival_exponent = 0.0;      // (the S-D link costs are not used here,
  front.family_wise_veto = false;  // nor the S-D tuple rule)
  SparseSDProblem half = build_sparse_front_half(file, front, SensorRule::kThree);
  SparseAssociationProblem p;
  static_cast<AlignedSensors&>(p) = std::move(static_cast<AlignedSensors&>(half));
  const std::array<std::pair<int, int>, 3> sensor_pairs{{{0, 1}, {1, 2}, {0, 2}}};
  std::array<SparsePairStatistic*, 3> out{&p.s12, &p.s23, &p.s13};
  for (int q = 0; q < 3; ++q) {
    const std::size_t slot = static_cast<std::size_t>(sensor_pairs[q].first) * 3 + sensor_pairs[q].second;
    p.candidate_pairs[q] = half.candidate_pairs[slot];
    *out[q] = std::move(half.pairs[slot]);
  }
  p.components = std::move(half.components);
  p.stages = std::move(half.stages);
  // G, the dense rule over the matrices the cost form uses (kernels/statistics/cost_tensor.hpp).
  if (po.cost.gated_pair_cost > 0.0) {
    p.gated_pair_cost = po.cost.gated_pair_cost;
  } else {
    double max_lambda = 0.0;
    const int used = po.cost.form == CostForm::kAllPairs ? 3 : 2;
    for (int q = 0; q < used; ++q)
      for (double l : out[q]->lambda)
        if (std::isfinite(l)) max_lambda = std::max(max_lambda, l);
    p.gated_pair_cost = std::min(std::max(10.0 * max_lambda, 1e3), 1e30);
  }
  return p;
}

std::array<int32_t, 3> component_track_counts(const SparseAssociationProblem& p, int32_t c) {
  std::array<int32_t, 3> n{0, 0, 0};
  for (int32_t node : p.components.members(c)) {
    int d = 0;
    while (node >= p.offset[d + 1]) ++d;
    ++n[d];
  }
  return n;
}

namespace {

// A pair's cost in the tensor: float, clamped so that a sum of three stays finite (cost_tensor.cpp).
float pair_cost(double lambda) { return static_cast<float>(std::min(lambda, 1e30)); }

// Gated-in λ of the pair (ia, ib) or NaN.
double gated_lambda(const SparsePairStatistic& s, int32_t ia, int32_t ib) {
  const int64_t q = s.find(ia, ib);
  return q < 0 ? std::numeric_limits<double>::quiet_NaN() : s.lambda[q];
}

// Local index → track row of each sensor of component c.
std::array<std::vector<int32_t>, 3> component_rows(const SparseAssociationProblem& p, int32_t c) {
  std::array<std::vector<int32_t>, 3> rows;
  for (int32_t node : p.components.members(c)) {
    int d = 0;
    while (node >= p.offset[d + 1]) ++d;
    rows[d].push_back(node - p.offset[d]);
  }
  return rows;
}

}  // namespace

SparseComponentMatrices sparse_component_matrices(const SparseAssociationProblem& p, int32_t c,
                                                  const SparsePipelineOptions& o) {
  SparseComponentMatrices m;
  const auto rows = component_rows(p, c);
  for (int d = 0; d < 3; ++d) m.tracks[d] = static_cast<int32_t>(rows[d].size());
  const bool pad = std::isinf(o.miss_cost);
  std::array<int32_t, 3>& n = m.n;
  n = m.tracks;
  if (pad) n.fill(*std::max_element(n.begin(), n.end()));
  const double entries = static_cast<double>(n[0]) * n[1] * n[2];
  if (entries > static_cast<double>(o.max_component_entries))
    throw InputError(
        "sparse association: component " + std::to_string(c) + " holds " + std::to_string(rows[0].size()) +
        "×" + std::to_string(rows[1].size()) + "×" + std::to_string(rows[2].size()) +
        " tracks, a dense sub-tensor of " + std::to_string(static_cast<long long>(entries)) +
        " entries > max_component_entries = " + std::to_string(o.max_component_entries) +
        "; tighten the gate (--gate) or raise the limit (no sparse-capable solver is registered)");
  const double G = p.gated_pair_cost;
  // Pair costs as the dense tensor has them (kernels/statistics/cost_tensor.cpp): float(λ) in the gate,
  // float(G) otherwise (phantoms too).
  auto pair_matrix = [&](const SparsePairStatistic& s, int da, int db) {
    std::vector<float> x(static_cast<std::size_t>(n[da]) * n[db], pair_cost(G));
    for (std::size_t i = 0; i < rows[da].size(); ++i)
      for (std::size_t j = 0; j < rows[db].size(); ++j) {
        const double l = gated_lambda(s, rows[da][i], rows[db][j]);
        if (!std::isnan(l)) x[i * n[db] + j] = pair_cost(l);
      }
    return x;
  };
  m.c12 = pair_matrix(p.s12, 0, 1);
  m.c23 = pair_matrix(p.s23, 1, 2);
  m.all_pairs = o.pipeline.cost.form == CostForm::kAllPairs;
  if (m.all_pairs) m.c13 = pair_matrix(p.s13, 0, 2);
  m.miss_cost = o.miss_cost;
  return m;
}

CostTensor3 sparse_component_tensor(const SparseComponentMatrices& m) {
  const auto& n = m.n;
  const bool all_pairs = m.all_pairs;
  CostTensor3 tensor(n[0], n[1], n[2]);
  tensor.miss_cost = m.miss_cost;
  // Summed in float in the dense tensor's order, so that the costs are bit-identical.
  for (int32_t i = 0; i < n[0]; ++i)
    for (int32_t j = 0; j < n[1]; ++j)
      for (int32_t k = 0; k < n[2]; ++k) {
        const float a = m.c12[static_cast<std::size_t>(i) * n[1] + j],
                    c = m.c23[static_cast<std::size_t>(j) * n[2] + k];
        tensor.at(i, j, k) = all_pairs ? a + c + m.c13[static_cast<std::size_t>(i) * n[2] + k]
                                       : a + c;  // seed 000 Eq. 3: λ_ij + λ_jk
      }
  return tensor;
}

std::vector<int32_t> sparse_component_work(const SparseAssociationProblem& p,
                                           const SparsePipelineOptions& options) {
  // Components of one track need no solver; the others are solved largest first for balance.
  std::vector<int32_t> work;
  for (int32_t c = 0; c < p.components.count; ++c)
    if (p.components.size(c) > 1) work.push_back(c);
  std::stable_sort(work.begin(), work.end(),
                   [&](int32_t x, int32_t y) { return p.components.size(x) > p.components.size(y); });
  // Refuse oversized components before any work (clear error, nothing half done).
  for (int32_t c : work) {
    const auto n = component_track_counts(p, c);
    const double m = std::isinf(options.miss_cost) ? std::pow(*std::max_element(n.begin(), n.end()), 3.0)
                                                   : static_cast<double>(n[0]) * n[1] * n[2];
    if (m > static_cast<double>(options.max_component_entries))
      (void)sparse_component_matrices(p, c, options);
  }
  return work;
}

namespace {

// The decoding of engine/pipeline/tuple_decoding.hpp on track rows, with sparse gate lookups.
struct SparseDecoder {
  const SparseAssociationProblem& p;
  bool all_pairs;
  std::vector<int32_t>& rows;
  std::vector<double>& costs;
  GatedLambda lambda() const {
    return [this](int q, int32_t a, int32_t b) {
      return gated_lambda(q == 0 ? p.s12 : (q == 1 ? p.s23 : p.s13), a, b);
    };
  }
  EmitTuple emit() const {
    return
        [this](const std::array<int32_t, 3>& t, double cost) { append_output_row(p, t, cost, rows, costs); };
  }
  // A tuple kept whole costs what the dense tensor holds for it (float).
  void split(const std::array<int32_t, 3>& t, std::array<std::vector<int32_t>, 3>& left_over) const {
    split_tuple(
        lambda(), t, all_pairs,
        [this](double l12, double l23, double l13) -> double {
          return all_pairs ? pair_cost(l12) + pair_cost(l23) + pair_cost(l13)
                           : pair_cost(l12) + pair_cost(l23);
        },
        emit(), left_over);
  }
};

struct ComponentResult {
  std::vector<int32_t> rows;  // decoded output tuples, S columns
  std::vector<double> costs;
  SolverSummary summary;
};

// A component as it travels (engine/distributed/shard_items.hpp): its seed key and matrices; every
// component of a part shares the solver and its options (JSON text).
struct SparseShardItem {
  uint64_t key = 0;
  SparseComponentMatrices matrices;
};
struct SparseShardHeader {
  std::string solver, options;
};

constexpr auto wire_codec(std::type_identity<SparseShardItem>) {
  return distributed::codec<SparseShardItem>("sparse 3-D work", &SparseShardItem::key,
                                             &SparseShardItem::matrices);
}
constexpr auto wire_codec(std::type_identity<SparseShardHeader>) {
  return distributed::codec<SparseShardHeader>("sparse 3-D shard header", &SparseShardHeader::solver,
                                               &SparseShardHeader::options);
}

constexpr distributed::ItemJob<SparseShardHeader, SparseShardItem, SparseComponentSolution> kSparseComponents{
    "component", "tracks",
    [](const SparseShardItem& x) {
      const auto& t = x.matrices.tracks;
      return static_cast<std::size_t>(t[0] + t[1] + t[2]);
    },
    [](const SparseShardHeader& h, const SparseShardItem& x) {
      Solution3 sol = find_solver(h.solver).solve(sparse_component_tensor(x.matrices),
                                                  nlohmann::json::parse(h.options), x.key);
      return SparseComponentSolution{std::move(sol.tuples), sol.summary};
    }};

}  // namespace

SparseComponentCosts sparse_component_costs(const SparseAssociationProblem& p,
                                            const SparsePipelineOptions& options) {
  SparseComponentCosts plan;
  (void)sparse_component_work(p, options);  // an oversized component is refused as by one process
  const bool pad = std::isinf(options.miss_cost);
  for (int32_t c = 0; c < p.components.count; ++c) {
    if (p.components.size(c) < 2) continue;
    auto n = component_track_counts(p, c);
    if (pad) n.fill(std::max({n[0], n[1], n[2]}));
    plan.component.push_back(c);
    plan.cost.push_back(static_cast<double>(n[0]) * n[1] * n[2]);
  }
  return plan;
}

std::vector<SparseComponentSolution> solve_sparse_components_sharded(
    distributed::Communicator& comm, const SparseAssociationProblem& p, const std::string& solver,
    const nlohmann::json& solver_options, uint64_t seed, const SparsePipelineOptions& options) {
  const SparseComponentCosts plan = sparse_component_costs(p, options);
  auto solved = distributed::shard_items(comm, kSparseComponents, "sparse 3-D components of 2+ tracks",
                                         {solver, solver_options.dump()}, plan.component, plan.cost,
                                         [&](std::size_t k) {
                                           const auto c = static_cast<int32_t>(plan.component[k]);
                                           return SparseShardItem{stream_key(seed, static_cast<uint64_t>(c)),
                                                                  sparse_component_matrices(p, c, options)};
                                         });
  std::vector<SparseComponentSolution> results(p.components.count);
  for (std::size_t k = 0; k < solved.size(); ++k) results[plan.component[k]] = std::move(solved[k]);
  return results;
}

void serve_sparse_components(distributed::Communicator& comm) {
  distributed::serve_items(comm, kSparseComponents);
}

AssociationRecord solve_sparse_association(const SparseAssociationProblem& p, const std::string& solver,
                                           const nlohmann::json& solver_options, uint64_t seed,
                                           const SparsePipelineOptions& options,
                                           std::vector<StageReport>* stages) {
  const SolverEntry& entry = find_solver(solver);
  AssociationRecord rec;
  if (options.ranks && options.ranks->size() > 1) {
    // The components shared out over the ranks (solve_sparse_components_sharded), decoded here.
    options.validate();
    const auto t0 = std::chrono::steady_clock::now();
    const auto solutions =
        solve_sparse_components_sharded(*options.ranks, p, solver, solver_options, seed, options);
    rec = sparse_record_from_solutions(p, solutions, solver, seed, options, t0, stages);
  } else {
    rec = solve_sparse_association(
        p, [&](const CostTensor3& b, uint64_t s) { return entry.solve(b, solver_options, s); }, solver, seed,
        options, stages);
  }
  nlohmann::json opts = {{"solver", solver_options.is_null() ? nlohmann::json::object() : solver_options},
                         {"pipeline", options.to_json()}};
  rec.options_json = opts.dump();
  return rec;
}

std::set<std::vector<int32_t>> tuple_set(const AssociationRecord& record) {
  std::set<std::vector<int32_t>> s;
  for (std::size_t q = 0; q < record.num_tuples(); ++q)
    s.emplace(record.tuples.begin() + q * record.num_sensors,
              record.tuples.begin() + (q + 1) * record.num_sensors);
  return s;
}

AssociationRecord solve_sparse_association(const SparseAssociationProblem& p, const ComponentSolver& solve,
                                           const std::string& solver, uint64_t seed,
                                           const SparsePipelineOptions& options,
                                           std::vector<StageReport>* stages) {
  options.validate();
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<int32_t> work = sparse_component_work(p, options);
  std::vector<SparseComponentSolution> solutions(p.components.count);
  tbb::parallel_for(std::size_t{0}, work.size(), [&](std::size_t w) {
    const int32_t c = work[w];
    Solution3 sol = solve(sparse_component_tensor(sparse_component_matrices(p, c, options)),
                          stream_key(seed, static_cast<uint64_t>(c)));
    solutions[c] = {std::move(sol.tuples), sol.summary};
  });
  return sparse_record_from_solutions(p, solutions, solver, seed, options, t0, stages);
}

AssociationRecord sparse_record_from_solutions(const SparseAssociationProblem& p,
                                               const std::vector<SparseComponentSolution>& solutions,
                                               const std::string& solver, uint64_t seed,
                                               const SparsePipelineOptions& options,
                                               std::chrono::steady_clock::time_point t0,
                                               std::vector<StageReport>* stages) {
  const bool all_pairs = options.pipeline.cost.form == CostForm::kAllPairs;
  const int32_t C = p.components.count;
  std::vector<int32_t> work;
  for (int32_t c = 0; c < C; ++c)
    if (p.components.size(c) > 1) work.push_back(c);
  std::vector<ComponentResult> results(C);
  tbb::parallel_for(std::size_t{0}, work.size(), [&](std::size_t w) {
    const int32_t c = work[w];
    const auto cp_rows = component_rows(p, c);
    const SparseComponentSolution& sol = solutions.at(c);
    ComponentResult& r = results[c];
    r.summary = sol.summary;
    std::array<std::vector<char>, 3> seen;
    for (int d = 0; d < 3; ++d) seen[d].assign(cp_rows[d].size(), 0);
    auto to_rows = [&](const Tuple3& t) {
      std::array<int32_t, 3> rows{kNoTrack, kNoTrack, kNoTrack};
      for (int d = 0; d < 3; ++d)
        if (t[d] >= 0 && t[d] < static_cast<int32_t>(cp_rows[d].size())) {  // phantoms decode as no track
          rows[d] = cp_rows[d][t[d]];
          seen[d][t[d]] = 1;
        }
      return rows;
    };
    const SparseDecoder decoder{p, all_pairs, r.rows, r.costs};
    // Tracks split off and tracks the solver left unassigned (finite miss cost: the solvers return
    // complete tuples only) are paired by gated-in λ.
    std::array<std::vector<int32_t>, 3> leftovers;
    for (const Tuple3& t : sol.tuples) decoder.split(to_rows(t), leftovers);
    for (int d = 0; d < 3; ++d)
      for (std::size_t x = 0; x < cp_rows[d].size(); ++x)
        if (!seen[d][x]) leftovers[d].push_back(cp_rows[d][x]);
    pair_leftovers(decoder.lambda(), leftovers, decoder.emit());
  });

  AssociationRecord rec;
  rec.name = solver;
  rec.num_sensors = p.file_sensors;
  rec.solver = solver;
  rec.seed = seed;
  rec.options_json = nlohmann::json({{"pipeline", options.to_json()}}).dump();
  ComponentTotals totals;  // the partition stage's sums (engine/pipeline/partition.hpp)
  for (int32_t c = 0; c < C; ++c) {
    if (p.components.size(c) == 1) {
      const int32_t node = p.components.members(c)[0];
      int d = 0;
      while (node >= p.offset[d + 1]) ++d;
      std::array<int32_t, 3> rows{kNoTrack, kNoTrack, kNoTrack};
      rows[d] = node - p.offset[d];
      const SparseDecoder decoder{p, all_pairs, rec.tuples, rec.cost};
      std::array<std::vector<int32_t>, 3> alone;
      decoder.split(rows, alone);
      pair_leftovers(decoder.lambda(), alone, decoder.emit());
      continue;
    }
    const ComponentResult& r = results[c];
    rec.tuples.insert(rec.tuples.end(), r.rows.begin(), r.rows.end());
    rec.cost.insert(rec.cost.end(), r.costs.begin(), r.costs.end());
    // Σ component objectives (phantom pairs charged G)
    totals.add(r.summary.objective, r.summary.lower_bound, termination_name(r.summary.termination));
  }
  totals.write_to(rec);
  rec.runtime_s = seconds_since(t0);
  if (stages) {
    std::size_t bytes = rec.tuples.size() * sizeof(int32_t) + rec.cost.size() * sizeof(double);
    stages->push_back({"solve", rec.runtime_s, peak_rss_mib(), static_cast<double>(bytes) / kMiB});
  }
  return rec;
}

}  // namespace trackassoc
