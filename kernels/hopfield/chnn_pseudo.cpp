#include "kernels/hopfield/chnn_pseudo.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <string>

#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/random.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

void PseudoTrackInput::validate() const {
  const int32_t S = static_cast<int32_t>(n.size());
  require(S >= 2, "PseudoTrackInput.n", "needs at least 2 sensors, got " + std::to_string(S));
  require(distance.size() == static_cast<std::size_t>(S) * S && pseudo_cost.size() == distance.size(),
          "PseudoTrackInput", "distance and pseudo_cost need S×S pair slots");
  for (int32_t a = 0; a < S; ++a) {
    require(n[a] >= 0, "PseudoTrackInput.n", "negative track count for sensor " + std::to_string(a));
    for (int32_t b = a + 1; b < S; ++b) {
      const std::string where =
          "PseudoTrackInput pair (" + std::to_string(a) + ", " + std::to_string(b) + ")";
      const auto& d = distance[pair(a, b, S)];
      require(d.size() == static_cast<std::size_t>(n[a]) * n[b], where, "distance matrix has the wrong size");
      for (double x : d) require(!std::isnan(x) && x >= 0.0, where, "distances must be >= 0 (or +inf)");
      const double l = pseudo_cost[pair(a, b, S)];
      require(std::isfinite(l) && l > 0.0, where, "pseudo-track cost λ must be finite and > 0");
    }
  }
}

void ChnnPseudoOptions::validate() const {
  require(A >= 0 && B > 0 && C > 0 && D >= 0 && std::isfinite(A + B + C + D), "ChnnPseudoOptions.A/B/C/D",
          "need A >= 0, B > 0, C > 0, D >= 0, all finite");
  require(dt > 0 && std::isfinite(dt), "ChnnPseudoOptions.dt", "must be > 0");
  require(tau >= 0 && std::isfinite(tau), "ChnnPseudoOptions.tau", "must be >= 0");
  require(u0 > 0 && std::isfinite(u0), "ChnnPseudoOptions.u0", "must be > 0");
  require(max_steps >= 1, "ChnnPseudoOptions.max_steps", "must be >= 1");
  require(tolerance > 0, "ChnnPseudoOptions.tolerance", "must be > 0");
  require(noise >= 0 && std::isfinite(noise), "ChnnPseudoOptions.noise", "must be >= 0");
  require(leftover_passes >= -1, "ChnnPseudoOptions.leftover_passes", "must be >= -1");
}

namespace {

struct Ref {
  int32_t sensor, track;
};

}  // namespace

PseudoNeurons enumerate_pseudo_neurons(const PseudoTrackInput& in) {
  in.validate();
  const int32_t S = static_cast<int32_t>(in.n.size());
  // Extended index sets: copies of sensors 0 … s−1, then sensor s's own tracks.
  std::vector<std::vector<Ref>> ext(S);
  std::vector<std::vector<int32_t>> block_start(S, std::vector<int32_t>(S, 0));
  for (int32_t s = 0; s < S; ++s) {
    for (int32_t q = 0; q <= s; ++q) {
      block_start[s][q] = static_cast<int32_t>(ext[s].size());
      for (int32_t i = 0; i < in.n[q]; ++i) ext[s].push_back({q, i});
    }
  }
  // Finite neurons by depth-first enumeration of the chain links.
  std::vector<int32_t> idx;  // K×S
  std::vector<double> cost;
  std::vector<int32_t> t(S);
  auto rec = [&](auto&& self, int32_t s, double acc) -> void {
    if (s == S) {
      idx.insert(idx.end(), t.begin(), t.end());
      cost.push_back(acc);
      return;
    }
    const Ref u = ext[s - 1][t[s - 1]];
    const std::size_t p = PseudoTrackInput::pair(u.sensor, s, S);
    t[s] = block_start[s][u.sensor] + u.track;  // the copy of u: "no track at sensor s"
    self(self, s + 1, acc + in.pseudo_cost[p]);
    const double* d = in.distance[p].data() + static_cast<std::size_t>(u.track) * in.n[s];
    for (int32_t k = 0; k < in.n[s]; ++k)
      if (std::isfinite(d[k])) {
        t[s] = block_start[s][s] + k;
        self(self, s + 1, acc + d[k]);
      }
  };
  for (int32_t j = 0; j < in.n[0]; ++j) {
    t[0] = j;
    rec(rec, 1, 0.0);
  }
  PseudoNeurons out;
  out.S = S;
  out.idx = std::move(idx);
  out.cost = std::move(cost);
  out.stands_for.resize(S);
  for (int32_t s = 0; s < S; ++s)
    for (const Ref& r : ext[s]) out.stands_for[s].push_back({r.sensor, r.track});
  return out;
}

