// The sparse S-D pipeline; see engine/pipeline/sparse_sd_pipeline.hpp for the formulation.
#include "engine/pipeline/sparse_sd_pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>

#include "engine/pipeline/pipeline_sd.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "kernels/assignment/lap.hpp"
#include "kernels/assignment/lap_sparse.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/random.hpp"
#include "kernels/statistics/scan_candidates.hpp"

namespace trackassoc {
namespace {

constexpr double kMiB = 1048576.0;
constexpr double kNotLinked = std::numeric_limits<double>::quiet_NaN();

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The tracks of one component, by sensor, and the link costs among them.
struct ComponentView {
  int32_t S = 0;
  std::vector<std::vector<int32_t>> tracks;  // tracks[s] = local track indices of sensor s
  std::vector<std::vector<int32_t>> node;    // node[s][i] = problem node of tracks[s][i]
  std::vector<std::vector<double>> link;     // slot a·S + b (a < b): n_a × n_b, NaN = no gated pair
  const SparseSDProblem* p = nullptr;

  double link_cost(int32_t a, int32_t i, int32_t b, int32_t j) const {
    if (a > b) std::swap(a, b), std::swap(i, j);
    return link[static_cast<std::size_t>(a) * S + b][static_cast<std::size_t>(i) * tracks[b].size() + j];
  }
  bool overlap(int32_t a, int32_t i, int32_t b, int32_t j) const {
    return p->coexist(node[a][i], node[b][j]);
  }
};

ComponentView component_view(const SparseSDProblem& p, int32_t c) {
  ComponentView v;
  v.p = &p;
  v.S = p.S();
  v.tracks.resize(v.S);
  v.node.resize(v.S);
  for (int32_t u : p.components.members(c)) {
    const int32_t s = p.sensor_of(u);
    v.tracks[s].push_back(u - p.offset[s]);
    v.node[s].push_back(u);
  }
  v.link.resize(static_cast<std::size_t>(v.S) * v.S);
  for (int32_t a = 0; a < v.S; ++a)
    for (int32_t b = a + 1; b < v.S; ++b) {
      const std::size_t slot = static_cast<std::size_t>(a) * v.S + b;
      auto& m = v.link[slot];
      m.assign(v.tracks[a].size() * v.tracks[b].size(), kNotLinked);
      if (m.empty()) continue;
      const SparsePairStatistic& st = p.pairs[slot];
      for (std::size_t i = 0; i < v.tracks[a].size(); ++i) {
        const int32_t ia = v.tracks[a][i];
        auto lo = std::lower_bound(st.a.begin(), st.a.end(), ia);
        for (std::size_t q = lo - st.a.begin(); q < st.size() && st.a[q] == ia; ++q) {
          auto it = std::lower_bound(v.tracks[b].begin(), v.tracks[b].end(), st.b[q]);
          if (it != v.tracks[b].end() && *it == st.b[q])
            m[i * v.tracks[b].size() + (it - v.tracks[b].begin())] = p.link[slot][q];
        }
      }
    }
  return v;
}

// Cost of the tuple with members (sensor, component index) — see the header: +inf when two
// members overlap in time without a gated pair, or the members are not connected by gated pairs.
double tuple_cost(const ComponentView& v, const std::vector<std::pair<int32_t, int32_t>>& m, bool all_pairs) {
  const std::size_t k = m.size();
  if (k <= 1) return 0.0;
  double cost = 0.0;
  uint32_t reach[16];
  for (std::size_t x = 0; x < k; ++x) reach[x] = 1u << x;
  for (std::size_t x = 0; x < k; ++x)
    for (std::size_t y = x + 1; y < k; ++y) {
      const double l = v.link_cost(m[x].first, m[x].second, m[y].first, m[y].second);
      if (std::isnan(l)) {
        if (v.overlap(m[x].first, m[x].second, m[y].first, m[y].second))
          return std::numeric_limits<double>::infinity();
        continue;  // never together: no evidence either way
      }
      reach[x] |= 1u << y;
      reach[y] |= 1u << x;
      if (all_pairs || y == x + 1) cost += l;
    }
  uint32_t seen = reach[0], prev = 0;  // connectivity through gated pairs
  while (seen != prev) {
    prev = seen;
    for (std::size_t x = 0; x < k; ++x)
      if (seen >> x & 1u) seen |= reach[x];
  }
  return seen == (1u << k) - 1 ? cost : std::numeric_limits<double>::infinity();
}

struct ComponentResult {
  std::vector<std::vector<int32_t>> tuples;  // problem nodes per tuple (any order)
  std::vector<double> costs;                 // tuple_cost of each tuple
  double objective = 0.0, lower_bound = 0.0;
  bool fallback = false, optimal = false;
  std::size_t entries = 0;
};

ComponentResult solve_dense_component(const ComponentView& v, const std::string& solver,
                                      const nlohmann::json& options, bool all_pairs) {
  ComponentResult r;
  const int32_t S = v.S;
  std::vector<int32_t> n(S);
  for (int32_t s = 0; s < S; ++s) n[s] = static_cast<int32_t>(v.tracks[s].size());
  CostTensorSD t(n, 0.f);
  r.entries = t.cost.size();
  std::vector<int32_t> idx(S, 0);
  std::vector<std::pair<int32_t, int32_t>> members;
  for (std::size_t e = 0; e < t.cost.size(); ++e) {
    // idx is the odometer of entry e in the tensor's own order (stride[S−1] = 1).
    std::size_t rem = e;
    for (int32_t s = 0; s < S; ++s) {
      idx[s] = static_cast<int32_t>(rem / t.stride[s]);
      rem %= t.stride[s];
    }
    members.clear();
    for (int32_t s = 0; s < S; ++s)
      if (idx[s] < n[s]) members.emplace_back(s, idx[s]);
    const double c = tuple_cost(v, members, all_pairs);
    t.cost[e] = std::isfinite(c) ? static_cast<float>(c) : std::numeric_limits<float>::infinity();
  }
  const SolutionSD sol = solve_sd_tensor(t, solver, options);
  std::vector<std::vector<char>> used(S);
  for (int32_t s = 0; s < S; ++s) used[s].assign(n[s], 0);
  std::vector<std::pair<int32_t, int32_t>> chosen;
  for (std::size_t k = 0; k + S <= sol.tuples.size(); k += S) {
    std::vector<int32_t> tuple;
    chosen.clear();
    for (int32_t s = 0; s < S; ++s) {
      const int32_t i = sol.tuples[k + s];
      if (i < 0 || i >= n[s] || used[s][i]) continue;
      used[s][i] = 1;
      tuple.push_back(v.node[s][i]);
      chosen.emplace_back(s, i);
    }
    if (tuple.empty()) continue;
    r.tuples.push_back(std::move(tuple));
    r.costs.push_back(tuple_cost(v, chosen, all_pairs));
  }
  for (int32_t s = 0; s < S; ++s)  // a solver that dropped a track: it stays alone
    for (int32_t i = 0; i < n[s]; ++i)
      if (!used[s][i]) {
        r.tuples.push_back({v.node[s][i]});
        r.costs.push_back(0.0);
      }
  r.objective = sol.summary.objective;
  r.lower_bound = sol.summary.lower_bound;
  r.optimal = sol.summary.termination == Termination::kOptimal;
  return r;
}

// Sequential LAP merging for a component too large for its dense sub-tensor (see the header).
ComponentResult solve_by_merging(const ComponentView& v, bool all_pairs) {
  ComponentResult r;
  r.fallback = true;
  r.lower_bound = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::vector<std::pair<int32_t, int32_t>>> groups;
  constexpr double kForbidden = std::numeric_limits<double>::infinity();  // no gain: never merged
  for (int32_t s = 0; s < v.S; ++s) {
    const int32_t nt = static_cast<int32_t>(v.tracks[s].size());
    if (nt == 0) continue;
    const int32_t ng = static_cast<int32_t>(groups.size());
    std::vector<double> cost(static_cast<std::size_t>(ng) * nt, kForbidden);
    parallel_for_range(ng, 8, [&](std::size_t lo, std::size_t hi) {
      std::vector<std::pair<int32_t, int32_t>> m;
      for (std::size_t g = lo; g < hi; ++g)
        for (int32_t j = 0; j < nt; ++j) {
          m = groups[g];
          const double before = tuple_cost(v, m, all_pairs);
          m.emplace_back(s, j);
          const double c = tuple_cost(v, m, all_pairs) - before;
          if (std::isfinite(c) && c < 0.0) cost[g * nt + j] = c;
        }
    });
    std::vector<int32_t> col_to_row(nt, -1);
    if (ng > 0) {
      LapOptions lo;
      lo.allow_unassigned = true;
      lo.unassigned_cost = 0.0;
      col_to_row = solve_gated_lap(cost, ng, nt, lo).col_to_row;  // sparse when large and gated
    }
    for (int32_t j = 0; j < nt; ++j) {
      const int32_t g = col_to_row[j];
      if (g >= 0 && cost[static_cast<std::size_t>(g) * nt + j] < kForbidden)
        groups[g].emplace_back(s, j);
      else
        groups.push_back({{s, j}});
    }
  }
  for (const auto& g : groups) {
    r.costs.push_back(tuple_cost(v, g, all_pairs));
    r.objective += r.costs.back();
    std::vector<int32_t> tuple;
    for (const auto& [s, i] : g) tuple.push_back(v.node[s][i]);
    r.tuples.push_back(std::move(tuple));
  }
  return r;
}

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
  p.sensor_ids = std::move(sel.ids);
  p.sensor_columns = std::move(sel.columns);
  const double period = sel.period;
  const int32_t S = p.S();
  if (S > 16)
    throw InputError("/sensors: at most 16 sensors are associated at once, got " + std::to_string(S));
  auto stage = [&](const char* name, std::chrono::steady_clock::time_point t0, double bytes) {
    p.stages.push_back({name, seconds_since(t0), peak_rss_mib(), bytes / kMiB});
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
    }
  stage("candidates", t0, bytes);

