// seed 004's continuous Hopfield network with pseudo-tracks (kernels/hopfield/chnn_pseudo.hpp) as
// an S-D solver: the registry's chnn-pseudo (engine/solvers/solver_registry.hpp), on the whole S-D
// problem (it needs the distances λ and the gates, not only the cost tensor). Options: A, B, C, D,
// dt, tau, u0, max_steps, tolerance, noise, leftover_passes (−1 = S − 2, 0 = the paper's single
// pass), gated (Eq. 12, default true), lambda_margin (λ = (1 + margin)·γ, default 0.1), and
// reference (a sensor position; default: the sensor with the most tracks). Its tuples are scored
// on the problem's S-D cost tensor, so objectives compare with the tensor solvers'.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>

#include "engine/solvers/option_fields.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "kernels/hopfield/chnn_pseudo.hpp"

namespace trackassoc {

// Seed 004's inputs from the problem: distances λ (gated: +inf outside the gate, Eq. 12), and
// pseudo-track costs (1 + margin)·γ; sensors reordered so that `reference` comes first.
PseudoTrackInput pseudo_track_input(const SDProblemView& p, bool gated, double lambda_margin,
                                    int32_t reference);

// The options of chnn-pseudo (header comment): the network's, and how its inputs are built.
struct ChnnPseudoSolverOptions {
  ChnnPseudoOptions network;  // seed: the run's seed, not an option
  bool gated = true;
  double lambda_margin = 0.1;
  int32_t reference = 0;  // solve_chnn_sd's default: the sensor with the most tracks
};
const OptionFields<ChnnPseudoSolverOptions>& chnn_pseudo_option_fields();

// The chnn-pseudo solver alone; `raw`, when given, receives the network's own result (neurons,
// Euler steps, convergence).
SolutionSD solve_chnn_sd(const SDProblemView& p, const nlohmann::json& options, uint64_t seed,
                         ChnnPseudoResult* raw = nullptr);

}  // namespace trackassoc
