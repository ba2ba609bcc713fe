// A connected component of the sparse S-D pipeline as a self-contained problem
// (engine/pipeline/sparse_sd_components.hpp).
#include "engine/pipeline/sparse_sd_components.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/distributed/shard_items.hpp"
#include "engine/pipeline/pair_statistics_sharded.hpp"
#include "engine/pipeline/pipeline_sd.hpp"
#include "engine/pipeline/sparse_sd_tuples.hpp"
#include "engine/pipeline/tuple_cost.hpp"
#include "io/memory_budget.hpp"
#include "kernels/assignment/lap.hpp"
#include "kernels/assignment/lap_sparse.hpp"
#include "kernels/core/parallel.hpp"

namespace trackassoc {
namespace {

constexpr double kNotLinked = std::numeric_limits<double>::quiet_NaN();

SDComponentResult solve_dense_sd_component(const SDComponentView& v, const std::string& solver,
                                           const nlohmann::json& options, bool all_pairs) {
  SDComponentResult r;
  const int32_t S = v.S;
  std::vector<int32_t> n(S);
  for (int32_t s = 0; s < S; ++s) n[s] = static_cast<int32_t>(v.tracks[s].size());
  // The tensor spans the sensors present in the component only (issue 31: a tuple needs only the
  // sensors of its component), in their order: a sensor without tracks adds a dimension of one
  // dummy index, where the relaxation would keep the first two dimensions and relax the sensors
  // that have tracks (measured on widearea_small: 23 components of two sensors, 6 entries, stopped
  // at 300 iterations with 7-100 % gaps; over their two sensors it is one exact LAP).
  std::vector<int32_t> present;  // tensor dimension → sensor
  for (int32_t s = 0; s < S; ++s)
    if (n[s] > 0) present.push_back(s);
  if (present.size() < 2) {  // (gated pairs join two sensors; kept for any view)
    present.resize(S);
    for (int32_t s = 0; s < S; ++s) present[s] = s;
  }
  const int32_t P = static_cast<int32_t>(present.size());
  std::vector<int32_t> np(P);
  for (int32_t q = 0; q < P; ++q) np[q] = n[present[q]];
  CostTensorSD t(np, 0.f);
  r.entries = t.cost.size();
  // The one S-D rule over the component's tracks (engine/pipeline/tuple_cost.hpp).
  fill_sd_tensor(
      t, all_pairs,
      [&](int32_t q, int32_t i, int32_t u, int32_t j) { return v.link_cost(present[q], i, present[u], j); },
      [&](int32_t q, int32_t i, int32_t u, int32_t j) { return v.overlap(present[q], i, present[u], j); });
  const SolutionSD sol = solve_sd_tensor(t, solver, options);
  std::vector<std::vector<char>> used(S);
  for (int32_t s = 0; s < S; ++s) used[s].assign(n[s], 0);
  std::vector<std::pair<int32_t, int32_t>> chosen;
  for (std::size_t k = 0; k + P <= sol.tuples.size(); k += P) {
    std::vector<int32_t> tuple;
    chosen.clear();
    for (int32_t q = 0; q < P; ++q) {
      const int32_t s = present[q], i = sol.tuples[k + q];
      if (i < 0 || i >= n[s] || used[s][i]) continue;
      used[s][i] = 1;
      tuple.push_back(v.node[s][i]);
      chosen.emplace_back(s, i);
    }
    if (tuple.empty()) continue;
    r.tuples.push_back(std::move(tuple));
    r.costs.push_back(sd_component_tuple_cost(v, chosen, all_pairs));
  }
  for (int32_t s = 0; s < S; ++s)  // a solver that dropped a track: it stays alone
    for (int32_t i = 0; i < n[s]; ++i)
      if (!used[s][i]) {
        r.tuples.push_back({v.node[s][i]});
        r.costs.push_back(0.0);
      }
  r.objective = sol.summary.objective;
  r.lower_bound = sol.summary.lower_bound;
  r.termination = sol.summary.termination;
  return r;
}

}  // namespace

// Sequential LAP merging for a component too large for its dense sub-tensor (see the header).
// Sensor s's tracks join the groups of the sensors before it by one rectangular LAP. A track j can
// lower a group's cost only when it has a gated pair with one of the group's members (otherwise
// the tuple cost is +inf: not connected, or overlapping without a gated pair), so the LAP's finite
// entries are found through the members' gated pairs: memory O(gated pairs), never the groups ×
// tracks matrix (7.2 GB at 30 000 × 30 000; issue 30). The LAP gets the same finite entries as
// the dense matrix gave, so the same solution.
SDComponentResult solve_sd_component_by_merging(const SDComponentView& v, bool all_pairs) {
  SDComponentResult r;
  r.fallback = true;
  r.termination = Termination::kHeuristic;
  r.lower_bound = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::vector<std::pair<int32_t, int32_t>>> groups;
  for (int32_t s = 0; s < v.S; ++s) {
    const int32_t nt = static_cast<int32_t>(v.tracks[s].size());
    if (nt == 0) continue;
    const int32_t ng = static_cast<int32_t>(groups.size());
    // Row g: the tracks j of sensor s that join group g at a gain (cost change < 0), ascending j.
    std::vector<std::vector<std::pair<int32_t, double>>> gain(ng);
    parallel_for_range(ng, 8, [&](std::size_t lo, std::size_t hi) {
      std::vector<std::pair<int32_t, int32_t>> m;
      std::vector<int32_t> partners;
      for (std::size_t g = lo; g < hi; ++g) {
        partners.clear();
        for (const auto& [sm, i] : groups[g])  // members are of sensors before s
          v.link[static_cast<std::size_t>(sm) * v.S + s].for_row(
              i, [&](int32_t j, double) { partners.push_back(j); });
        std::sort(partners.begin(), partners.end());
        partners.erase(std::unique(partners.begin(), partners.end()), partners.end());
        const double before = sd_component_tuple_cost(v, groups[g], all_pairs);
        for (const int32_t j : partners) {
          m = groups[g];
          m.emplace_back(s, j);
          const double c = sd_component_tuple_cost(v, m, all_pairs) - before;
          if (std::isfinite(c) && c < 0.0) gain[g].emplace_back(j, c);
        }
      }
    });
    std::vector<int32_t> col_to_row(nt, -1);
    if (ng > 0) {
      std::vector<int32_t> row_start(static_cast<std::size_t>(ng) + 1, 0), col;
      std::vector<double> val;
      for (int32_t g = 0; g < ng; ++g) {
        for (const auto& [j, c] : gain[g]) col.push_back(j), val.push_back(c);
        row_start[g + 1] = static_cast<int32_t>(col.size());
      }
      LapOptions lo;
      lo.allow_unassigned = true;
      lo.unassigned_cost = 0.0;
      // solve_gated_lap solves a dense ng × nt matrix when the entries are too dense for its
      // sparse solver (or a side is small): that matrix is counted against the memory budget.
      if (solve_gated_lap_is_dense(ng, nt, col.size()))
        require_memory(bytes_of(static_cast<double>(ng) * nt, sizeof(double)) + v.link_bytes(),
                       "the merging fallback's dense LAP of a component (" + std::to_string(ng) +
                           " groups x " + std::to_string(nt) + " tracks, " + std::to_string(col.size()) +
                           " gated)");
      col_to_row = solve_gated_lap(SparseCostView{ng, nt, row_start, col, val}, lo).col_to_row;
    }
    for (int32_t j = 0; j < nt; ++j) {
      const int32_t g = col_to_row[j];
      bool gained = false;
      if (g >= 0) {
        const auto it = std::lower_bound(gain[g].begin(), gain[g].end(), j,
                                         [](const auto& x, int32_t col) { return x.first < col; });
        gained = it != gain[g].end() && it->first == j;
      }
      if (gained)
        groups[g].emplace_back(s, j);
      else
        groups.push_back({{s, j}});
    }
  }
  for (const auto& g : groups) {
    r.costs.push_back(sd_component_tuple_cost(v, g, all_pairs));
    r.objective += r.costs.back();
    std::vector<int32_t> tuple;
    for (const auto& [s, i] : g) tuple.push_back(v.node[s][i]);
    r.tuples.push_back(std::move(tuple));
  }
  return r;
}

SDLinkMatrix SDLinkMatrix::from_entries(int32_t rows, int32_t cols,
                                        std::vector<std::tuple<int32_t, int32_t, double>> entries) {
  SDLinkMatrix m;
  m.rows = rows;
  m.cols = cols;
  const std::size_t n = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
  m.sparse = n > kDenseEntries;
  if (!m.sparse) {
    m.dense.assign(n, kNotLinked);
    for (const auto& [i, j, c] : entries) m.dense[static_cast<std::size_t>(i) * cols + j] = c;
    return m;
  }
  auto key = [](const auto& x) { return std::make_pair(std::get<0>(x), std::get<1>(x)); };
  std::stable_sort(entries.begin(), entries.end(),
                   [&](const auto& x, const auto& y) { return key(x) < key(y); });
  m.row_start.assign(static_cast<std::size_t>(rows) + 1, 0);
  for (std::size_t e = 0; e < entries.size(); ++e) {
    const auto& [i, j, c] = entries[e];
    if (e > 0 && key(entries[e - 1]) == key(entries[e])) {
      m.cost.back() = c;  // a repeated (i, j): the last, as the dense form keeps it
      continue;
    }
    m.col.push_back(j);
    m.cost.push_back(c);
    ++m.row_start[i + 1];
  }
  for (int32_t i = 0; i < rows; ++i) m.row_start[i + 1] += m.row_start[i];
  return m;
}

double SDLinkMatrix::at(int32_t i, int32_t j) const {
  if (!sparse) return dense[static_cast<std::size_t>(i) * cols + j];
  const auto begin = col.begin() + row_start[i], end = col.begin() + row_start[i + 1];
  const auto it = std::lower_bound(begin, end, j);
  return it != end && *it == j ? cost[it - col.begin()] : kNotLinked;
}

std::size_t SDComponentView::link_bytes() const {
  std::size_t bytes = 0;
  for (const auto& m : link) bytes += m.bytes();
  return bytes;
}

double SDComponentView::entries() const {
  double e = 1.0;
  for (int32_t s = 0; s < S; ++s) e *= static_cast<double>(tracks[s].size() + 1);
  return e;
}

SDComponentView sd_component_view(const SparseSDProblem& p, int32_t c) {
  SDComponentView v;
  v.S = p.S();
  v.tracks.resize(v.S);
  v.node.resize(v.S);
  v.first.resize(v.S);
  v.last.resize(v.S);
  for (int32_t u : p.components.members(c)) {
    const int32_t s = p.sensor_of(u);
    v.tracks[s].push_back(u - p.offset[s]);
    v.node[s].push_back(u);
    v.first[s].push_back(p.first_valid[u]);
    v.last[s].push_back(p.last_valid[u]);
  }
  v.link.resize(static_cast<std::size_t>(v.S) * v.S);
  std::vector<std::tuple<int32_t, int32_t, double>> entries;
  for (int32_t a = 0; a < v.S; ++a)
    for (int32_t b = a + 1; b < v.S; ++b) {
      const std::size_t slot = static_cast<std::size_t>(a) * v.S + b;
      entries.clear();
      // The pairs of `st` (sorted by the track of a) among the component's tracks, with their link
      // costs; the doubtful ones of the family-wise veto tagged (engine/pipeline/tuple_cost.hpp).
      auto add = [&](const SparsePairStatistic& st, const std::vector<double>& link, bool doubtful) {
        for (std::size_t i = 0; i < v.tracks[a].size(); ++i) {
          const int32_t ia = v.tracks[a][i];
          auto lo = std::lower_bound(st.a.begin(), st.a.end(), ia);
          for (std::size_t q = lo - st.a.begin(); q < st.size() && st.a[q] == ia; ++q) {
            auto it = std::lower_bound(v.tracks[b].begin(), v.tracks[b].end(), st.b[q]);
            if (it != v.tracks[b].end() && *it == st.b[q])
              entries.emplace_back(static_cast<int32_t>(i), static_cast<int32_t>(it - v.tracks[b].begin()),
                                   doubtful ? doubtful_pair_entry(link[q]) : link[q]);
          }
        }
      };
      add(p.pairs[slot], p.link[slot], false);
      if (slot < p.doubtful.size()) add(p.doubtful[slot], p.doubtful_link[slot], true);
      v.link[slot] = SDLinkMatrix::from_entries(static_cast<int32_t>(v.tracks[a].size()),
                                                static_cast<int32_t>(v.tracks[b].size()), entries);
    }
  return v;
}

SDComponentResult solve_sd_component(const SDComponentView& v, const std::string& solver,
                                     const nlohmann::json& solver_options, bool all_pairs,
                                     std::size_t max_entries) {
  const double entries = v.entries();
  // The dense sub-tensor (float per entry) when it is small enough and fits the memory budget with
  // what is held (issue 30); the relaxation over its allowed tuples when the tensor does not fit,
  // or when it is far larger than their list (engine/pipeline/sparse_sd_tuples.hpp: a component
  // that many sensors share, as in a radar network, has Π(n_s + 1) entries growing with the
  // sensors, and each relaxation iteration passes over all of them); else the merging fallback,
  // the last resort, which needs O(gated pairs).
  const double held = v.bytes_held + static_cast<double>(v.link_bytes());
  const bool fits_dense = entries <= static_cast<double>(max_entries) &&
                          bytes_of(held + entries * sizeof(float), 1) <= memory_budget_bytes();
  std::optional<TupleListSD> list;
  if (!fits_dense || entries > kListAboveEntries) {
    // The room beside what is held, shared by the components listed at once (one per thread).
    const double room = (static_cast<double>(memory_budget_bytes()) - held) /
                        std::max(1, oneapi::tbb::this_task_arena::max_concurrency());
    list = list_component_tuples(v, all_pairs, room);
  }
  if (fits_dense && (!list || static_cast<double>(list->size()) * kTensorPerListedTuple > entries))
    return solve_dense_sd_component(v, solver, solver_options, all_pairs);
  SDComponentResult r =
      list ? solve_sd_component_by_tuples(v, *list, all_pairs) : solve_sd_component_by_merging(v, all_pairs);
  r.entries = static_cast<std::size_t>(std::min(entries, 1e18));
  return r;
}

SDComponentResult single_track_component(int32_t u) {
  SDComponentResult r;
  r.tuples.push_back({u});
  r.costs.push_back(0.0);
  r.termination = Termination::kOptimal;
  return r;
}

std::vector<SDComponentResult> solve_sd_components(const SparseSDProblem& p, const std::string& solver,
                                                   const nlohmann::json& solver_options, bool all_pairs,
                                                   std::size_t max_entries) {
  const int32_t C = p.components.count;
  std::vector<SDComponentResult> results(C);
  // A component's view holds its gated pairs (i, j, cost: 28 bytes each while built): at most the
  // gated pairs of its members, counted against the memory budget before it is built (issue 30).
  std::vector<int64_t> degree(p.nodes(), 0);
  for (int32_t a = 0; a < p.S(); ++a)
    for (int32_t b = a + 1; b < p.S(); ++b) {
      const SparsePairStatistic& st = p.pairs[static_cast<std::size_t>(a) * p.S() + b];
      for (std::size_t q = 0; q < st.size(); ++q) ++degree[p.offset[a] + st.a[q]];
    }
  parallel_for_range(C, 1, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t c = lo; c < hi; ++c) {
      const auto ci = static_cast<int32_t>(c);
      if (p.components.size(ci) == 1) {
        results[c] = single_track_component(p.components.members(ci)[0]);
        continue;
      }
      double pairs = 0;
      for (int32_t u : p.components.members(ci)) pairs += static_cast<double>(degree[u]);
      require_memory(bytes_of(p.bytes_held + 28.0 * pairs, 1),
                     "the link costs of a component of " + std::to_string(p.components.size(ci)) +
                         " local tracks and " + std::to_string(static_cast<int64_t>(pairs)) + " gated pairs");
      SDComponentView v = sd_component_view(p, ci);
      v.bytes_held = p.bytes_held;
      results[c] = solve_sd_component(v, solver, solver_options, all_pairs, max_entries);
    }
  });
  return results;
}

