// The sparse S-D pipeline; see engine/pipeline/sparse_sd_pipeline.hpp for the formulation.
#include "engine/pipeline/sparse_sd_pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <set>

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
#include "kernels/statistics/scan_candidates.hpp"

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

}  // namespace

void SparseSDOptions::validate() const {
  pipeline.validate();
  require(pipeline.statistic.gate_probability < 1.0, "--gate",
          "the S-D formulation uses the gate as the cost of not linking two tracks; it needs a gate "
          "probability below 1");
  require(radius_scale >= 1.0 && std::isfinite(radius_scale), "SparseSDOptions.radius_scale", "must be >= 1");
  require(max_component_entries >= 1, "SparseSDOptions.max_component_entries", "must be >= 1");
  segments.validate();
}

nlohmann::json SparseSDOptions::to_json() const {
  nlohmann::json j = pipeline.to_json();
  j["sparse"] = true;
  j["radius_scale"] = radius_scale;
  j["max_component_entries"] = max_component_entries;
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
  const auto& names = sparse_sd_solver_names();
  if (std::find(names.begin(), names.end(), name) != names.end()) return;
  std::string known;
  for (const auto& n : names) known += " " + n;
  throw InputError("--solver: '" + name +
                   "' is not a solver of the default (sparse S-D) pipeline; its solvers:" + known +
                   " (the 3-D solvers run with --solver NAME --3d)");
}

