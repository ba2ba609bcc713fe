#include "kernels/assignment/branch_and_bound.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>

#include "kernels/assignment/assignment_canonical.hpp"
#include "kernels/assignment/clique_cuts.hpp"
#include "kernels/assignment/lap.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

void BranchAndBoundOptions::validate() const {
  require(time_limit_s > 0.0 && !std::isnan(time_limit_s), "BranchAndBoundOptions.time_limit_s",
          "must be > 0");
  require(max_nodes >= 1, "BranchAndBoundOptions.max_nodes", "must be >= 1");
  require(node_subgradient_iterations >= 1, "BranchAndBoundOptions.node_subgradient_iterations",
          "must be >= 1");
  root.validate();
  cuts.validate();
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string bound_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

struct Child {
  double bound;
  int32_t i, j, k;
};

// A bound `raw` cannot lead to a solution strictly cheaper than `incumbent` (integer costs: ⌈raw⌉).
bool cannot_beat(double raw, double incumbent, bool integer_costs) {
  if (raw == kInf || !std::isfinite(incumbent)) return raw == kInf;  // (ceil(∞ − ∞) would be NaN)
  if (integer_costs) return std::ceil(raw - 1e-7 * std::max(1.0, std::abs(raw))) >= incumbent;
  return raw >= incumbent - 1e-9 * std::max(1.0, std::abs(incumbent));
}

// Root reduced costs over w at μ (Lagrangian constant `offset`): the raw bound L and, per tuple,
// rc_s = w_s + μ_k − u_i − v_j ≥ 0 from the LAP duals (u, v) of min_k w_ijk + μ_k, so every
// assignment containing s costs at least L + rc_s (the child bound of the search, at the root).
struct RootReducedCosts {
  double raw = -kInf;
  std::vector<double> rc;  // empty when the root LAP is infeasible
};

template <class T>
RootReducedCosts root_reduced_costs(const CostTensor3& b, const T* w, double offset,
                                    const std::vector<double>& mu) {
  RootReducedCosts out;
  std::vector<double> c(static_cast<std::size_t>(b.n1) * b.n2);
  std::vector<int32_t> arg(c.size());
  reduce_over_k(w, b.n1, b.n2, b.n3, mu, c, arg);
  const LapResult lap = solve_lap(c, b.n1, b.n2);
  if (!lap.feasible) return out;
  double mu_sum = 0.0;
  for (double m : mu) mu_sum += m;
  out.raw = lap.cost - mu_sum + offset;
  out.rc.resize(b.cost.size());
  for (int32_t i = 0; i < b.n1; ++i)
    for (int32_t j = 0; j < b.n2; ++j)
      for (int32_t k = 0; k < b.n3; ++k) {
        const std::size_t s = b.index(i, j, k);
        out.rc[s] = static_cast<double>(w[s]) + mu[k] - lap.row_dual[i] - lap.col_dual[j];
      }
  return out;
}

// The search over costs w (T = float: the tensor itself; double: the clique-penalised costs of
// clique_cuts.hpp) whose Lagrangian carries the constant `offset` (−Σ λ); incumbents are costed on b.
template <class T>
class Search {
 public:
  // cuts: the relaxed clique cuts behind w (null when w carries none).
  Search(const CanonicalProblem3& p, const BranchAndBoundOptions& o, const T* w, double offset,
         const CliqueRelaxation* cuts, std::chrono::steady_clock::time_point t0)
      : p_(p), b_(p.tensor), o_(o), w_(w), offset_(offset), t0_(t0) {
    used_j_.assign(b_.n2, 0);
    used_k_.assign(b_.n3, 0);
    used_i_.assign(b_.n1, 0);
    fixed_of_i_.assign(b_.n1, {-1, -1, -1});
    owner_of_j_.assign(b_.n2, -1);
    if (cuts)
      for (std::size_t c = 0; c < cuts->roots.size(); ++c)
        if (cuts->lambda[c] > 0.0) active_cuts_.push_back({cuts->roots[c], cuts->lambda[c]});
  }

  std::vector<Tuple3> incumbent;
  double incumbent_cost = kInf;
  double open_bound = kInf;  // least bound of subtrees abandoned at the time or node limit
  int64_t nodes = 0;
  bool interrupted = false;
  bool node_limit = false;

  // Returns after exploring (or abandoning) the subtree below the current fixings.
  // fixed_w: Σ w over the fixed tuples; fixed_b: their true cost.
  void explore(double fixed_w, double fixed_b, std::vector<double> mu) {
    ++nodes;
    if (nodes > o_.max_nodes) node_limit = true;
    if (node_limit || elapsed() > o_.time_limit_s) {
      interrupted = true;
      open_bound = std::min(open_bound, node_bound_for_interrupt(fixed_w));
      return;
    }
    std::vector<int32_t> I, J, K;
    for (int32_t i = 0; i < b_.n1; ++i)
      if (!used_i_[i]) I.push_back(i);
    for (int32_t j = 0; j < b_.n2; ++j)
      if (!used_j_[j]) J.push_back(j);
    for (int32_t k = 0; k < b_.n3; ++k)
      if (!used_k_[k]) K.push_back(k);
    const int32_t r = static_cast<int32_t>(I.size()), nj = static_cast<int32_t>(J.size()),
                  nk = static_cast<int32_t>(K.size());
    if (r == 0) {
      if (fixed_b < incumbent_cost) {
        incumbent_cost = fixed_b;
        incumbent = fixed_;
      }
      return;
    }
    // K equality only while |K| = |I| (then every free k must be used).
    const bool equality = nk == r;
    const double offset = offset_ + dead_cut_multipliers(I, J, K);
    std::vector<double> c(static_cast<std::size_t>(r) * nj), g(nk);
    std::vector<int32_t> arg(static_cast<std::size_t>(r) * nj), count(nk);
    double best_raw = -kInf;
    LapResult best_lap;
    std::vector<double> best_mu;
    double theta = 2.0;
    for (int it = 0; it < o_.node_subgradient_iterations; ++it) {
      // c_ij = min_{k ∈ K} (b_ijk + μ_k)   (Pattipati Eq. 16 on the free indices)
      for (int32_t a = 0; a < r; ++a)
        for (int32_t bj = 0; bj < nj; ++bj) {
          const T* row = w_ + (static_cast<std::size_t>(I[a]) * b_.n2 + J[bj]) * b_.n3;
          double best = kInf;
          int32_t kb = 0;
          for (int32_t q = 0; q < nk; ++q) {
            const double x = static_cast<double>(row[K[q]]) + mu[K[q]];
            if (x < best) {
              best = x;
              kb = q;
            }
          }
          c[static_cast<std::size_t>(a) * nj + bj] = best;
          arg[static_cast<std::size_t>(a) * nj + bj] = kb;
        }
      LapResult lap = solve_lap(c, r, nj);
      if (!lap.feasible) return;  // no completion of finite cost
      double mu_sum = 0.0;
      for (int32_t k : K) mu_sum += mu[k];
      const double raw = fixed_w + lap.cost - mu_sum + offset;
      if (prunable(raw)) return;
      // Relaxed solution → counts per free k.
      std::fill(count.begin(), count.end(), 0);
      for (int32_t a = 0; a < r; ++a) ++count[arg[static_cast<std::size_t>(a) * nj + lap.row_to_col[a]]];
      double g2 = 0.0;
      for (int32_t q = 0; q < nk; ++q) {
        g[q] = count[q] - 1.0;
        if (!equality && mu[K[q]] <= 0.0 && g[q] < 0.0) g[q] = 0.0;
        g2 += g[q] * g[q];
      }
      bool all_distinct = true;
      for (int32_t q = 0; q < nk; ++q) all_distinct &= count[q] <= 1;
      if (all_distinct) {
        // The relaxed solution is a feasible completion: a candidate incumbent.
        double total = fixed_b;
        for (int32_t a = 0; a < r; ++a) {
          const int32_t bj = lap.row_to_col[a];
          total += b_.at(I[a], J[bj], K[arg[static_cast<std::size_t>(a) * nj + bj]]);
        }
        if (total < incumbent_cost) {
          incumbent_cost = total;
          incumbent = fixed_;
          for (int32_t a = 0; a < r; ++a) {
            const int32_t bj = lap.row_to_col[a];
            incumbent.push_back({I[a], J[bj], K[arg[static_cast<std::size_t>(a) * nj + bj]]});
          }
        }
        // Without cuts, g = 0 makes raw equal to this completion's cost (complementary slackness),
        // so the node is pruned here; with cuts their slack may keep it open.
        if (prunable(raw)) return;
      }
      if (raw > best_raw) {
        best_raw = raw;
        best_lap = std::move(lap);
        best_mu = mu;
      } else {
        theta *= 0.5;
      }
      if (it + 1 == o_.node_subgradient_iterations || g2 == 0.0) break;
      const double target =
          std::isfinite(incumbent_cost) ? incumbent_cost : raw + 0.05 * std::max(1.0, std::abs(raw));
      const double step = theta * std::max(target - raw, 1e-9) / g2;
      for (int32_t q = 0; q < nk; ++q) {
        mu[K[q]] += step * g[q];
        if (!equality) mu[K[q]] = std::max(mu[K[q]], 0.0);
      }
    }
    if (best_lap.row_dual.empty()) return;

    // Surviving children (tuples whose bound from the dual certificate can beat the incumbent),
    // counted per free i, j and k. An index that must be used (i always; j, k while as many are
    // free as i) with no survivor has no completion; else branch on the one with the fewest.
    const std::vector<double>& u = best_lap.row_dual;
    const std::vector<double>& v = best_lap.col_dual;
    std::vector<int32_t> per_i(r, 0), per_j(nj, 0), per_k(nk, 0);
    for (int32_t a = 0; a < r; ++a)
      for (int32_t bj = 0; bj < nj; ++bj) {
        const T* row = w_ + (static_cast<std::size_t>(I[a]) * b_.n2 + J[bj]) * b_.n3;
        const double base = best_raw - u[a] - v[bj];
        for (int32_t q = 0; q < nk; ++q)
          if (!prunable(base + static_cast<double>(row[K[q]]) + best_mu[K[q]])) {
            ++per_i[a];
            ++per_j[bj];
            ++per_k[q];
          }
      }
    int dim = 0, at = 0, fewest = std::numeric_limits<int32_t>::max();
    auto consider = [&](int d, const std::vector<int32_t>& counts) {
      for (int32_t x = 0; x < static_cast<int32_t>(counts.size()); ++x)
        if (counts[x] < fewest) {
          fewest = counts[x];
          dim = d;
          at = x;
        }
    };
    consider(0, per_i);
    if (nj == r) consider(1, per_j);
    if (equality) consider(2, per_k);
    if (fewest == 0) return;  // no completion can beat the incumbent
    std::vector<Child> best_children;
    best_children.reserve(fewest);
    for (int32_t a = dim == 0 ? at : 0; a < (dim == 0 ? at + 1 : r); ++a)
      for (int32_t bj = dim == 1 ? at : 0; bj < (dim == 1 ? at + 1 : nj); ++bj) {
        const T* row = w_ + (static_cast<std::size_t>(I[a]) * b_.n2 + J[bj]) * b_.n3;
        const double base = best_raw - u[a] - v[bj];
        for (int32_t q = dim == 2 ? at : 0; q < (dim == 2 ? at + 1 : nk); ++q) {
          const double child = base + static_cast<double>(row[K[q]]) + best_mu[K[q]];
          if (!prunable(child)) best_children.push_back({child, I[a], J[bj], K[q]});
        }
      }
    std::sort(best_children.begin(), best_children.end(), [](const Child& x, const Child& y) {
      return x.bound < y.bound || (x.bound == y.bound && std::tie(x.i, x.j, x.k) < std::tie(y.i, y.j, y.k));
    });
    for (std::size_t ch = 0; ch < best_children.size(); ++ch) {
      const Child& child = best_children[ch];
      const int32_t i = child.i;
      if (prunable(child.bound)) break;  // sorted: the rest are no better
      if (interrupted) {
        open_bound = std::min(open_bound, child.bound);
        break;
      }
      used_i_[i] = 1;
      used_j_[child.j] = 1;
      used_k_[child.k] = 1;
      fixed_.push_back({i, child.j, child.k});
      fixed_of_i_[i] = fixed_.back();
      owner_of_j_[child.j] = i;
      explore(fixed_w + static_cast<double>(w_[b_.index(i, child.j, child.k)]),
              fixed_b + b_.at(i, child.j, child.k), best_mu);
      fixed_.pop_back();
      fixed_of_i_[i] = {-1, -1, -1};
      owner_of_j_[child.j] = -1;
      used_i_[i] = used_j_[child.j] = used_k_[child.k] = 0;
    }
  }

 private:
  double elapsed() const { return seconds_since(t0_); }

  // A bound `raw` cannot lead to a strictly better solution than the incumbent.
  bool prunable(double raw) const { return cannot_beat(raw, incumbent_cost, p_.integer_costs); }

  // Σ λ_c over the dead cuts: no fixed tuple is in Q(r_c) and no member is free with finite w.
  // Every completion then has load 0 on c, so the term λ_c (load − 1) of the Lagrangian is exactly
  // −λ_c beside w, which the member penalties never recover: adding λ_c back keeps the bound valid.
  // (A cut with a fixed member has load exactly 1 and costs nothing.) O(|I| + |J| + |K|) per cut.
  double dead_cut_multipliers(const std::vector<int32_t>& I, const std::vector<int32_t>& J,
                              const std::vector<int32_t>& K) const {
    double sum = 0.0;
    for (const auto& [root, lambda] : active_cuts_) {
      const int32_t i = root[0], j = root[1], k = root[2];
      if (used_i_[i] && (fixed_of_i_[i][1] == j || fixed_of_i_[i][2] == k)) continue;
      if (used_j_[j] && fixed_of_i_[owner_of_j_[j]][2] == k) continue;
      auto finite = [&](int32_t a, int32_t bj, int32_t q) {
        return static_cast<double>(w_[b_.index(a, bj, q)]) < kInf;
      };
      bool alive = false;
      if (!used_i_[i] && !used_j_[j])
        for (int32_t q : K)
          if ((alive = finite(i, j, q))) break;
      if (!alive && !used_i_[i] && !used_k_[k])
        for (int32_t q : J)
          if ((alive = finite(i, q, k))) break;
      if (!alive && !used_j_[j] && !used_k_[k])
        for (int32_t q : I)
          if ((alive = finite(q, j, k))) break;
      if (!alive) sum += lambda;
    }
    return sum;
  }

  // A cheap valid bound of an abandoned node: its fixed cost plus the minimum possible per free i
  // (over w, plus the offset: the Lagrangian at μ = 0 with the j and k constraints relaxed too).
  double node_bound_for_interrupt(double fixed_w) const {
    double s = fixed_w + offset_;
    for (int32_t i = 0; i < b_.n1; ++i) {
      if (used_i_[i]) continue;
      double m = kInf;
      for (int32_t j = 0; j < b_.n2; ++j) {
        if (used_j_[j]) continue;
        for (int32_t k = 0; k < b_.n3; ++k)
          if (!used_k_[k]) m = std::min(m, static_cast<double>(w_[b_.index(i, j, k)]));
      }
      s += m;
    }
    return s;
  }

  const CanonicalProblem3& p_;
  const CostTensor3& b_;
  const BranchAndBoundOptions& o_;
  const T* w_;
  double offset_;
  std::chrono::steady_clock::time_point t0_;
  std::vector<char> used_i_, used_j_, used_k_;
  std::vector<Tuple3> fixed_, fixed_of_i_;  // fixed_of_i_[i]: the fixed tuple of i ({-1, -1, -1}: none)
  std::vector<int32_t> owner_of_j_;         // the fixed i of j, or −1
  std::vector<std::pair<Tuple3, double>> active_cuts_;  // (r_c, λ_c) with λ_c > 0
};

struct SearchOutcome {
  std::vector<Tuple3> best;
  double lower_bound = -kInf;
  Termination termination = Termination::kOptimal;
  int64_t nodes = 0;
  int passes = 0;
  int64_t fixed_tuples = 0;  // fixed to 0 by reduced costs in the first pass
};

// The search below a root bound `lb`. With integer costs it first looks only for a solution of
// cost lb (pruning at lb + 1 instead of at a poor incumbent), then lb + 1, and so on: a pass that
// finds one ends the proof (nothing costs less than lb), a pass that completes without one proves
// optimum ≥ lb + 1. Once the target reaches the incumbent the pass is the plain search. The node
// limit counts over all passes.
template <class T>
SearchOutcome search_from_root(const CanonicalProblem3& p, const BranchAndBoundOptions& o, const T* w,
                               double offset, const CliqueRelaxation* cuts, const std::vector<double>& mu,
                               const RootReducedCosts& root, const std::vector<Tuple3>& incumbent,
                               double incumbent_cost, double lb, std::chrono::steady_clock::time_point t0) {
  SearchOutcome out;
  out.best = incumbent;
  std::vector<T> pass_w;
  while (true) {
    const bool targeted = p.integer_costs && std::isfinite(lb) && lb + 1.0 < incumbent_cost;
    const double pass_incumbent = targeted ? lb + 1.0 : incumbent_cost;  // targeted: only cost lb survives
    // Reduced-cost fixing: a tuple whose root bound L + rc_s cannot beat the pass's incumbent is
    // in no solution the pass looks for; w = +∞ removes it from every node's relaxation.
    const T* search_w = w;
    if (o.reduced_cost_fixing && !root.rc.empty()) {
      pass_w.assign(w, w + p.tensor.cost.size());
      int64_t fixed = 0;
      for (std::size_t s = 0; s < pass_w.size(); ++s)
        if (cannot_beat(root.raw + root.rc[s], pass_incumbent, p.integer_costs) &&
            pass_w[s] != std::numeric_limits<T>::infinity()) {
          pass_w[s] = std::numeric_limits<T>::infinity();
          ++fixed;
        }
      if (out.passes == 0) out.fixed_tuples = fixed;
      search_w = pass_w.data();
    }
    Search<T> state(p, o, search_w, offset, cuts, t0);
    state.nodes = out.nodes;
    state.incumbent_cost = pass_incumbent;
    if (!targeted) state.incumbent = incumbent;
    state.explore(0.0, 0.0, mu);
    out.nodes = state.nodes;
    ++out.passes;
    if (targeted && !state.incumbent.empty()) {  // cost lb: optimal
      out.best = std::move(state.incumbent);
      out.lower_bound = state.incumbent_cost;
      return out;
    }
    if (state.interrupted) {
      out.termination = state.node_limit ? Termination::kIterationLimit : Termination::kTimeLimit;
      out.lower_bound = std::max(lb, std::min(state.open_bound, state.incumbent_cost));
      if (!targeted) out.best = std::move(state.incumbent);
      return out;
    }
    if (!targeted) {
      out.best = std::move(state.incumbent);
      out.lower_bound = state.incumbent_cost;  // proven: every other subtree was pruned
      if (!std::isfinite(state.incumbent_cost)) out.termination = Termination::kInfeasible;
      return out;
    }
    lb += 1.0;  // the pass proved that nothing costs less than lb + 1
  }
}

}  // namespace

