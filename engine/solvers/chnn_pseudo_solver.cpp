// seed 004's CHNN with pseudo-tracks as the registry's chnn-pseudo S-D solver; see
// engine/solvers/chnn_pseudo_solver.hpp.
#include "engine/solvers/chnn_pseudo_solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

// Members of a tuple whose tensor cost is +inf (possible only for the CHNN without Eq. 12's gate)
// are split into tuples of one track each.
void split_forbidden(const CostTensorSD& c, std::vector<int32_t>& tuples) {
  const int32_t S = c.dims();
  std::vector<int32_t> out;
  out.reserve(tuples.size());
  for (std::size_t k = 0; k < tuples.size(); k += S) {
    const std::span<const int32_t> t(tuples.data() + k, S);
    if (std::isfinite(c.at(t))) {
      out.insert(out.end(), t.begin(), t.end());
      continue;
    }
    for (int32_t s = 0; s < S; ++s)
      if (t[s] >= 0) {
        std::vector<int32_t> one(S, kNoTrack);
        one[s] = t[s];
        out.insert(out.end(), one.begin(), one.end());
      }
  }
  tuples.swap(out);
}

ChnnPseudoSolverOptions chnn_options(const nlohmann::json& o, uint64_t seed, ChnnPseudoSolverOptions c) {
  c.network.seed = seed;
  chnn_pseudo_option_fields().read(o, c, "chnn-pseudo");
  require(c.lambda_margin > 0.0 && std::isfinite(c.lambda_margin), "chnn-pseudo options: lambda_margin",
          "must be > 0");
  c.network.validate();
  return c;
}

}  // namespace

const OptionFields<ChnnPseudoSolverOptions>& chnn_pseudo_option_fields() {
  using O = ChnnPseudoSolverOptions;
  using N = ChnnPseudoOptions;
  static const OptionFields<O> fields{{
      field("A", path(&O::network, &N::A), ">= 0", "energy weight of term 1 (seed 004 Eq. 7)"),
      field("B", path(&O::network, &N::B), "> 0", "energy weight of term 2"),
      field("C", path(&O::network, &N::C), "> 0", "energy weight of term 3"),
      field("D", path(&O::network, &N::D), ">= 0", "energy weight of term 4"),
      field("dt", path(&O::network, &N::dt), "> 0", "Euler step"),
      field("tau", path(&O::network, &N::tau), ">= 0", "decay time constant (0 = no decay)"),
      field("u0", path(&O::network, &N::u0), "> 0", "gain 1/u0 of V = ½(1 + tanh(u/u0))"),
      field("max_steps", path(&O::network, &N::max_steps), ">= 1", "Euler steps per pass at most"),
      field("tolerance", path(&O::network, &N::tolerance), "> 0",
            "converged when max |Δu|/u0 of a step is below"),
      field("noise", path(&O::network, &N::noise), ">= 0", "initial u noise·N(0,1)"),
      field("gated", &O::gated, "", "λ = +inf outside the gate (Eq. 12)"),
      field("lambda_margin", &O::lambda_margin, "> 0", "pseudo-track cost (1 + margin)·γ"),
      field("reference", &O::reference, "a sensor position",
            "the sensor taken first (default: the most tracks)"),
      field("leftover_passes", path(&O::network, &N::leftover_passes), ">= -1",
            "extra passes over the tracks left alone (−1 = S − 2, 0 = the paper's one pass)"),
  }};
  return fields;
}

PseudoTrackInput pseudo_track_input(const SDProblemView& p, bool gated, double lambda_margin,
                                    int32_t reference) {
  const int32_t S = p.S();
  require(reference >= 0 && reference < S, "chnn-pseudo options: reference",
          "must be a sensor position in 0.." + std::to_string(S - 1));
  std::vector<int32_t> order{reference};
  for (int32_t s = 0; s < S; ++s)
    if (s != reference) order.push_back(s);
  PseudoTrackInput in;
  in.n.resize(S);
  for (int32_t s = 0; s < S; ++s) in.n[s] = p.tracks[order[s]];
  in.distance.resize(static_cast<std::size_t>(S) * S);
  in.pseudo_cost.assign(in.distance.size(), 1.0);
  for (int32_t a = 0; a < S; ++a)
    for (int32_t b = a + 1; b < S; ++b) {
      const int32_t oa = order[a], ob = order[b];
      const bool swap = oa > ob;
      const std::size_t slot = static_cast<std::size_t>(std::min(oa, ob)) * S + std::max(oa, ob);
      const PairStatistic& st = p.pairs[slot];
      auto& d = in.distance[PseudoTrackInput::pair(a, b, S)];
      d.assign(static_cast<std::size_t>(in.n[a]) * in.n[b], std::numeric_limits<double>::infinity());
      for (int32_t i = 0; i < in.n[a]; ++i)
        for (int32_t k = 0; k < in.n[b]; ++k) {
          const std::size_t e =
              swap ? static_cast<std::size_t>(k) * st.n_b + i : static_cast<std::size_t>(i) * st.n_b + k;
          if (st.dof[e] <= 0 || (gated && !st.in_gate[e])) continue;  // Eq. 12: outside the gate → ∞
          d[static_cast<std::size_t>(i) * in.n[b] + k] = st.lambda[e];
        }
      in.pseudo_cost[PseudoTrackInput::pair(a, b, S)] = (1.0 + lambda_margin) * p.gate[slot];
    }
  return in;
}

SolutionSD solve_chnn_sd(const SDProblemView& p, const nlohmann::json& options, uint64_t seed,
                         ChnnPseudoResult* raw) {
  SolutionSD sol;
  ChnnPseudoSolverOptions defaults;
  for (int32_t s = 1; s < p.S(); ++s)
    if (p.tracks[s] > p.tracks[defaults.reference]) defaults.reference = s;
  const ChnnPseudoSolverOptions co = chnn_options(options, seed, defaults);
  const int32_t reference = co.reference;
  const ChnnPseudoResult r =
      solve_chnn_pseudo(pseudo_track_input(p, co.gated, co.lambda_margin, reference), co.network);
  // Back to tensor order: position 0 is `reference`, then the others in order.
  const int32_t S = p.S();
  std::vector<int32_t> order{reference};
  for (int32_t s = 0; s < S; ++s)
    if (s != reference) order.push_back(s);
  sol.S = S;
  sol.tuples.resize(r.solution.tuples.size());
  for (std::size_t k = 0; k < r.solution.tuples.size(); k += S)
    for (int32_t s = 0; s < S; ++s) sol.tuples[k + order[s]] = r.solution.tuples[k + s];
  split_forbidden(*p.tensor, sol.tuples);
  sol.summary = r.solution.summary;
  finish_summary_sd(*p.tensor, sol.tuples, std::numeric_limits<double>::quiet_NaN(), sol.summary);
  if (raw) *raw = r;
  return sol;
}

}  // namespace trackassoc