double sd_component_cost(const SDComponentView& v, std::size_t max_entries) {
  const double entries = v.entries();
  if (entries <= static_cast<double>(max_entries)) return entries;
  double cost = 0.0, groups = 0.0;
  for (int32_t s = 0; s < v.S; ++s) {
    const auto n = static_cast<double>(v.tracks[s].size());
    cost += groups * n;
    groups += n;
  }
  return cost;
}

SDLinkMatrix::Gated SDLinkMatrix::gated(const SDLinkMatrix& m) {
  Gated g;
  g.rows = m.rows;
  g.cols = m.cols;
  m.for_each([&](int32_t i, int32_t j, double c) {
    g.index.push_back(static_cast<uint64_t>(i) * static_cast<uint64_t>(m.cols) + static_cast<uint64_t>(j));
    g.cost.push_back(c);
  });
  return g;
}

SDLinkMatrix SDLinkMatrix::from_gated(const Gated& g) {
  const uint64_t size =
      static_cast<uint64_t>(std::max(g.rows, 0)) * static_cast<uint64_t>(std::max(g.cols, 0));
  if (g.rows < 0 || g.cols < 0 || g.index.size() != g.cost.size())
    throw std::runtime_error("S-D link entries: " + std::to_string(g.index.size()) + " indices and " +
                             std::to_string(g.cost.size()) + " costs for " + std::to_string(g.rows) + " x " +
                             std::to_string(g.cols) + " (a bug)");
  std::vector<std::tuple<int32_t, int32_t, double>> entries;
  entries.reserve(g.index.size());
  for (std::size_t k = 0; k < g.index.size(); ++k) {
    if (g.index[k] >= size)
      throw std::runtime_error("S-D link entries: index " + std::to_string(g.index[k]) + " outside " +
                               std::to_string(g.rows) + " x " + std::to_string(g.cols) + " (a bug)");
    entries.emplace_back(static_cast<int32_t>(g.index[k] / g.cols), static_cast<int32_t>(g.index[k] % g.cols),
                         g.cost[k]);
  }
  return from_entries(g.rows, g.cols, std::move(entries));
}

