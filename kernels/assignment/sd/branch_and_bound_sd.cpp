// Exact depth-first branch and bound for the S-D assignment with dummies (see assignment_sd.hpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "kernels/assignment/sd/assignment_sd.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

void ExactSDOptions::validate() const {
  require(time_limit_s > 0.0 && !std::isnan(time_limit_s), "ExactSDOptions.time_limit_s", "must be > 0");
  require(max_nodes >= 1, "ExactSDOptions.max_nodes", "must be >= 1");
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Search {
  const CostTensorSD& c;
  const ExactSDOptions& options;
  int32_t S;
  std::vector<std::vector<double>> share;  // cheapest equal share of a tuple holding (s, i)
  std::vector<std::vector<char>> used;
  std::vector<int32_t> current, best;
  double best_cost = kInf;
  int64_t nodes = 0;
  bool stopped = false;
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();

  Search(const CostTensorSD& cost, const ExactSDOptions& o) : c(cost), options(o), S(cost.dims()) {
    share.resize(S);
    used.resize(S);
    for (int32_t s = 0; s < S; ++s) {
      share[s].assign(c.n[s], kInf);
      used[s].assign(c.n[s], 0);
    }
    // One pass over the tensor with an odometer over the indices.
    std::vector<int32_t> idx(S, 0);
    for (std::size_t e = 0; e < c.cost.size(); ++e) {
      int members = 0;
      for (int32_t s = 0; s < S; ++s) members += idx[s] < c.n[s];
      const double v = c.cost[e];
      if (members > 0 && std::isfinite(v)) {
        const double part = v / members;
        for (int32_t s = 0; s < S; ++s)
          if (idx[s] < c.n[s]) share[s][idx[s]] = std::min(share[s][idx[s]], part);
      }
      for (int32_t s = S - 1; s >= 0; --s) {
        if (++idx[s] <= c.n[s]) break;
        idx[s] = 0;
      }
    }
  }

  double root_bound() const {
    double lb = 0.0;
    for (const auto& v : share)
      for (double x : v) lb += x;
    return lb;
  }

  bool out_of_budget() {
    if (stopped) return true;
    if (++nodes >= options.max_nodes || ((nodes & 1023) == 0 && seconds_since(t0) > options.time_limit_s))
      stopped = true;
    return stopped;
  }

  struct Child {
    double bound;
    double cost;
    std::vector<int32_t> tuple;
  };

  // Every tuple holding index i of sensor s, dummies before s, free indices or dummies after s.
  void enumerate(int32_t s, std::vector<int32_t>& t, int32_t q, double base, double lb_rest,
                 std::vector<Child>& out) {
    if (q == S) {
      const double v = c.at(t);
      if (!std::isfinite(v)) return;
      double members_share = 0.0;
      for (int32_t r = s; r < S; ++r)
        if (t[r] >= 0) members_share += share[r][t[r]];
      const double bound = base + v + lb_rest - members_share;
      if (bound >= best_cost - 1e-12 * std::max(1.0, std::abs(best_cost))) return;
      out.push_back({bound, v, t});
      return;
    }
    t[q] = kNoTrack;
    enumerate(s, t, q + 1, base, lb_rest, out);
    for (int32_t i = 0; i < c.n[q]; ++i) {
      if (used[q][i]) continue;
      t[q] = i;
      enumerate(s, t, q + 1, base, lb_rest, out);
    }
    t[q] = kNoTrack;
  }

  void dfs(double cost_so_far, double lb_rest) {
    if (out_of_budget()) return;
    int32_t s = 0, i = -1;
    for (; s < S; ++s) {
      for (int32_t x = 0; x < c.n[s]; ++x)
        if (!used[s][x]) {
          i = x;
          break;
        }
      if (i >= 0) break;
    }
    if (i < 0) {
      if (cost_so_far < best_cost) {
        best_cost = cost_so_far;
        best = current;
      }
      return;
    }
    std::vector<int32_t> t(S, kNoTrack);
    t[s] = i;
    std::vector<Child> children;
    used[s][i] = 1;  // so that enumerate() does not offer i again in a later sensor (it cannot: s differs)
    enumerate(s, t, s + 1, cost_so_far, lb_rest, children);
    used[s][i] = 0;
    std::sort(children.begin(), children.end(),
              [](const Child& a, const Child& b) { return a.bound < b.bound; });
    for (const Child& ch : children) {
      if (ch.bound >= best_cost - 1e-12 * std::max(1.0, std::abs(best_cost))) break;
      double members_share = 0.0;
      for (int32_t r = s; r < S; ++r)
        if (ch.tuple[r] >= 0) {
          used[r][ch.tuple[r]] = 1;
          members_share += share[r][ch.tuple[r]];
        }
      current.insert(current.end(), ch.tuple.begin(), ch.tuple.end());
      dfs(cost_so_far + ch.cost, lb_rest - members_share);
      current.resize(current.size() - S);
      for (int32_t r = s; r < S; ++r)
        if (ch.tuple[r] >= 0) used[r][ch.tuple[r]] = 0;
      if (stopped) return;
    }
  }
};

}  // namespace

SolutionSD solve_exact_sd(const CostTensorSD& c, const ExactSDOptions& options,
                          const std::vector<int32_t>* incumbent) {
  options.validate();
  c.validate();
  const auto t0 = std::chrono::steady_clock::now();
  Search search(c, options);
  SolutionSD sol;
  sol.S = c.dims();
  const double root = search.root_bound();
  if (!std::isfinite(root)) {  // some track is in no finite tuple
    sol.summary.termination = Termination::kInfeasible;
    sol.summary.feasible = false;
    sol.summary.message = "a track has no tuple of finite cost";
    return sol;
  }
  if (incumbent && is_valid_assignment_sd(c, *incumbent)) {
    search.best = *incumbent;
    search.best_cost = assignment_cost_sd(c, *incumbent);
  }
  search.dfs(0.0, root);
  sol.tuples = search.best;
  sol.summary.iterations = search.nodes;
  const bool proven = !search.stopped;
  if (sol.tuples.empty() && c.n != std::vector<int32_t>(c.n.size(), 0)) {
    sol.summary.termination = proven ? Termination::kInfeasible : Termination::kTimeLimit;
  } else {
    sol.summary.termination = proven ? Termination::kOptimal : Termination::kTimeLimit;
  }
  finish_summary_sd(c, sol.tuples, proven ? search.best_cost : root, sol.summary);
  sol.summary.message =
      std::to_string(search.nodes) + " nodes" + (proven ? "" : "; stopped at the node/time limit");
  sol.summary.wall_time_s = seconds_since(t0);
  return sol;
}

}  // namespace trackassoc
