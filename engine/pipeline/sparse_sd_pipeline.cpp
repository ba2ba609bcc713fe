// The sparse S-D pipeline; see engine/pipeline/sparse_sd_pipeline.hpp for the formulation.
#include "engine/pipeline/sparse_sd_pipeline.hpp"

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "engine/pipeline/pair_source.hpp"
#include "engine/pipeline/pair_statistics_sharded.hpp"
#include "engine/pipeline/partition.hpp"
#include "engine/pipeline/pipeline_sd.hpp"
#include "engine/pipeline/sparse_sd_components.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "io/memory_budget.hpp"
#include "kernels/assignment/lap.hpp"
#include "kernels/assignment/lap_sparse.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/random.hpp"
#include "kernels/core/stopwatch.hpp"
#include "kernels/statistics/gate_candidates.hpp"

namespace trackassoc {
namespace {

constexpr double kMiB = 1048576.0;

// Bad input: no two tracks of different sensors ever coexist at a common time, so there is
// nothing to associate (a sweep over the tracks' valid intervals, O(N log N + N·S)).
void require_some_overlap(const SparseSDProblem& p) {
  struct Interval {
    int32_t first, last, sensor;
  };
  std::vector<Interval> iv;
  for (int32_t s = 0; s < p.S(); ++s)
    for (int32_t u = p.offset[s]; u < p.offset[s + 1]; ++u)
      if (p.first_valid[u] >= 0) iv.push_back({p.first_valid[u], p.last_valid[u], s});
  std::sort(iv.begin(), iv.end(), [](const Interval& x, const Interval& y) { return x.first < y.first; });
  std::vector<int32_t> max_last(p.S(), -1);
  for (const auto& x : iv) {
    for (int32_t s = 0; s < p.S(); ++s)
      if (s != x.sensor && max_last[s] >= x.first) return;
    max_last[x.sensor] = std::max(max_last[x.sensor], x.last);
  }
  std::string ids;
  for (int32_t id : p.sensor_ids) ids += (ids.empty() ? "" : ", ") + std::to_string(id);
  throw InputError("/tracks: no two local tracks of different sensors (" + ids +
                   ") exist at a common time, so there is nothing to associate");
}

// The record's options attribute beside the request ("solver", "pipeline"): the solve's counts,
// and empty_sensors, unfiltered_sensors and the segment counts only when there are any (issue 30,
// track_segments.hpp).
nlohmann::json record_info(const SparseSDSolveReport& rep, const std::vector<int32_t>& empty_sensors,
                           const std::vector<UnfilteredSensor>& unfiltered, const SegmentSummary* segments) {
  nlohmann::json info = {{"formulation", "sparse S-D with dummies"},
                         {"components", rep.components},
                         {"fallback_components", rep.fallback_components},
                         {"candidate_pairs", rep.candidate_pairs},
                         {"gated_pairs", rep.gated_pairs}};
  if (!empty_sensors.empty()) info["empty_sensors"] = empty_sensors;
  for (const UnfilteredSensor& u : unfiltered) info["unfiltered_sensors"].push_back(u.sensor);
  if (rep.listed_components > 0) {  // only when there are any, so that other records are unchanged
    info["listed_components"] = rep.listed_components;
    info["largest_listed_tuples"] = rep.largest_listed_tuples;
  }
  if (segments) {
    info["segments_joined"] = segments->joined;
    info["segment_duplicates_joined"] = segments->duplicates;
    info["segment_targets_joined"] = segments->targets_joined;
    info["segment_rounds"] = segments->rounds;
  }
  return info;
}

}  // namespace

void SparseSDOptions::validate() const {
  pipeline.validate();
  require(pipeline.statistic.gate_probability < 1.0, "--gate",
          "the S-D formulation uses the gate as the cost of not linking two tracks; it needs a gate "
          "probability below 1");
  require(radius_scale >= 1.0 && std::isfinite(radius_scale), "SparseSDOptions.radius_scale", "must be >= 1");
  require(max_component_entries >= 1, "SparseSDOptions.max_component_entries", "must be >= 1");
  require(rival_exponent >= 0.0 && std::isfinite(rival_exponent), "SparseSDOptions.rival_exponent",
          "expected an exponent >= 0");
  segments.validate();
}

nlohmann::json SparseSDOptions::to_json() const {
  nlohmann::json j = pipeline.to_json();
  j["sparse"] = true;
  j["radius_scale"] = radius_scale;
  j["max_component_entries"] = max_component_entries;
  j["rival_exponent"] = rival_exponent;
  j["family_wise_veto"] = family_wise_veto;
  j["segments"] = segments.to_json();
  return j;
}

const std::vector<std::string>& sparse_sd_solver_names() {
  // The registry's tensor S-D solvers, the pipeline's default (lr+ls) first.
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n = solver_names_with(&SolverCapabilities::sd_tensor);
    const auto it = std::find(n.begin(), n.end(), "lr+ls");
    if (it != n.end()) std::rotate(n.begin(), it, it + 1);
    return n;
  }();
  return names;
}

