// Decoding of solver tuples into output tuples, shared by the dense (engine/pipeline/pipeline.hpp) and the
// sparse (engine/pipeline/sparse_pipeline.hpp) three-sensor pipelines, which differ only in how they look
// up a pair's gated-in λ.
//
// Rules (docs/design.md §4.3, "Decoding"):
//  * split_tuple: a solver tuple whose chained pairs (1–2 and 2–3; with the all-pairs cost form
//    also 1–3) are all inside the gate is kept whole; otherwise its best gated-in pair by λ is kept
//    and the remaining tracks are left over.
//  * pair_leftovers: the tracks left over by splitting and those a solver left unassigned
//    (unequal track counts, or a finite miss cost) are paired greedily by ascending gated-in λ, so
//    that a target seen by two of the three sensors is still grouped; the rest stay alone.
//    Without this step such a target loses its pair whenever the solver's min(n1, n2, n3) tuples
//    join its tracks to other targets' tracks (with the chain cost, always for a target that the
//    middle sensor missed: the tensor never rewards a 1–3 pair).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "kernels/assignment/assignment_types.hpp"

namespace trackassoc {

// λ of the pair (a, b) of sensors pair q (0: sensors 0–1, 1: sensors 1–2, 2: sensors 0–2), NaN
// when the pair is outside the gate. Indices are the pipeline's track indices per sensor.
using GatedLambda = std::function<double(int q, int32_t a, int32_t b)>;

// Receives one output tuple: the track index per sensor (kNoTrack = none) and its cost.
using EmitTuple = std::function<void(const std::array<int32_t, 3>& tracks, double cost)>;

// Splits solver tuple t (kNoTrack = none) as above: emits the tuple or its best pair, and appends
// the tracks left over to `left_over` (per sensor). `triple_cost` gives the cost of a tuple kept
// whole from its three λ (λ13 is NaN unless all_pairs).
void split_tuple(const GatedLambda& lambda, const std::array<int32_t, 3>& t, bool all_pairs,
                 const std::function<double(double l12, double l23, double l13)>& triple_cost,
                 const EmitTuple& emit, std::array<std::vector<int32_t>, 3>& left_over);

// Pairs the leftover tracks (per sensor: those split_tuple left over and those no solver tuple
// used) greedily by ascending gated-in λ and emits the pairs (cost λ), then every track still alone (cost 0).
// Ties keep the enumeration order (sensor pairs 0–1, 1–2, 0–2; then by index). O(Σ u_a·u_b log) for u
// leftovers.
void pair_leftovers(const GatedLambda& lambda, const std::array<std::vector<int32_t>, 3>& leftovers,
                    const EmitTuple& emit);

}  // namespace trackassoc
