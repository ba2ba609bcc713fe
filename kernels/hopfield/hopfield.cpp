#include "kernels/hopfield/hopfield.hpp"

#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <numeric>
#include <utility>

#include "kernels/assignment/local_search.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/radix_sort.hpp"
#include "kernels/core/random.hpp"
#include "kernels/hopfield/hopfield_continuous.hpp"
#include "kernels/hopfield/hopfield_diagonal.hpp"
#include "kernels/hopfield/hopfield_discrete.hpp"

namespace trackassoc {

const char* hopfield_schedule_label(const HopfieldOptions& o) {
  return o.network == HopfieldNetwork::kContinuous ? enum_name(o.network) : enum_name(o.schedule);
}

void SliceRandomOrder::draw(int32_t n1, int32_t n2, int32_t n3, CounterRng& rng) {
  if (slices.size() != static_cast<std::size_t>(n1)) {
    slices.resize(n1);
    std::iota(slices.begin(), slices.end(), 0u);
    packed_jk.clear();
    for (int32_t j = 0; j < n2; ++j)
      for (int32_t k = 0; k < n3; ++k)
        packed_jk.push_back(static_cast<uint32_t>(j) << 16 | static_cast<uint32_t>(k));
    rotation.assign(n1, 0);
  }
  rng.shuffle(std::span<uint32_t>(slices));
  rng.shuffle(std::span<uint32_t>(packed_jk));
  for (auto& r : rotation) r = static_cast<uint32_t>(rng.uniform_int(packed_jk.size()));
}

void HopfieldOptions::validate() const {
  require(restarts >= 1 && restarts <= 100000, "restarts", "expected 1..100000");
  require(max_sweeps >= 1, "max_sweeps", "expected >= 1");
  require(init_density > 0 && std::isfinite(init_density), "init_density", "expected > 0");
  require(greedy_noise >= 0 && std::isfinite(greedy_noise), "greedy_noise", "expected >= 0");
  require(anneal_E_factor >= 1 && std::isfinite(anneal_E_factor), "anneal_E_factor", "expected >= 1");
  require(anneal_sweeps >= 0, "anneal_sweeps", "expected >= 0");
  require(temperature >= 0 && std::isfinite(temperature), "temperature", "expected >= 0");
  require(damping > 0 && damping <= 1, "damping", "expected in (0, 1]");
  require(dt > 0 && std::isfinite(dt), "dt", "expected > 0");
  require(tau >= 0 && std::isfinite(tau), "tau", "expected >= 0 (0 = no decay)");
  require(u0_start > 0 && u0_end > 0 && std::isfinite(u0_start) && std::isfinite(u0_end), "u0_start/u0_end",
          "expected > 0");
  require(noise >= 0 && std::isfinite(noise), "noise", "expected >= 0");
  require(self_excitation >= 0 && self_excitation <= 1, "self_excitation", "expected in [0, 1]");
  require(tolerance > 0, "tolerance", "expected > 0");
  require(mean_field_steps >= 1, "mean_field_steps", "expected >= 1");
  require(gain_anneal_steps >= 0, "gain_anneal_steps", "expected >= 0");
  if (!auto_weights) {
    for (float x : {weights.A, weights.B, weights.C, weights.D, weights.E})
      require(x >= 0 && std::isfinite(x), "weights", "A, B, C, D, E must be finite and >= 0");
  }
  const bool discrete = network == HopfieldNetwork::kDiscrete;
  if (discrete && schedule == HopfieldSchedule::kDiagonal) {
    require(energy == HopfieldEnergy::kFullPlane, "schedule 'diagonal'", "needs the full-plane energy");
    require(auto_weights || weights.D == 0.f, "schedule 'diagonal'", "needs D = 0");
  }
  if (!discrete)
    require(energy == HopfieldEnergy::kFullPlane, "schedule 'continuous'", "needs the full-plane energy");
}

std::vector<uint32_t> ascending_cost_order(std::span<const float> c) {
  const std::size_t K = c.size();
  require(K < (std::size_t{1} << 32), "cost order", "more than 2^32 entries");
  // Radix sort of (key, index) (kernels/core/radix_sort.hpp): stable, so ties keep ascending index
  // order, and a stable sort's output is unique: its parallel chunks (this is part of the serial
  // prologue of the restarts) cannot change it.
  struct Entry {
    uint32_t key, index;
  };
  std::vector<Entry> entries(K), buffer;
  // Keys whose unsigned order is the float order (sign flip for ≥ 0, complement for < 0; −0 as +0).
  parallel_for_range(K, 16384, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t a = lo; a < hi; ++a) {
      uint32_t bits;
      std::memcpy(&bits, &c[a], sizeof bits);
      if (bits == 0x80000000u) bits = 0;
      entries[a] = {(bits & 0x80000000u) ? ~bits : bits | 0x80000000u, static_cast<uint32_t>(a)};
    }
  });
  radix_sort_by_key(
      entries, buffer, [](const Entry& e) { return uint64_t{e.key}; },
      std::clamp<std::size_t>(K / 16384, 1, 16));
  std::vector<Entry>().swap(buffer);
  std::vector<uint32_t> order(K);
  parallel_for_range(K, 16384, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t a = lo; a < hi; ++a) order[a] = entries[a].index;
  });
  return order;
}