void require_sparse_sd_solver(const std::string& name) {
  require_solver_among(name, sparse_sd_solver_names(),
                       "is not a solver of the default (sparse S-D) pipeline; its solvers",
                       " (the 3-D solvers run with --solver NAME --3d)");
}

double family_wise_gate_probability(double p, int32_t S) {
  if (S <= 2) return p;
  return 1.0 - (1.0 - p) / (0.5 * static_cast<double>(S) * static_cast<double>(S - 1));
}

namespace {

// Splits the pairs of `st` (gated at the family-wise level) into those inside `gate` (λ ≤ G(n)),
// left in `st`, and the doubtful rest, returned; keep_in_gate keeps each side in order.
SparsePairStatistic split_doubtful_pairs(SparsePairStatistic& st, const SequentialGate& gate, int dim) {
  for (std::size_t q = 0; q < st.size(); ++q) st.in_gate[q] = st.lambda[q] <= gate.threshold(st.dof[q] / dim);
  SparsePairStatistic inside = keep_in_gate(st);
  for (uint8_t& g : st.in_gate) g = !g;
  SparsePairStatistic doubtful = keep_in_gate(st);
  st = std::move(inside);
  return doubtful;
}

}  // namespace

std::vector<double> rival_link_costs(const SparsePairStatistic& st, const AlignedSensors& sensors, int32_t sa,
                                     int32_t sb, const SequentialGate& gate,
                                     const StatisticOptions& statistic, double rival_exponent) {
  const int dim = sensors.dim;
  std::vector<double> link(st.size());
  // Each track's gated partners (pair indices), on either side.
  auto partners = [&](const std::vector<int32_t>& side, int32_t count) {
    std::vector<int32_t> start(static_cast<std::size_t>(count) + 1, 0), list(side.size());
    for (int32_t i : side) ++start[static_cast<std::size_t>(i) + 1];
    for (int32_t i = 0; i < count; ++i) start[i + 1] += start[i];
    std::vector<int32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t q = 0; q < side.size(); ++q)
      list[static_cast<std::size_t>(fill[side[q]]++)] = static_cast<int32_t>(q);
    return std::pair{std::move(start), std::move(list)};
  };
  const auto [start_a, of_a] = partners(st.a, st.n_a);
  const auto [start_b, of_b] = partners(st.b, st.n_b);
  const int32_t oa = sensors.offset[sa], ob = sensors.offset[sb];
  // m of pair q: the rivals that compete at the same time, the partners of one of its tracks that
  // coexist with its other track (the pair itself included).
  auto rivals = [&](std::size_t q) {
    int32_t ma = 0, mb = 0;
    for (int32_t k = start_a[st.a[q]]; k < start_a[st.a[q] + 1]; ++k)
      ma += sensors.coexist(ob + st.b[q], ob + st.b[of_a[k]]) || of_a[k] == static_cast<int32_t>(q);
    for (int32_t k = start_b[st.b[q]]; k < start_b[st.b[q] + 1]; ++k)
      mb += sensors.coexist(oa + st.a[q], oa + st.a[of_b[k]]) || of_b[k] == static_cast<int32_t>(q);
    return std::max(ma, mb);
  };
  // The tightened gates by m, built on demand, and their thresholds G_{p(m)}(n) cached by (m, n).
  std::map<int32_t, SequentialGate> tightened;
  std::map<std::pair<int32_t, int32_t>, double> threshold;  // (m, n) -> G_{p(m)}(n)
  for (std::size_t q = 0; q < st.size(); ++q) {
    const int32_t n = st.dof[q] / dim;
    const int32_t m = rival_exponent == 0.0 || n <= 0 ? 1 : rivals(q);
    if (m <= 1) {
      link[q] = gate.link_cost(st.lambda[q], n);
      continue;
    }
    auto it = threshold.find({m, n});
    if (it == threshold.end()) {
      auto g = tightened.find(m);
      if (g == tightened.end()) {
        StatisticOptions o = statistic;
        o.gate_probability = std::max(
            0.5, 1.0 - (1.0 - statistic.gate_probability) * std::pow(static_cast<double>(m), rival_exponent));
        g = tightened.emplace(m, SequentialGate(dim, o, 0)).first;
      }
      it = threshold.emplace(std::pair{m, n}, g->second.threshold(n)).first;
    }
    link[q] = gate.excess_cost(st.lambda[q] - it->second, n);  // against the tightened threshold
  }
  return link;
}