Solution3 solve_branch_and_bound3(const CostTensor3& cost, const BranchAndBoundOptions& options,
                                  BranchAndBoundStats* stats) {
  options.validate();
  const auto t0 = std::chrono::steady_clock::now();
  const CanonicalProblem3 p = make_canonical(cost);
  LagrangianOptions root = options.root;
  root.local_search = true;
  root.time_limit_s = std::min(root.time_limit_s, options.time_limit_s);
  const LagrangianRun run = run_lagrangian(p, root);

  Solution3 s;
  double lower_bound = run.lower_bound, root_bound = run.lower_bound;
  std::vector<Tuple3> best = run.best_tuples;
  int64_t nodes = 0;
  Termination termination = Termination::kOptimal;
  CliqueRelaxation cut;
  SearchOutcome outcome;
  bool penalised_search = false;
  if (run.termination == Termination::kInfeasible && run.best_tuples.empty() && run.lower_bound == kInf) {
    termination = Termination::kInfeasible;
  } else if (run.termination == Termination::kOptimal) {
    lower_bound = run.upper_bound;
  } else if (options.cuts.max_rounds > 0 && !p.padded) {  // padded cubes (dummies): 4× slower with cuts
    cut = run_clique_relaxation(p, root, options.cuts, run, t0);
    root_bound = lower_bound = std::max(run.lower_bound, cut.lower_bound);
    best = cut.best_tuples;
    if (cut.termination == Termination::kOptimal) {
      lower_bound = cut.upper_bound;
    } else {
      // Search on the penalised costs when the cuts lift the unrounded bound (ap3.50.4: 270.003 →
      // 270.965, both rounding to 271): the narrower gap fixes more tuples and every node's bound
      // keeps the cuts. Else on b, from the cut phase's incumbent.
      const RootReducedCosts plain =
          root_reduced_costs(p.tensor, p.tensor.cost.data(), 0.0, run.best_multipliers);
      const RootReducedCosts penalised =
          root_reduced_costs(p.tensor, cut.penalised.data(), -cut.lambda_sum, cut.mu);
      penalised_search = penalised.raw > plain.raw;
      if (penalised_search)
        outcome = search_from_root(p, options, cut.penalised.data(), -cut.lambda_sum, &cut, cut.mu, penalised,
                                   cut.best_tuples, cut.upper_bound, root_bound, t0);
      else
        outcome = search_from_root(p, options, p.tensor.cost.data(), 0.0, nullptr, run.best_multipliers,
                                   plain, cut.best_tuples, cut.upper_bound, root_bound, t0);
    }
  } else {
    const RootReducedCosts plain =
        root_reduced_costs(p.tensor, p.tensor.cost.data(), 0.0, run.best_multipliers);
    outcome = search_from_root(p, options, p.tensor.cost.data(), 0.0, nullptr, run.best_multipliers, plain,
                               run.best_tuples, run.upper_bound, root_bound, t0);
  }
  if (outcome.passes > 0) {
    best = std::move(outcome.best);
    lower_bound = outcome.lower_bound;
    termination = outcome.termination;
    nodes = outcome.nodes;
  }
  s.tuples = to_original(p, best);
  s.summary.iterations = nodes;
  s.summary.sweeps = run.iterations;
  s.summary.termination = termination;
  finish_summary(
      cost, s.tuples,
      termination == Termination::kInfeasible ? std::numeric_limits<double>::quiet_NaN() : lower_bound,
      s.summary);
  if (termination == Termination::kOptimal && s.summary.feasible) {
    s.summary.lower_bound = s.summary.objective;
    s.summary.gap = s.summary.abs_gap = 0.0;
  }
  s.summary.message = "nodes " + std::to_string(nodes) + ", root relaxation iterations " +
                      std::to_string(run.iterations) + ", clique cuts " + std::to_string(cut.roots.size()) +
                      " in " + std::to_string(cut.rounds) + " rounds (" + std::to_string(cut.iterations) +
                      " iterations), root bound " + bound_text(root_bound) + ", search passes " +
                      std::to_string(outcome.passes) + ", tuples fixed by reduced cost " +
                      std::to_string(outcome.fixed_tuples);
  s.summary.wall_time_s = seconds_since(t0);
  if (stats)
    *stats = {root_bound,           nodes,           cut.roots.size(), cut.rounds, outcome.passes,
              outcome.fixed_tuples, penalised_search};
  return s;
}

}  // namespace trackassoc