HopfieldWeights hopfield_weights(const HopfieldOptions& o, const NormalisedCost& c) {
  HopfieldWeights w = o.weights;
  if (o.auto_weights) {
    // ĉ ∈ [0, 1]: E just below the fixed-point bound keeps every valid assignment a fixed point
    // and (full plane) lets every triple of free planes switch on. The printed energy needs its
    // D term (see fixed_point_E_bound).
    w.A = w.B = w.C = 1.f;
    w.D = o.energy == HopfieldEnergy::kFullPlane ? 0.f : 1.f;
    w.E = static_cast<float>(0.999 * fixed_point_E_bound(o.energy, w));
  }
  w.N = std::min({c.n1, c.n2, c.n3});
  return w;
}

namespace {

using Clock = std::chrono::steady_clock;

// Cost-ordered greedy state: neurons by ĉ (+ noise·U(0,1)), each kept if its planes are free.
std::vector<uint8_t> greedy_state(const NormalisedCost& c, double noise, CounterRng& rng) {
  const std::size_t K = c.size();
  const int32_t m = std::min({c.n1, c.n2, c.n3});
  std::vector<std::pair<float, uint32_t>> keys(K);
  for (std::size_t a = 0; a < K; ++a)
    keys[a] = {c.c[a] + (noise > 0 ? static_cast<float>(noise * rng.uniform()) : 0.f),
               static_cast<uint32_t>(a)};
  std::vector<uint8_t> V(K, 0), ui(c.n1, 0), uj(c.n2, 0), uk(c.n3, 0);
  int32_t taken = 0;
  // Sort a cheap prefix first; the full sort only if the prefix does not complete the assignment.
  std::size_t prefix = std::min<std::size_t>(K, static_cast<std::size_t>(64) * std::max(m, 1));
  std::size_t done = 0;
  while (taken < m && done < K) {
    std::nth_element(keys.begin() + done, keys.begin() + (prefix - 1), keys.end());
    std::sort(keys.begin() + done, keys.begin() + prefix);
    for (std::size_t p = done; p < prefix && taken < m; ++p) {
      const uint32_t a = keys[p].second;
      const int32_t k = static_cast<int32_t>(a % c.n3), j = static_cast<int32_t>((a / c.n3) % c.n2);
      const int32_t i = static_cast<int32_t>(a / (static_cast<uint32_t>(c.n3) * c.n2));
      if (ui[i] || uj[j] || uk[k]) continue;
      ui[i] = uj[j] = uk[k] = 1;
      V[a] = 1;
      ++taken;
    }
    done = prefix;
    prefix = K;
  }
  return V;
}

ContinuousNetwork anneal_continuous(const NormalisedCost& c, const HopfieldOptions& o,
                                    const HopfieldWeights& w, CounterRng& rng, HopfieldRestart& rec);

std::vector<uint8_t> initial_state(const HopfieldOptions& o, const NormalisedCost& c,
                                   const HopfieldWeights& w, int32_t restart, CounterRng& rng,
                                   HopfieldRestart& rec) {
  const std::size_t K = c.size();
  switch (o.init) {
    case HopfieldInit::kZero:
      return std::vector<uint8_t>(K, 0);
    case HopfieldInit::kRandom: {
      const double p = std::min(1.0, o.init_density * std::min({c.n1, c.n2, c.n3}) / static_cast<double>(K));
      std::vector<uint8_t> V(K);
      for (auto& v : V) v = rng.uniform() < p;
      return V;
    }
    case HopfieldInit::kGreedy:
      return greedy_state(c, restart == 0 ? 0.0 : o.greedy_noise, rng);
    case HopfieldInit::kMeanField: {
      HopfieldRestart mf;  // the mean-field phase: its steps are counted in rec.sweeps below
      HopfieldOptions co = o;
      co.max_sweeps = o.mean_field_steps;
      co.trace = false;
      // The mean-field phase always uses the automatic full-plane weights (whatever the discrete
      // energy): it is a start heuristic, measured with these weights.
      HopfieldOptions fo;
      const HopfieldWeights cw = hopfield_weights(fo, c);
      const ContinuousNetwork net = anneal_continuous(c, co, cw, rng, mf);
      rec.mean_field_steps = mf.sweeps;
      std::vector<uint8_t> V(K);
      for (std::size_t a = 0; a < K; ++a) V[a] = net.V[a] > 0.5f;
      return V;
    }
  }
  return {};
}

double E_at(const HopfieldOptions& o, const HopfieldWeights& w, int64_t sweep) {
  if (sweep >= o.anneal_sweeps || o.anneal_E_factor == 1.0) return w.E;
  return w.E * std::pow(o.anneal_E_factor, 1.0 - static_cast<double>(sweep) / o.anneal_sweeps);
}

struct RestartOutput {
  HopfieldRestart record;
  std::vector<Tuple3> tuples;
};

void finish_restart(const CostTensor3& cost, const HopfieldOptions& o, std::span<const uint32_t> priority,
                    RestartOutput& out) {
  out.tuples = repair_assignment(cost, priority, o.repair);
  out.record.repaired_objective = assignment_cost(cost, out.tuples);
  if (o.polish) out.tuples = solve_local_search3(cost, out.tuples).tuples;
  out.record.objective = assignment_cost(cost, out.tuples);
}

RestartOutput run_discrete(const CostTensor3& cost, const NormalisedCost& c, const HopfieldOptions& o,
                           const HopfieldWeights& w, const OrderedSweepPlan* cost_plan,
                           const std::shared_ptr<const DiagonalCost>& diagonal_cost, uint64_t seed,
                           int32_t restart) {
  CounterRng rng(seed, 0, static_cast<uint64_t>(restart));
  RestartOutput out;
  HopfieldRestart& rec = out.record;
  const std::vector<uint8_t> V0 = initial_state(o, c, w, restart, rng, rec);
  DiscreteNetwork net(o.energy, w, c);
  net.set_state(V0);
  const bool diag = o.schedule == HopfieldSchedule::kDiagonal;
  std::unique_ptr<DiagonalNetwork> dnet;
  std::vector<uint32_t> order;
  SliceRandomOrder slice_order;
  if (diag) {
    dnet = std::make_unique<DiagonalNetwork>(w, diagonal_cost);
    dnet->set_state(V0);
    order.resize(dnet->num_blocks());
    std::iota(order.begin(), order.end(), 0u);
  } else if (o.schedule == HopfieldSchedule::kAsync) {
    if (o.order == HopfieldOrder::kCost && o.temperature > 0)
      order = cost_plan->neuron;
    else if (o.order == HopfieldOrder::kRandom || o.temperature > 0) {
      order.resize(c.size());
      std::iota(order.begin(), order.end(), 0u);
    }
  }
  uint64_t hash_prev = net.hash, hash_prev2 = ~net.hash;
  rec.termination = Termination::kIterationLimit;
  for (int64_t s = 0; s < o.max_sweeps; ++s) {
    const float E = static_cast<float>(E_at(o, w, s));
    int64_t flips = 0;
    if (diag) {
      dnet->set_E(E);
      rng.shuffle(std::span<uint32_t>(order));
      flips = dnet->sweep(order);
    } else if (o.schedule == HopfieldSchedule::kAsync) {
      net.w.E = E;
      if (o.order == HopfieldOrder::kRandom) rng.shuffle(std::span<uint32_t>(order));
      const double T =
          s < o.anneal_sweeps ? o.temperature * (1.0 - static_cast<double>(s) / o.anneal_sweeps) : 0.0;
      if (o.order == HopfieldOrder::kSliceRandom && T == 0.0) {
        slice_order.draw(c.n1, c.n2, c.n3, rng);
        flips = async_sweep_slices(net, slice_order.slices, slice_order.packed_jk, slice_order.rotation);
      } else if (o.order == HopfieldOrder::kCost && T == 0.0) {
        flips = async_sweep_planned(net, *cost_plan);
      } else {
        if (o.order == HopfieldOrder::kSliceRandom) rng.shuffle(std::span<uint32_t>(order));
        flips = async_sweep(net, order, T, &rng);
      }
    } else {
      net.w.E = E;
      flips = sync_sweep(net, o.damping, stream_key(seed, restart, s)).flips;
    }
    rec.sweeps = s + 1;
    if (o.trace) {
      if (diag) dnet->get_state(net.V);
      rec.energy_trace.push_back(static_cast<float>(hopfield_energy(o.energy, net.w, c, net.V)));
    }
    const bool annealing = s + 1 < o.anneal_sweeps && o.anneal_E_factor != 1.0;
    if (flips == 0 && !annealing && !(o.temperature > 0 && s + 1 < o.anneal_sweeps)) {
      rec.termination = Termination::kConverged;
      break;
    }
    if (o.schedule == HopfieldSchedule::kSync && o.damping >= 1.0 && !annealing) {
      if (net.hash == hash_prev2) {
        rec.termination = Termination::kCycle;
        break;
      }
      hash_prev2 = hash_prev;
      hash_prev = net.hash;
    }
  }
  if (diag) dnet->get_state(net.V);
  net.w.E = w.E;
  rec.energy = hopfield_energy(o.energy, w, c, net.V);
  rec.raw_feasible = is_valid_state(net.V, c.n1, c.n2, c.n3);
  finish_restart(cost, o, active_by_cost(net.V, cost), out);
  return out;
}

// Anneals the continuous network of one restart (mean-field annealing of the gain); fills the
// sweeps, termination and trace of `rec`.
ContinuousNetwork anneal_continuous(const NormalisedCost& c, const HopfieldOptions& o,
                                    const HopfieldWeights& w, CounterRng& rng, HopfieldRestart& rec) {
  const double K = static_cast<double>(c.size());
  const double v_init = std::clamp(w.N / K, 1e-6, 0.5);
  ContinuousNetwork net(c);
  const float u_init = static_cast<float>(o.u0_start * std::atanh(2.0 * v_init - 1.0));
  net.initialise(u_init, static_cast<float>(o.noise * o.u0_start), static_cast<float>(o.u0_start), rng);
  ContinuousParams p;
  p.w = w;
  p.dt = static_cast<float>(o.dt);
  p.tau = static_cast<float>(o.tau);
  p.self_excitation = static_cast<float>(o.self_excitation);
  std::vector<uint32_t> order;
  if (o.continuous_async) {
    order.resize(c.size());
    std::iota(order.begin(), order.end(), 0u);
  }
  rec.termination = Termination::kIterationLimit;
  for (int64_t s = 0; s < o.max_sweeps; ++s) {
    const double f =
        o.gain_anneal_steps > 0 ? std::min(1.0, static_cast<double>(s) / o.gain_anneal_steps) : 1.0;
    p.u0 = static_cast<float>(o.u0_start * std::pow(o.u0_end / o.u0_start, f));
    float dmax;
    if (o.continuous_async) {
      rng.shuffle(std::span<uint32_t>(order));
      dmax = continuous_async_step(net, p, order);
    } else {
      dmax = continuous_sync_step(net, p);
    }
    rec.sweeps = s + 1;
    if (o.trace) rec.energy_trace.push_back(static_cast<float>(net.energy(w)));
    if (s + 1 >= o.gain_anneal_steps && dmax < o.tolerance) {
      rec.termination = Termination::kConverged;
      break;
    }
  }
  return net;
}

RestartOutput run_continuous(const CostTensor3& cost, const NormalisedCost& c, const HopfieldOptions& o,
                             const HopfieldWeights& w, uint64_t seed, int32_t restart) {
  CounterRng rng(seed, 0, static_cast<uint64_t>(restart));
  RestartOutput out;
  HopfieldRestart& rec = out.record;
  const ContinuousNetwork net = anneal_continuous(c, o, w, rng, rec);
  rec.energy = net.energy(w);
  std::vector<uint8_t> binary(c.size());
  for (std::size_t a = 0; a < binary.size(); ++a) binary[a] = net.V[a] > 0.5f;
  rec.raw_feasible = is_valid_state(binary, c.n1, c.n2, c.n3);
  finish_restart(cost, o, active_by_output(net.V, 0.5f), out);
  return out;
}

}  // namespace

