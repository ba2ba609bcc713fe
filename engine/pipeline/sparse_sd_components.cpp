// A connected component of the sparse S-D pipeline as a self-contained problem
// (engine/pipeline/sparse_sd_components.hpp).
#include "engine/pipeline/sparse_sd_components.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/pipeline/pipeline_sd.hpp"
#include "kernels/assignment/lap.hpp"
#include "kernels/assignment/lap_sparse.hpp"
#include "kernels/core/parallel.hpp"

namespace trackassoc {
namespace {

constexpr double kNotLinked = std::numeric_limits<double>::quiet_NaN();

// Cost of the tuple with members (sensor, component index) — see the header: +inf when two
// members overlap in time without a gated pair, or the members are not connected by gated pairs.
double sd_tuple_cost(const SDComponentView& v, const std::vector<std::pair<int32_t, int32_t>>& m,
                     bool all_pairs) {
  const std::size_t k = m.size();
  if (k <= 1) return 0.0;
  double cost = 0.0;
  // Connectivity through gated pairs: union-find over the k members (one per sensor, so k <= S;
  // no cap on S: the buffer is on the stack up to 32 members).
  int32_t stack_parent[32];
  std::vector<int32_t> heap_parent;
  int32_t* parent = stack_parent;
  if (k > 32) {
    heap_parent.resize(k);
    parent = heap_parent.data();
  }
  for (std::size_t x = 0; x < k; ++x) parent[x] = static_cast<int32_t>(x);
  auto root = [&](int32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::size_t groups = k;
  for (std::size_t x = 0; x < k; ++x)
    for (std::size_t y = x + 1; y < k; ++y) {
      const double l = v.link_cost(m[x].first, m[x].second, m[y].first, m[y].second);
      if (std::isnan(l)) {
        if (v.overlap(m[x].first, m[x].second, m[y].first, m[y].second))
          return std::numeric_limits<double>::infinity();
        continue;  // never together: no evidence either way
      }
      const int32_t rx = root(static_cast<int32_t>(x)), ry = root(static_cast<int32_t>(y));
      if (rx != ry) {
        parent[rx] = ry;
        --groups;
      }
      if (all_pairs || y == x + 1) cost += l;
    }
  return groups == 1 ? cost : std::numeric_limits<double>::infinity();
}

SDComponentResult solve_dense_sd_component(const SDComponentView& v, const std::string& solver,
                                           const nlohmann::json& options, bool all_pairs) {
  SDComponentResult r;
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
    const double c = sd_tuple_cost(v, members, all_pairs);
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
    r.costs.push_back(sd_tuple_cost(v, chosen, all_pairs));
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
SDComponentResult solve_sd_component_by_merging(const SDComponentView& v, bool all_pairs) {
  SDComponentResult r;
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
          const double before = sd_tuple_cost(v, m, all_pairs);
          m.emplace_back(s, j);
          const double c = sd_tuple_cost(v, m, all_pairs) - before;
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
    r.costs.push_back(sd_tuple_cost(v, g, all_pairs));
    r.objective += r.costs.back();
    std::vector<int32_t> tuple;
    for (const auto& [s, i] : g) tuple.push_back(v.node[s][i]);
    r.tuples.push_back(std::move(tuple));
  }
  return r;
}

}  // namespace

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

SDComponentResult solve_sd_component(const SDComponentView& v, const std::string& solver,
                                     const nlohmann::json& solver_options, bool all_pairs,
                                     std::size_t max_entries) {
  const double entries = v.entries();
  SDComponentResult r = entries <= static_cast<double>(max_entries)
                            ? solve_dense_sd_component(v, solver, solver_options, all_pairs)
                            : solve_sd_component_by_merging(v, all_pairs);
  if (r.fallback) r.entries = static_cast<std::size_t>(std::min(entries, 1e18));
  return r;
}

SDComponentResult single_track_component(int32_t u) {
  SDComponentResult r;
  r.tuples.push_back({u});
  r.costs.push_back(0.0);
  r.optimal = true;
  return r;
}

std::vector<SDComponentResult> solve_sd_components(const SparseSDProblem& p, const std::string& solver,
                                                   const nlohmann::json& solver_options, bool all_pairs,
                                                   std::size_t max_entries) {
  const int32_t C = p.components.count;
  std::vector<SDComponentResult> results(C);
  parallel_for_range(C, 1, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t c = lo; c < hi; ++c) {
      const auto ci = static_cast<int32_t>(c);
      results[c] = p.components.size(ci) == 1 ? single_track_component(p.components.members(ci)[0])
                                              : solve_sd_component(sd_component_view(p, ci), solver,
                                                                   solver_options, all_pairs, max_entries);
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

// The link matrices travel sparse: per slot, the gated-in entries (index, cost) only, since
// most of a large component's n_a × n_b entries are NaN (no gated pair).
void encode_sd_component_view(distributed::ByteWriter& w, const SDComponentView& v) {
  w.put(v.S);
  w.put_nested(v.tracks);
  w.put_nested(v.node);
  w.put_nested(v.first);
  w.put_nested(v.last);
  w.put<uint64_t>(v.link.size());
  std::vector<uint64_t> index;
  std::vector<double> cost;
  for (const auto& m : v.link) {
    index.clear();
    cost.clear();
    for (std::size_t k = 0; k < m.size(); ++k)
      if (!std::isnan(m[k])) {
        index.push_back(k);
        cost.push_back(m[k]);
      }
    w.put<uint64_t>(m.size());
    w.put(index);
    w.put(cost);
  }
}

SDComponentView decode_sd_component_view(distributed::ByteReader& r) {
  SDComponentView v;
  v.S = r.get<int32_t>();
  v.tracks = r.get_nested<int32_t>();
  v.node = r.get_nested<int32_t>();
  v.first = r.get_nested<int32_t>();
  v.last = r.get_nested<int32_t>();
  v.link.resize(r.get<uint64_t>());
  for (auto& m : v.link) {
    m.assign(r.get<uint64_t>(), kNotLinked);
    const auto index = r.get_vector<uint64_t>();
    const auto cost = r.get_vector<double>();
    for (std::size_t k = 0; k < index.size(); ++k) m.at(index[k]) = cost[k];
  }
  return v;
}

void encode_sd_component_result(distributed::ByteWriter& w, const SDComponentResult& x) {
  w.put_nested(x.tuples);
  w.put(x.costs);
  w.put(x.objective);
  w.put(x.lower_bound);
  w.put<uint8_t>(x.fallback);
  w.put<uint8_t>(x.optimal);
  w.put<uint64_t>(x.entries);
}

SDComponentResult decode_sd_component_result(distributed::ByteReader& r) {
  SDComponentResult x;
  x.tuples = r.get_nested<int32_t>();
  x.costs = r.get_vector<double>();
  x.objective = r.get<double>();
  x.lower_bound = r.get<double>();
  x.fallback = r.get<uint8_t>() != 0;
  x.optimal = r.get<uint8_t>() != 0;
  x.entries = r.get<uint64_t>();
  return x;
}

}  // namespace trackassoc