namespace {

// What every component of a part shares.
struct SDShardHeader {
  std::string solver, options;  // options: JSON text
  bool all_pairs = false;
  uint64_t max_entries = 0;
};

constexpr auto wire_codec(std::type_identity<SDShardHeader>) {
  return distributed::codec<SDShardHeader>("S-D shard header", &SDShardHeader::solver,
                                           &SDShardHeader::options, &SDShardHeader::all_pairs,
                                           &SDShardHeader::max_entries);
}

constexpr distributed::ItemJob<SDShardHeader, SDComponentView, SDComponentResult> kSDComponents{
    "component", "tracks",
    [](const SDComponentView& v) {
      std::size_t n = 0;
      for (const auto& t : v.tracks) n += t.size();
      return n;
    },
    [](const SDShardHeader& h, const SDComponentView& v) {
      return solve_sd_component(v, h.solver, nlohmann::json::parse(h.options), h.all_pairs, h.max_entries);
    }};

}  // namespace

SDComponentCosts sd_component_costs(const SparseSDProblem& p, std::size_t max_entries) {
  SDComponentCosts out;
  for (int32_t c = 0; c < p.components.count; ++c) {
    if (p.components.size(c) < 2) continue;
    SDComponentView counts;  // only the track counts, for the estimate
    counts.S = p.S();
    counts.tracks.assign(p.S(), {});
    for (int32_t u : p.components.members(c)) counts.tracks[p.sensor_of(u)].push_back(0);
    out.component.push_back(c);
    out.cost.push_back(sd_component_cost(counts, max_entries));
  }
  return out;
}