SparseSDProblem build_sparse_sd_problem(const TrackFile& file, const SparseSDOptions& options) {
  options.validate();
  return build_sparse_front_half(file, options, SensorRule::kTwoOrMore);
}

SparseSDProblem build_sparse_front_half(const TrackFile& file, const SparseSDOptions& options,
                                        SensorRule rule) {
  const PipelineOptions& po = options.pipeline;
  SparseSDProblem p;
  auto stage = [&](const char* name, std::chrono::steady_clock::time_point t0, double bytes) {
    p.stages.push_back(stage_since(name, t0, bytes / kMiB));
  };

  // The memory budget (issues 30, 31; docs/design.md §7): every stage's large allocation is
  // counted against it, with what the input and the stages before still hold (`held`: their
  // count, or the process's resident set above its baseline when that is larger), before it is
  // made: from its size where that is known in advance (the grid and aligned tracks:
  // common_time_grid; the statistics, the components), and buffer by buffer as it grows in the
  // candidate search, whose size is known only once found (an AllocationGauge).
  const auto D = static_cast<double>(file.tracks.dim());
  double held = static_cast<double>(file.tracks.size()) * 8.0 * (4.0 + D + D * (D + 1) / 2);
  auto require_held = [&](double more, const std::string& what) {
    require_memory_beside_held(held, more, what);
  };
  auto pair_name = [&](int32_t a, int32_t b) {
    return "sensors " + std::to_string(p.sensor_ids[a]) + " and " + std::to_string(p.sensor_ids[b]);
  };

  auto t0 = std::chrono::steady_clock::now();
  static_cast<AlignedSensors&>(p) = align_sensors(
      file, po, rule, rule == SensorRule::kThree ? EmptySensors::kRefuse : EmptySensors::kLeaveOut);
  double bytes = 0;
  for (const AlignedTracks& x : p.aligned)
    bytes += static_cast<double>(x.state.size() + x.cov.size()) * sizeof(double) + x.valid.size();
  stage("alignment", t0, bytes);
  held += bytes;
  require_some_overlap(p);
  const int32_t S = p.S();

  const std::size_t slots = static_cast<std::size_t>(S) * S;
  p.pairs.resize(slots);
  p.link.resize(slots);
  p.candidate_pairs.assign(slots, 0);
  t0 = std::chrono::steady_clock::now();
  std::vector<CandidatePairs> cand(slots);
  const double candidates_beside = held_or_resident(held);
  const std::string candidates_what =
      "the candidate search of " + std::to_string(S) + " sensors (" + std::to_string(p.nodes()) +
      " local tracks; the pairs found so far; a wide gate finds many, see --gate)";
  // What the search counts on top of what it started beside, or, when more, the process's
  // resident set now (freed buffers the allocator keeps count too) with the new buffer and, when
  // other threads may be allocating too, one for each as large as the largest granted to a thread
  // (given, maybe not filled yet, so not resident: two threads growing at once each see the
  // other's buffer as free).
  const int threads = std::max(1, oneapi::tbb::this_task_arena::max_concurrency());
  std::atomic<double> largest{0.0};
  AllocationGauge gauge([&](double stage_bytes, double request, bool concurrent) {
    require_memory_beside(candidates_beside, stage_bytes, candidates_what);
    double others = 0.0;
    if (concurrent) {
      double l = largest.load();
      while (request > l && !largest.compare_exchange_weak(l, request)) {
      }
      others = (threads - 1) * std::max(l, request);
    }
    require_memory_beside_held(0.0, request + others, candidates_what);
  });
  // More ranks (docs/mpi.md): rank 0 runs the index alone; each sensor pair's prune and statistic
  // are shared out in the statistics stage (engine/pipeline/pair_statistics_sharded.hpp), so the
  // candidates held here are those found, before the prune.
  const bool sharded = options.ranks && options.ranks->size() > 1;
  // With the family-wise veto the candidates and statistics are those of the family-wise gate (a
  // superset); the gated pairs are then those inside the gate, the others doubtful.
  StatisticOptions searched = po.statistic;
  if (options.family_wise_veto)
    searched.gate_probability = family_wise_gate_probability(po.statistic.gate_probability, S);
  if (sharded) {
    std::vector<const AlignedTracks*> x;
    for (const AlignedTracks& t : p.aligned) x.push_back(&t);
    cand = candidate_pairs_for_gate(x, searched, options.radius_scale, &gauge, &p.candidate_pairs);
  } else {
    std::vector<IndexedCandidates> found = indexed_candidates(p, searched, options.radius_scale, &gauge);
    for (std::size_t slot = 0; slot < slots; ++slot) {
      p.candidate_pairs[slot] = found[slot].found;
      cand[slot] = std::move(found[slot].pairs);
    }
  }
  bytes = 0;
  for (int32_t a = 0; a < S; ++a)
    for (int32_t b = a + 1; b < S; ++b) {
      const std::size_t slot = static_cast<std::size_t>(a) * S + b;
      bytes += cand[slot].size() * 2.0 * sizeof(int32_t);
    }
  held += bytes;
  stage("candidates", t0, bytes);

  t0 = std::chrono::steady_clock::now();
  const SequentialGate gate(p.dim, po.statistic, static_cast<int32_t>(p.common_times.size()));
  std::vector<GatedPairs> gated;
  std::size_t gated_pairs = 0;
  bytes = 0;
  std::vector<PairStatisticsResult> shared;  // more ranks: each slot's pruned count and gated pairs
  if (sharded) shared = gated_statistics_sharded(*options.ranks, p, cand, searched);
  p.doubtful.assign(slots, {});
  p.doubtful_link.assign(slots, {});
  for (int32_t a = 0; a < S; ++a)
    for (int32_t b = a + 1; b < S; ++b) {
      const std::size_t slot = static_cast<std::size_t>(a) * S + b;
      // The statistic of every candidate (SparsePairStatistic: 21 bytes each) and its rows (8 bytes
      // at most each) beside the gated ones kept (21 bytes, at most every one); then, those freed,
      // the link cost and both nodes of each gated one (16 bytes): at most 50 bytes a candidate.
      const std::size_t kept = sharded ? shared[slot].kept : cand[slot].size();
      const auto n = static_cast<double>(kept);
      const auto candidates_held = static_cast<double>(cand[slot].size());  // (more ranks: before the prune)
      require_held(bytes + n * (21.0 + 8.0 + 21.0), "the statistics of the " + std::to_string(kept) +
                                                        " candidate pairs of " + pair_name(a, b));
      p.pairs[slot] =
          sharded ? std::move(shared[slot].gated) : gated_candidate_statistic(p, a, b, cand[slot], searched);
      if (options.family_wise_veto) {
        const SparsePairStatistic& d = p.doubtful[slot] = split_doubtful_pairs(p.pairs[slot], gate, p.dim);
        for (std::size_t q = 0; q < d.size(); ++q)
          p.doubtful_link[slot].push_back(gate.link_cost(d.lambda[q], d.dof[q] / p.dim));
      }
      const SparsePairStatistic& st = p.pairs[slot];
      gated.push_back({a, b, &st});
      gated_pairs += st.size();
      auto& link = p.link[slot];
      link = rival_link_costs(st, p, a, b, gate, po.statistic, options.rival_exponent);
      // The link costs, and the two nodes of each gated pair that the partition's edges take.
      bytes += static_cast<double>(st.bytes() + link.size() * sizeof(double)) + 8.0 * link.size();
      // The candidates, freed above (more ranks: those found, held here before the prune).
      held -= candidates_held * 2 * sizeof(int32_t);
    }
  stage("statistics", t0, bytes);
  held += bytes;

  t0 = std::chrono::steady_clock::now();
  // connected_components: a union-find and the members by component (int32 per node, a few times).
  require_held(4.0 * sizeof(int32_t) * p.nodes(),
               "the connected components of " + std::to_string(p.nodes()) + " local tracks");
  p.components = gated_pair_components(p, gated);
  stage("components", t0, static_cast<double>(p.components.nodes.size() * sizeof(int32_t)));
  held -= 8.0 * static_cast<double>(gated_pairs);  // the edges, freed on return
  p.bytes_held = std::max(held + static_cast<double>(p.components.nodes.size() * sizeof(int32_t)),
                          static_cast<double>(work_resident_bytes()));
  return p;
}