namespace {

ChnnPseudoResult solve_once(const PseudoTrackInput& in, const ChnnPseudoOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const PseudoNeurons net = enumerate_pseudo_neurons(in);
  const int32_t S = net.S;
  const std::vector<int32_t>& idx = net.idx;
  std::vector<double> cost = net.cost;
  const auto& ext = net.stands_for;
  std::vector<int32_t> t(S);
  // The reference track j's copies sit at extended index j of every sensor (sensor 0's block is first).
  const std::size_t K = cost.size();
  ChnnPseudoResult res;
  res.neurons = static_cast<int64_t>(K);
  res.solution.S = S;

  // Normalised cost, initial state.
  // ĉ = min(b / b_ref, 2), b_ref = the costliest all-pseudo chain (a tuple dearer than "no match
  // anywhere" is never worth much; without the cap, Eq. 7's far pairs would squash every useful
  // cost difference towards 0).
  double cmax = 0.0;
  for (int32_t s = 1; s < S; ++s) {
    double worst = 0.0;
    for (int32_t q = 0; q < s; ++q) worst = std::max(worst, in.pseudo_cost[PseudoTrackInput::pair(q, s, S)]);
    cmax += worst;
  }
  for (double& c : cost) c = std::min(c / cmax, 2.0);
  std::vector<int32_t> row_size(in.n[0], 0);
  for (std::size_t k = 0; k < K; ++k) ++row_size[idx[k * S]];
  std::vector<float> u(K), V(K), dv(K);
  CounterRng rng(o.seed, 0, 0x5EED004);
  for (std::size_t k = 0; k < K; ++k) {
    const double v0 = std::min(0.99, 1.0 / row_size[idx[k * S]]);
    u[k] = static_cast<float>(o.u0 * std::atanh(2.0 * v0 - 1.0) + o.noise * rng.normal());
    V[k] = static_cast<float>(0.5 * (1.0 + std::tanh(u[k] / o.u0)));
  }
  std::vector<std::vector<double>> R(S);
  for (int32_t s = 0; s < S; ++s) R[s].assign(ext[s].size(), 0.0);
  const double n_ref = in.n[0];
  for (int64_t step = 0; step < o.max_steps; ++step) {
    parallel_for_range(static_cast<std::size_t>(S), 1, [&](std::size_t b, std::size_t e) {
      for (std::size_t s = b; s < e; ++s) {
        std::fill(R[s].begin(), R[s].end(), 0.0);
        for (std::size_t k = 0; k < K; ++k) R[s][idx[k * S + s]] += V[k];
      }
    });
    const double M = std::accumulate(R[0].begin(), R[0].end(), 0.0);
    parallel_for_range(K, 4096, [&](std::size_t b, std::size_t e) {
      for (std::size_t k = b; k < e; ++k) {
        const int32_t* tk = idx.data() + k * S;
        double h = -o.B * (R[0][tk[0]] - 1.0) - o.C * cost[k] - o.D * (M - n_ref);
        for (int32_t s = 1; s < S; ++s) h -= o.A * (R[s][tk[s]] - V[k]);
        const double du = o.dt * ((o.tau > 0.0 ? -u[k] / o.tau : 0.0) + h);
        u[k] = static_cast<float>(u[k] + du);
        V[k] = static_cast<float>(0.5 * (1.0 + std::tanh(u[k] / o.u0)));
        dv[k] = static_cast<float>(std::abs(du) / o.u0);
      }
    });
    res.steps = step + 1;
    // Stationary when no gain-scaled input u/u₀ moves by more than the tolerance (a test on |ΔV|
    // alone would stop at once when every V starts near 0).
    const float max_du = K ? *std::max_element(dv.begin(), dv.end()) : 0.f;
    if (max_du < o.tolerance) {
      res.converged = true;
      break;
    }
  }

  // Decoding: greedy by V, then the all-copies tuple for any reference track left.
  std::vector<std::size_t> order(K);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return V[a] > V[b]; });
  std::vector<std::vector<char>> used(S);
  for (int32_t s = 0; s < S; ++s) used[s].assign(ext[s].size(), 0);
  std::vector<std::vector<char>> real_used(S);
  for (int32_t s = 0; s < S; ++s) real_used[s].assign(in.n[s], 0);
  auto emit = [&](const int32_t* tk) {
    std::vector<int32_t> row(S, kNoTrack);
    for (int32_t s = 0; s < S; ++s) {
      used[s][tk[s]] = 1;
      const auto [sensor, track] = ext[s][tk[s]];
      if (sensor == s) {
        row[s] = track;
        real_used[s][track] = 1;
      }
    }
    res.solution.tuples.insert(res.solution.tuples.end(), row.begin(), row.end());
  };
  for (std::size_t k : order) {
    const int32_t* tk = idx.data() + k * S;
    bool free = true;
    for (int32_t s = 0; s < S && free; ++s) free = !used[s][tk[s]];
    if (free) emit(tk);
  }
  for (int32_t j = 0; j < in.n[0]; ++j)
    if (!used[0][j]) {
      std::fill(t.begin(), t.end(), j);
      emit(t.data());
    }
  for (int32_t s = 1; s < S; ++s)
    for (int32_t i = 0; i < in.n[s]; ++i)
      if (!real_used[s][i]) {
        std::vector<int32_t> row(S, kNoTrack);
        row[s] = i;
        res.solution.tuples.insert(res.solution.tuples.end(), row.begin(), row.end());
      }
  res.solution.summary.termination = res.converged ? Termination::kConverged : Termination::kIterationLimit;
  res.solution.summary.sweeps = res.steps;
  res.wall_time_s = seconds_since(t0);
  res.solution.summary.wall_time_s = res.wall_time_s;
  res.solution.summary.message =
      std::to_string(K) + " neurons, " + std::to_string(res.steps) + " Euler steps";
  return res;
}

}  // namespace