std::vector<SDComponentResult> solve_sd_components_sharded(distributed::Communicator& comm,
                                                           const SparseSDProblem& p,
                                                           const std::string& solver,
                                                           const nlohmann::json& solver_options,
                                                           bool all_pairs, std::size_t max_entries) {
  const SDComponentCosts plan = sd_component_costs(p, max_entries);
  auto solved = distributed::shard_items(
      comm, kSDComponents, "sparse S-D components of 2+ tracks",
      {solver, solver_options.dump(), all_pairs, max_entries}, plan.component, plan.cost,
      [&](std::size_t k) { return sd_component_view(p, static_cast<int32_t>(plan.component[k])); });
  std::vector<SDComponentResult> results(p.components.count);
  for (int32_t c = 0; c < p.components.count; ++c)
    if (p.components.size(c) == 1) results[c] = single_track_component(p.components.members(c)[0]);
  for (std::size_t k = 0; k < solved.size(); ++k) results[plan.component[k]] = std::move(solved[k]);
  return results;
}

// The other ranks answer both sharded steps of the default path, round after round: the sensor
// pairs' gated statistics (engine/pipeline/pair_statistics_sharded.hpp) and the components.
void serve_sd_components(distributed::Communicator& comm) {
  distributed::serve_items(comm, kPairStatisticsJob, kSDComponents);
}

}  // namespace trackassoc