AssociationRecord solve_sparse_sd_association(const SparseSDProblem& p, const std::string& solver,
                                              const nlohmann::json& solver_options, uint64_t seed,
                                              const SparseSDOptions& options, SparseSDSolveReport* report) {
  require_sparse_sd_solver(solver);
  const auto t0 = std::chrono::steady_clock::now();
  const bool all_pairs = options.pipeline.cost.form == CostForm::kAllPairs;
  const int32_t C = p.components.count;
  // One process solves every component in parallel (TBB); more ranks share them out
  // (solve_sd_components_sharded, engine/pipeline/sparse_sd_components.hpp), with the same results.
  std::vector<SDComponentResult> results =
      options.ranks && options.ranks->size() > 1
          ? solve_sd_components_sharded(*options.ranks, p, solver, solver_options, all_pairs,
                                        options.max_component_entries)
          : solve_sd_components(p, solver, solver_options, all_pairs, options.max_component_entries);
  (void)seed;  // lr, lr+ls and exact are deterministic; the seed is recorded for the file

  ComponentTotals totals;  // the partition stage's sums (engine/pipeline/partition.hpp)
  SparseSDSolveReport rep;
  rep.components = C;
  for (const auto& r : results) {
    totals.add(r.objective, r.lower_bound, termination_name(r.termination));  // merging: heuristic, no bound
    rep.fallback_components += r.fallback;
    rep.largest_component_entries = std::max(rep.largest_component_entries, r.entries);
    rep.listed_components += r.listed_tuples > 0;
    rep.largest_listed_tuples = std::max(rep.largest_listed_tuples, r.listed_tuples);
  }
  rep.largest_component_gap = totals.largest_gap;
  rep.components_above_1pct_gap = totals.above_1pct_gap;
  SolverSummary summary;
  summary.message = std::to_string(C) + " components, " + std::to_string(rep.fallback_components) +
                    " by sequential LAP merging";
  if (rep.listed_components > 0)
    summary.message += ", " + std::to_string(rep.listed_components) + " over their listed tuples";
  summary.wall_time_s = seconds_since(t0);
  for (std::size_t slot = 0; slot < p.pairs.size(); ++slot) {
    rep.candidate_pairs += static_cast<int64_t>(p.candidate_pairs[slot]);
    rep.gated_pairs += static_cast<int64_t>(p.pairs[slot].size());
  }
  if (report) *report = rep;

  AssociationRecord rec =
      record_from_summary(solver, p.file_sensors, seed, solver_options, options.to_json(), summary,
                          summary.wall_time_s, record_info(rep, {}, {}, nullptr));
  totals.write_to(rec);
  rec.num_sensors = p.file_sensors;
  // Tuples in a deterministic order: by their nodes, sorted (so by their smallest node first).
  std::vector<std::pair<std::vector<int32_t>, double>> tuples;
  for (auto& r : results)
    for (std::size_t k = 0; k < r.tuples.size(); ++k) {
      std::sort(r.tuples[k].begin(), r.tuples[k].end());
      tuples.emplace_back(std::move(r.tuples[k]), r.costs[k]);
    }
  std::sort(tuples.begin(), tuples.end());
  for (const auto& [t, cost] : tuples) {
    std::vector<int32_t> row(p.file_sensors, kNoTrack);
    for (int32_t u : t) {
      const int32_t s = p.sensor_of(u);
      row[p.sensor_columns[s]] = p.aligned[s].track[u - p.offset[s]];
    }
    rec.tuples.insert(rec.tuples.end(), row.begin(), row.end());
    rec.cost.push_back(cost);
  }
  return rec;
}