SparseSDProblem build_sparse_sd_problem(const TrackFile& file, const SparseSDOptions& options) {
  options.validate();
  const PipelineOptions& po = options.pipeline;
  SparseSDProblem p;
  p.file_sensors = static_cast<int32_t>(file.sensors.size());
  p.dim = file.tracks.dim();
  SDSensorSelection sel = select_sd_sensors(file, po);
  // A sensor with no local tracks (down, or it saw nothing) is associated around: it takes no part
  // in the problem, and its column of the tuples stays -1 (issue 30). Any number of sensors: a
  // tuple holds only the sensors of its component (sd_tuple_cost has no cap).
  const std::set<int32_t> reporting(file.tracks.sensor.begin(), file.tracks.sensor.end());
  for (std::size_t k = 0; k < sel.ids.size(); ++k)
    if (reporting.count(sel.ids[k])) {
      p.sensor_ids.push_back(sel.ids[k]);
      p.sensor_columns.push_back(sel.columns[k]);
    } else {
      p.empty_sensor_ids.push_back(sel.ids[k]);
    }
  if (p.sensor_ids.size() < 2) {
    std::string empty;
    for (int32_t id : p.empty_sensor_ids) empty += (empty.empty() ? "" : ", ") + std::to_string(id);
    throw InputError("/tracks: association needs the local tracks of at least 2 sensors; sensor" +
                     std::string(p.empty_sensor_ids.size() > 1 ? "s " : " ") + empty + " of " +
                     std::to_string(sel.ids.size()) + " ha" + (p.empty_sensor_ids.size() > 1 ? "ve" : "s") +
                     " none");
  }
  const double period = sel.period;
  const int32_t S = p.S();
  auto stage = [&](const char* name, std::chrono::steady_clock::time_point t0, double bytes) {
    p.stages.push_back({name, seconds_since(t0), peak_rss_mib(), bytes / kMiB});
  };

  // The memory budget (issue 30): every stage's large allocation is counted against it, with what
  // the input and the stages before still hold (`held`), before it is made where its size is
  // known in advance (the grid and aligned tracks: common_time_grid; the statistics, the
  // components), and right after the candidate search, whose size is not.
  const auto D = static_cast<double>(file.tracks.dim());
  double held = static_cast<double>(file.tracks.size()) * 8.0 * (4.0 + D + D * (D + 1) / 2);
  auto require_held = [&](double more, const std::string& what) {
    require_memory(bytes_of(held + more, 1), what + " (with " + size_text(bytes_of(held, 1)) +
                                                 " held by the input and the stages before)");
  };
  auto pair_name = [&](int32_t a, int32_t b) {
    return "sensors " + std::to_string(p.sensor_ids[a]) + " and " + std::to_string(p.sensor_ids[b]);
  };

  auto t0 = std::chrono::steady_clock::now();
  p.common_times = common_time_grid(file.tracks, p.sensor_ids, period, po.span_union);
  p.offset.assign(1, 0);
  double bytes = 0;
  for (int32_t s = 0; s < S; ++s) {
    p.aligned.push_back(align_tracks(file.tracks, p.sensor_ids[s], p.common_times, po.alignment));
    const AlignedTracks& x = p.aligned.back();
    p.offset.push_back(p.offset.back() + x.n_tracks());
    bytes += static_cast<double>(x.state.size() + x.cov.size()) * sizeof(double) + x.valid.size();
    for (int32_t i = 0; i < x.n_tracks(); ++i) {
      int32_t first = -1, last = -1;
      for (int32_t k = 0; k < x.n_times; ++k)
        if (x.valid[static_cast<std::size_t>(i) * x.n_times + k]) {
          if (first < 0) first = k;
          last = k;
        }
      p.first_valid.push_back(first);
      p.last_valid.push_back(last);
    }
  }
  stage("alignment", t0, bytes);
  held += bytes;
  require_some_overlap(p);

  const std::size_t slots = static_cast<std::size_t>(S) * S;
  p.pairs.resize(slots);
  p.link.resize(slots);
  p.candidate_pairs.assign(slots, 0);
  t0 = std::chrono::steady_clock::now();
  std::vector<CandidatePairs> cand(slots);
  bytes = 0;
  for (int32_t a = 0; a < S; ++a)
    for (int32_t b = a + 1; b < S; ++b) {
      const std::size_t slot = static_cast<std::size_t>(a) * S + b;
      cand[slot] = candidate_pairs_for_gate(p.aligned[a], p.aligned[b], po.statistic, options.radius_scale);
      p.candidate_pairs[slot] = cand[slot].size();
      cand[slot] = prune_by_position_bound(p.aligned[a], p.aligned[b], cand[slot], po.statistic);
      bytes += cand[slot].size() * 2.0 * sizeof(int32_t);
      require_held(bytes, "the candidate pairs of " + pair_name(a, b) + " (" +
                              std::to_string(p.candidate_pairs[slot]) + " found, " +
                              std::to_string(cand[slot].size()) + " kept; a wide gate, see --gate)");
    }
  held += bytes;
  stage("candidates", t0, bytes);

  t0 = std::chrono::steady_clock::now();
  const SequentialGate gate(p.dim, po.statistic, static_cast<int32_t>(p.common_times.size()));
  std::vector<int32_t> u, v;
  bytes = 0;
  for (int32_t a = 0; a < S; ++a)
    for (int32_t b = a + 1; b < S; ++b) {
      const std::size_t slot = static_cast<std::size_t>(a) * S + b;
      // The statistic of every candidate (SparsePairStatistic: 21 bytes each) before the gate, and
      // the link cost and both nodes of each (at most every) gated one.
      const auto n = static_cast<double>(cand[slot].size());
      require_held(bytes + n * (21.0 + 8.0 + 8.0), "the statistics of the " +
                                                       std::to_string(cand[slot].size()) +
                                                       " candidate pairs of " + pair_name(a, b));
      p.pairs[slot] =
          keep_in_gate(sparse_sequential_statistic(p.aligned[a], p.aligned[b], cand[slot], po.statistic));
      CandidatePairs().a.swap(cand[slot].a);
      CandidatePairs().b.swap(cand[slot].b);
      const SparsePairStatistic& st = p.pairs[slot];
      auto& link = p.link[slot];
      link.resize(st.size());
      for (std::size_t q = 0; q < st.size(); ++q) {
        link[q] = gate.link_cost(st.lambda[q], st.dof[q] / p.dim);
        u.push_back(p.offset[a] + st.a[q]);
        v.push_back(p.offset[b] + st.b[q]);
      }
      bytes += static_cast<double>(st.bytes() + link.size() * sizeof(double)) + 8.0 * link.size();
      held -= n * 2 * sizeof(int32_t);  // the candidates, freed above
    }
  stage("statistics", t0, bytes);
  held += bytes;

  t0 = std::chrono::steady_clock::now();
  // connected_components: a union-find and the members by component (int32 per node, a few times).
  require_held(4.0 * sizeof(int32_t) * p.nodes(),
               "the connected components of " + std::to_string(p.nodes()) + " local tracks");
  p.components = connected_components(p.nodes(), u, v);
  stage("components", t0, static_cast<double>(p.components.nodes.size() * sizeof(int32_t)));
  held -= 8.0 * static_cast<double>(u.size());  // u, v are freed on return
  p.bytes_held = held + static_cast<double>(p.components.nodes.size() * sizeof(int32_t));
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

  SolverSummary summary;
  summary.objective = 0.0;
  summary.feasible = true;
  double bound = 0.0;
  bool all_optimal = true;
  SparseSDSolveReport rep;
  rep.components = C;
  for (const auto& r : results) {
    summary.objective += r.objective;
    bound += r.lower_bound;  // NaN for a fallback component
    all_optimal = all_optimal && r.optimal;
    rep.fallback_components += r.fallback;
    rep.largest_component_entries = std::max(rep.largest_component_entries, r.entries);
  }
  if (std::isfinite(bound)) set_bound_and_gap(summary, bound);
  summary.termination =
      all_optimal ? Termination::kOptimal
                  : (rep.fallback_components > 0 ? Termination::kHeuristic : Termination::kGapTolerance);
  summary.message = std::to_string(C) + " components, " + std::to_string(rep.fallback_components) +
                    " by sequential LAP merging";
  summary.wall_time_s = seconds_since(t0);
  if (report) *report = rep;

  std::size_t candidates = 0, gated = 0;
  for (std::size_t slot = 0; slot < p.pairs.size(); ++slot) {
    candidates += p.candidate_pairs[slot];
    gated += p.pairs[slot].size();
  }
  AssociationRecord rec = record_from_summary(solver, p.file_sensors, seed, solver_options, options.to_json(),
                                              summary, summary.wall_time_s,
                                              {{"formulation", "sparse S-D with dummies"},
                                               {"components", C},
                                               {"fallback_components", rep.fallback_components},
                                               {"candidate_pairs", candidates},
                                               {"gated_pairs", gated}});
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
                                      const SparseSDOptions& options, std::vector<StageReport>* stages) {
  require_sparse_sd_solver(solver);
  const SparseSDProblem p = build_sparse_sd_problem(file, options);
  if (options.segments.enabled) check_duplicate_sensors(options.segments, p.sensor_ids);
  const auto t0 = std::chrono::steady_clock::now();
  AssociationRecord rec = solve_sparse_sd_association(p, solver, solver_options, seed, options);
  if (!p.empty_sensor_ids.empty()) {  // only then: the records of other files are unchanged
    nlohmann::json info = nlohmann::json::parse(rec.options_json);
    info["empty_sensors"] = p.empty_sensor_ids;
    rec.options_json = info.dump();
  }
  const double solve_s = seconds_since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  if (options.segments.enabled) {
    SegmentSummary seg;
    rec = join_track_segments(p, file.tracks, rec, options.segments, &seg);
    nlohmann::json info = nlohmann::json::parse(rec.options_json);
    info["segments_joined"] = seg.joined;
    info["segment_duplicates_joined"] = seg.duplicates;
    info["segment_targets_joined"] = seg.targets_joined;
    info["segment_rounds"] = seg.rounds;
    rec.options_json = info.dump();
  }
  if (stages) {
    *stages = p.stages;
    stages->push_back({"solve", solve_s, peak_rss_mib(), 0.0});
    if (options.segments.enabled) stages->push_back({"segments", seconds_since(t1), peak_rss_mib(), 0.0});
  }
  double total = 0.0;
  for (const auto& s : p.stages) total += s.seconds;
  rec.runtime_s = total + seconds_since(t0);
  return rec;
}

}  // namespace trackassoc