ChnnPseudoResult solve_chnn_pseudo(const PseudoTrackInput& in, const ChnnPseudoOptions& o) {
  o.validate();
  in.validate();
  const auto t0 = std::chrono::steady_clock::now();
  const int32_t S = static_cast<int32_t>(in.n.size());
  ChnnPseudoResult res = solve_once(in, o);
  res.passes = 1;
  const int passes = o.leftover_passes < 0 ? std::max(0, S - 2) : o.leftover_passes;
  for (int pass = 0; pass < passes; ++pass) {
    // Tracks alone in their tuple, per sensor 1 … S−1 (the reference's singletons had their chance).
    std::vector<std::vector<int32_t>> alone(S);
    std::vector<char> keep(res.solution.tuples.size() / S, 1);
    for (std::size_t k = 0; k < keep.size(); ++k) {
      const int32_t* t = res.solution.tuples.data() + k * S;
      int32_t members = 0, sensor = -1;
      for (int32_t s = 0; s < S; ++s)
        if (t[s] >= 0) {
          ++members;
          sensor = s;
        }
      if (members == 1 && sensor > 0) {
        alone[sensor].push_back(t[sensor]);
        keep[k] = 0;
      }
    }
    std::vector<int32_t> sensors;  // sub-problem sensors, the one with most leftovers first
    for (int32_t s = 1; s < S; ++s)
      if (!alone[s].empty()) sensors.push_back(s);
    if (sensors.size() < 2) break;
    std::stable_sort(sensors.begin(), sensors.end(),
                     [&](int32_t a, int32_t b) { return alone[a].size() > alone[b].size(); });
    const int32_t m = static_cast<int32_t>(sensors.size());
    PseudoTrackInput sub;
    sub.n.resize(m);
    sub.distance.resize(static_cast<std::size_t>(m) * m);
    sub.pseudo_cost.assign(sub.distance.size(), 1.0);
    for (int32_t a = 0; a < m; ++a) sub.n[a] = static_cast<int32_t>(alone[sensors[a]].size());
    for (int32_t a = 0; a < m; ++a)
      for (int32_t b = a + 1; b < m; ++b) {
        const int32_t sa = sensors[a], sb = sensors[b];
        const bool swap = sa > sb;
        const std::size_t slot = PseudoTrackInput::pair(std::min(sa, sb), std::max(sa, sb), S);
        const int32_t nb_full = in.n[std::max(sa, sb)];
        auto& d = sub.distance[PseudoTrackInput::pair(a, b, m)];
        d.resize(static_cast<std::size_t>(sub.n[a]) * sub.n[b]);
        for (int32_t i = 0; i < sub.n[a]; ++i)
          for (int32_t k = 0; k < sub.n[b]; ++k) {
            const int32_t ti = alone[sa][i], tk = alone[sb][k];
            d[static_cast<std::size_t>(i) * sub.n[b] + k] =
                swap ? in.distance[slot][static_cast<std::size_t>(tk) * nb_full + ti]
                     : in.distance[slot][static_cast<std::size_t>(ti) * nb_full + tk];
          }
        sub.pseudo_cost[PseudoTrackInput::pair(a, b, m)] = in.pseudo_cost[slot];
      }
    const ChnnPseudoResult more = solve_once(sub, o);
    res.neurons += more.neurons;
    res.steps += more.steps;
    res.converged = res.converged && more.converged;
    ++res.passes;
    std::vector<int32_t> tuples;
    for (std::size_t k = 0; k < keep.size(); ++k)
      if (keep[k])
        tuples.insert(tuples.end(), res.solution.tuples.begin() + k * S,
                      res.solution.tuples.begin() + (k + 1) * S);
    for (std::size_t k = 0; k < more.solution.tuples.size(); k += m) {
      std::vector<int32_t> row(S, kNoTrack);
      for (int32_t a = 0; a < m; ++a)
        if (more.solution.tuples[k + a] >= 0)
          row[sensors[a]] = alone[sensors[a]][more.solution.tuples[k + a]];
      tuples.insert(tuples.end(), row.begin(), row.end());
    }
    res.solution.tuples.swap(tuples);
  }
  res.solution.summary.termination = res.converged ? Termination::kConverged : Termination::kIterationLimit;
  res.solution.summary.sweeps = res.steps;
  res.wall_time_s = seconds_since(t0);
  res.solution.summary.wall_time_s = res.wall_time_s;
  res.solution.summary.message = std::to_string(res.neurons) + " neurons, " + std::to_string(res.steps) +
                                 " Euler steps, " + std::to_string(res.passes) + " pass(es)";
  return res;
}

}  // namespace trackassoc