AssociationRecord associate_sparse_sd(const TrackFile& file, const std::string& solver,
                                      const nlohmann::json& solver_options, uint64_t seed,
                                      const SparseSDOptions& options, SparseSDReport* report) {
  require_sparse_sd_solver(solver);
  const SparseSDProblem p = build_sparse_sd_problem(file, options);
  if (options.segments.enabled) check_duplicate_sensors(options.segments, p.sensor_ids);
  const auto t0 = std::chrono::steady_clock::now();
  SparseSDReport rep;
  AssociationRecord rec = solve_sparse_sd_association(p, solver, solver_options, seed, options, &rep.solve);
  const double solve_s = seconds_since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  if (options.segments.enabled) {
    rep.segments.emplace();
    rec = join_track_segments(p, file.tracks, rec, options.segments, &*rep.segments);
  }
  rep.unfiltered = unfiltered_sensors(p);
  if (!p.empty_sensor_ids.empty() || !rep.unfiltered.empty() || rep.segments)  // the solve's, with these
    rec.options_json = record_options_json(
        solver_options, options.to_json(),
        record_info(rep.solve, p.empty_sensor_ids, rep.unfiltered, rep.segments ? &*rep.segments : nullptr));
  rep.stages = p.stages;
  rep.stages.push_back({"solve", solve_s, peak_rss_mib(), 0.0});
  if (options.segments.enabled) rep.stages.push_back(stage_since("segments", t1));
  rec.runtime_s = total_seconds(p.stages) + seconds_since(t0);
  rep.sensor_ids = p.sensor_ids;
  rep.empty_sensor_ids = p.empty_sensor_ids;
  if (report) *report = std::move(rep);
  return rec;
}

}  // namespace trackassoc