HopfieldResult solve_hopfield(const CostTensor3& cost, const HopfieldOptions& options, uint64_t seed) {
  options.validate();
  const auto t0 = Clock::now();
  require(cost.n1 >= 0 && cost.n2 >= 0 && cost.n3 >= 0 &&
              cost.size() == static_cast<std::size_t>(cost.n1) * cost.n2 * cost.n3,
          "cost tensor", "size does not match n1·n2·n3");
  require(cost.size() < (std::size_t{1} << 32), "cost tensor", "more than 2^32 neurons; use the sparse form");
  require(std::none_of(cost.cost.begin(), cost.cost.end(), [](float b) { return std::isnan(b); }),
          "cost tensor", "NaN cost");
  HopfieldResult result;
  const NormalisedCost c = normalise_cost(cost);
  result.weights = hopfield_weights(options, c);
  const int32_t m = std::min({cost.n1, cost.n2, cost.n3});
  if (m == 0) {
    result.solution.summary.termination = Termination::kConverged;
    result.solution.summary.feasible = true;
    result.solution.summary.objective = 0.0;
    result.raw_validity_rate = 1.0;
    return result;
  }
  const bool discrete = options.network == HopfieldNetwork::kDiscrete;
  if (discrete && options.schedule == HopfieldSchedule::kDiagonal)
    require(cost.n1 <= cost.n2 && cost.n1 <= cost.n3, "schedule 'diagonal'", "needs n1 <= n2 and n1 <= n3");
  // Shared by every restart, built once (the serial part of the solve: keep it O(n1n2n3) and small).
  std::unique_ptr<const OrderedSweepPlan> cost_plan;
  if (discrete && options.schedule == HopfieldSchedule::kAsync && options.order == HopfieldOrder::kCost)
    cost_plan = std::make_unique<const OrderedSweepPlan>(ascending_cost_order(c.c), c);
  std::shared_ptr<const DiagonalCost> diagonal_cost;
  if (discrete && options.schedule == HopfieldSchedule::kDiagonal)
    diagonal_cost = std::make_shared<const DiagonalCost>(c);
  std::vector<RestartOutput> outs(options.restarts);
  // One task per restart, balanced dynamically (restarts differ in their number of sweeps; a
  // static split of 8 restarts into 4 + 4 leaves one thread idle at the end). Each restart reads
  // only its own stream CounterRng(seed, 0, r), so the schedule does not change any result.
  // A restart's own parallel loops (continuous and sync steps) run isolated: a thread waiting for
  // them must not pick up another whole restart meanwhile, which would hold up this one.
  tbb::parallel_for(
      0, options.restarts,
      [&](int32_t r) {
        tbb::this_task_arena::isolate([&] {
          outs[r] = !discrete ? run_continuous(cost, c, options, result.weights, seed, r)
                              : run_discrete(cost, c, options, result.weights, cost_plan.get(), diagonal_cost,
                                             seed, r);
        });
      },
      tbb::simple_partitioner());
  int32_t best = 0;
  int64_t total_sweeps = 0, raw = 0;
  for (int32_t r = 0; r < options.restarts; ++r) {
    total_sweeps += outs[r].record.sweeps;
    raw += outs[r].record.raw_feasible;
    if (outs[r].record.objective < outs[best].record.objective) best = r;
  }
  result.best_restart = best;
  result.raw_validity_rate = static_cast<double>(raw) / options.restarts;
  result.solution.tuples = std::move(outs[best].tuples);
  SolverSummary& sum = result.solution.summary;
  sum.termination = outs[best].record.termination;
  sum.feasible = is_valid_assignment(cost, result.solution.tuples);
  sum.objective = assignment_cost(cost, result.solution.tuples);
  sum.sweeps = outs[best].record.sweeps;
  sum.iterations = total_sweeps;
  for (auto& o : outs) result.restarts.push_back(std::move(o.record));
  sum.wall_time_s = std::chrono::duration<double>(Clock::now() - t0).count();
  sum.message = std::string(hopfield_schedule_label(options)) + " " + enum_name(options.energy) +
                ": raw validity " + std::to_string(raw) + "/" + std::to_string(options.restarts) +
                ", best restart " + std::to_string(best);
  return result;
}

RestartTable hopfield_restart_table(const HopfieldResult& result) {
  RestartTable t;
  for (std::size_t r = 0; r < result.restarts.size(); ++r) {
    const HopfieldRestart& rr = result.restarts[r];
    t.restart.push_back(static_cast<int32_t>(r));
    t.valid_raw.push_back(rr.raw_feasible ? 1 : 0);
    t.sweeps.push_back(static_cast<int32_t>(rr.sweeps));
    t.mean_field_steps.push_back(static_cast<int32_t>(rr.mean_field_steps));
    t.energy.push_back(rr.energy);
    t.repaired_objective.push_back(rr.repaired_objective);
    t.objective.push_back(rr.objective);
  }
  return t;
}

}  // namespace trackassoc