  t0 = std::chrono::steady_clock::now();
  const SequentialGate gate(p.dim, po.statistic, static_cast<int32_t>(p.common_times.size()));
  std::vector<int32_t> u, v;
  bytes = 0;
  for (int32_t a = 0; a < S; ++a)
    for (int32_t b = a + 1; b < S; ++b) {
      const std::size_t slot = static_cast<std::size_t>(a) * S + b;
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
      bytes += static_cast<double>(st.bytes() + link.size() * sizeof(double));
    }
  stage("statistics", t0, bytes);

  t0 = std::chrono::steady_clock::now();
  p.components = connected_components(p.nodes(), u, v);
  stage("components", t0, static_cast<double>(p.components.nodes.size() * sizeof(int32_t)));
  return p;
}

AssociationRecord solve_sparse_sd_association(const SparseSDProblem& p, const std::string& solver,
                                              const nlohmann::json& solver_options, uint64_t seed,
                                              const SparseSDOptions& options, SparseSDSolveReport* report) {
  require_sparse_sd_solver(solver);
  const auto t0 = std::chrono::steady_clock::now();
  const bool all_pairs = options.pipeline.cost.form == CostForm::kAllPairs;
  const int32_t C = p.components.count, S = p.S();
  std::vector<ComponentResult> results(C);
  parallel_for_range(C, 1, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t c = lo; c < hi; ++c) {
      if (p.components.size(static_cast<int32_t>(c)) == 1) {
        results[c].tuples.push_back({p.components.members(static_cast<int32_t>(c))[0]});
        results[c].costs.push_back(0.0);
        results[c].optimal = true;
        continue;
      }
      const ComponentView view = component_view(p, static_cast<int32_t>(c));
      double entries = 1.0;
      for (int32_t s = 0; s < S; ++s) entries *= static_cast<double>(view.tracks[s].size() + 1);
      results[c] = entries <= static_cast<double>(options.max_component_entries)
                       ? solve_dense_component(view, solver, solver_options, all_pairs)
                       : solve_by_merging(view, all_pairs);
      if (results[c].fallback) results[c].entries = static_cast<std::size_t>(std::min(entries, 1e18));
    }
  });
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
