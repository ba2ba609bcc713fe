// The default association pipeline for recorded track sets: every sensor, sparse gated
// candidates, and an S-D assignment with dummies per connected component (docs/design.md §4.3; issue 20).
//
//   local tracks of S ≥ 2 sensors → common times over the union of their reports → two-sided
//     alignment (nearest report on either side)       (the front end, engine/pipeline/front_end.hpp)
//   → for every pair of sensors: candidate pairs from a per-scan index, the sequential statistic
//     on the candidates, the calibrated gate (SequentialGate)
//                                                     (the pair source, engine/pipeline/pair_source.hpp)
//   → connected components of the gated pair graph   (the partition, engine/pipeline/partition.hpp)
//   → per component, in parallel (TBB): the S-D assignment with a dummy per sensor over the
//     component's tracks (a dense sub-tensor; lr+ls, lr or exact), or, for a component whose
//     sub-tensor exceeds the budget, the Lagrangian relaxation over its listed allowed tuples
//     (engine/pipeline/sparse_sd_tuples.hpp, with its bound), or, when even the list would not fit
//     the memory budget, sequential LAP merging
//   → tuples over all sensors of the file (−1 = no track), every local track in exactly one tuple
//   → track segments joined to their targets (engine/pipeline/track_segments.hpp): a target's
//     tracks that follow each other on one sensor each join its tuples, with a target number.
//
// Cost of a tuple with the set M of real members (the S-D generalised likelihood-ratio cost with
// the gate as the miss cost): Σ over the linked pairs {a, b} ⊂ M of (λ_ab − G(n_ab))/f, the link
// cost of SequentialGate (≤ 0 inside the gate), where "linked" is every pair (all-pairs form,
// default: it uses all the evidence) or consecutive members of M (chain form). A tuple of one
// track costs 0. A tuple is allowed only if
//   * no two of its members overlap in time and fail the gate (a tested pair outside the gate),
//   * and its members are connected through gated-in pairs.
// Pairs that never coexist carry no evidence (docs/design.md §4.3): they neither forbid a tuple nor link it,
// so a target seen by sensor A early and sensor C late joins through a sensor B that saw both.
//
// Why components are independent: a tuple is connected through gated-in pairs, so all its members
// lie in one component of the gated pair graph; the S-D problem separates exactly.
//
// Huge components (a dense sub-tensor of Π(n_s + 1) entries above `max_component_entries`): the
// allowed tuples are listed and the S-D relaxation runs over the list, which reports the
// component's duality gap (issue 31 item 4; on recorded_10k at three times its density, 3 × 30 000
// targets, two such components of up to 236 064 listed tuples, gap 0.10 %).
// Fallback, the last resort when the list would not fit the memory budget: sensors are merged one at a time,
// each by a rectangular LAP with "unassigned" allowed between the groups formed so far and the next sensor's
// tracks, cost = the sum of link costs to the group's members (forbidden as above). It is what the pairwise
// peers do, and it is reported per record (`fallback_components`).
//
// Complexity: alignment O(Σ spans·D³) time and memory (each track over its own span, not the whole
// grid); candidates O(S·Σ spans·log n + hits); statistic O(Σ_hits |span_a ∩ span_b|·D³);
// components O(E α(N)); solves Σ_c Π(n_{c,s} + 1) · (solver iterations), in parallel.
#pragma once

#include <algorithm>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "engine/distributed/communicator.hpp"
#include "engine/pipeline/pipeline.hpp"
#include "engine/pipeline/sparse_pipeline.hpp"
#include "engine/pipeline/track_segments.hpp"
#include "kernels/assignment/clusters.hpp"
#include "kernels/statistics/sparse_candidates.hpp"

namespace trackassoc {

struct SparseSDOptions {
  PipelineOptions pipeline;   // sensors (empty = all of the file), grid, alignment, gate, cost form
  double radius_scale = 1.0;  // ≥ 1, widens the candidate bound (kernels/statistics/scan_candidates.hpp)
  // Largest dense sub-tensor per component, Π(n_s + 1) entries (16 Mi floats = 64 MiB); larger
  // components are solved by sequential LAP merging.
  std::size_t max_component_entries = std::size_t{1} << 24;
  // The exponent κ of the rival-weighted link cost (rival_link_costs below): a gated pair whose
  // tracks have up to m gated partners on the other's sensor counts as evidence only below the
  // gate of probability 1 − (1 − p)·m^κ. 0 = every pair against the gate itself.
  double rival_exponent = 2.0;
  // The family-wise veto (docs/design.md §4.3): a coexisting pair outside the gate of probability p
  // forbids a tuple only when it also fails the gate at the tuple's family-wise level
  // family_wise_gate_probability(p, S); a pair between the two (doubtful) may join a tuple that is
  // linked through gated-in pairs, at its positive link cost (engine/pipeline/tuple_cost.hpp).
  // false: every pair outside the gate forbids.
  bool family_wise_veto = true;
  // After the assignment, the segments of one target on one sensor joined to it
  // (engine/pipeline/track_segments.hpp); associate_sparse_sd runs it, solve_sparse_sd_association not.
  SegmentOptions segments;
  // The ranks that share the components (docs/design.md §8; engine/pipeline/sparse_sd_components.hpp): null
  // or one rank solves them all here. On more ranks this is rank 0's call; the others serve.
  distributed::Communicator* ranks = nullptr;
  void validate() const;
  nlohmann::json to_json() const;
};

// Bonferroni's family-wise level for the pairs of a tuple of S sensors, S(S − 1)/2 tests at the
// gate probability p each: 1 − (1 − p)/(S(S − 1)/2), so that a true tuple of every sensor keeps
// all its pairs with probability ≥ p (Bonferroni's inequality; a tuple of fewer sensors is held to
// a stricter level than it needs). p itself for S ≤ 2.
double family_wise_gate_probability(double p, int32_t S);

// The front end's aligned sensors (engine/pipeline/front_end.hpp; a chosen sensor without local
// tracks is left out: empty_sensor_ids), the gated pairs of the per-scan candidate index with
// their link costs, and their connected components.
struct SparseSDProblem : AlignedSensors {
  // Gated-in pairs of every sensor pair a < b, slot a·S + b, with their link cost.
  std::vector<SparsePairStatistic> pairs;
  std::vector<std::vector<double>> link;
  std::vector<std::size_t> candidate_pairs;  // index output before the gate, per slot
  // Doubtful pairs per slot (SparseSDOptions::family_wise_veto): outside the gate, inside the
  // family-wise gate, as `pairs` and `link` (link costs > 0). Only the components' tuple costs
  // (sd_component_view) and the segment pass's joins (engine/pipeline/track_segments.hpp) read them.
  std::vector<SparsePairStatistic> doubtful;
  std::vector<std::vector<double>> doubtful_link;
  Components components;
  std::vector<StageReport> stages;  // alignment, candidates, statistics, components
  double bytes_held = 0.0;          // the input and the problem [bytes], counted against the memory budget
};

// Rival-weighted link costs (docs/design.md §4.9, issue 29). The S-D link cost of a gated pair is
// its excess over the gate, (λ − G_p(n))/f (SequentialGate::link_cost), the same whatever else the
// two tracks gate with. In dense traffic on one heading (recorded_bias_dense: 60 targets within
// 12 km, neighbours 0.1-3 km apart at 100 km range) a track gates with several tracks of the other
// sensor, and a neighbour's track that fits at the tail of the gate (λ/n ≈ 6-9 against ≈ 2.6 for
// the true pairs) still earns a reward and completes a tuple. As the alternative hypothesis of a
// likelihood-ratio track score weighs a fit against the density of competing tracks (n / V of the
// fragment stitching's gap statistic; the new-target density β of the track score of multiple-
// hypothesis tracking, Blackman and Popoli, Design and Analysis of Modern Tracking Systems, 1999),
// the link is
// measured against a gate tightened by the pair's rivals: with m = the larger of the two tracks'
// numbers of rivals, the gated partners on the other's sensor that coexist with the pair's other
// track (the pair itself included; a target's successive fragments on one sensor compete for
// nothing, so they are no rivals: on widearea_small counting them cost 2.9 points of correct),
//     c = (λ − G_{p(m)}(n))/f,   p(m) = max(1/2, 1 − (1 − p)·m^κ),
// so an unambiguous pair (m = 1) is scored as before, and p(2) = 0.96, p(3) = 0.91 at p = 0.99,
// κ = 2. The gate itself (which pairs may share a tuple) is unchanged; a rival pair above its
// tightened threshold only costs (c > 0). κ chosen by measurement on the recorded family
// (docs/design.md §4.9): p(m) = 1 − (1 − p)·c·m for c = 1, 2, 3, 5 and m^κ for κ = 1.5, 2, 3.
// Thresholds are computed once per distinct (m, n). O(Σ_pairs rivals + n_a + n_b).
// `st` holds the gated pairs of sensors sa < sb (positions in `sensors`); `gate` is
// SequentialGate(sensors.dim, statistic, ...), shared by the sensor pairs.
std::vector<double> rival_link_costs(const SparsePairStatistic& st, const AlignedSensors& sensors, int32_t sa,
                                     int32_t sb, const SequentialGate& gate,
                                     const StatisticOptions& statistic, double rival_exponent);

// Throws InputError on unknown sensor ids, fewer than 2 sensors with local tracks (a sensor without
// any is left out: empty_sensor_ids), a gate probability of 1 (the gate is the miss cost), or no
// common time at all.
SparseSDProblem build_sparse_sd_problem(const TrackFile& file, const SparseSDOptions& options);

// The front half of both sparse paths, written once (docs/design.md §4): the front end (the sensors
// of `rule`: any two or more, a chosen sensor without tracks left out; or exactly three, as
// --sparse), the pair source (the per-scan candidate index, λ on its candidates, the gate; the
// link costs with options.rival_exponent), the partition (connected components of the gated
// pairs), each with its StageReport and checked against the memory budget. Validates nothing
// (build_sparse_sd_problem validates the S-D options, build_sparse_association_problem the 3-D
// ones); options.segments are not used and options.ranks share the statistics.
SparseSDProblem build_sparse_front_half(const TrackFile& file, const SparseSDOptions& options,
                                        SensorRule rule);

// Solvers of the components: the registry's tensor S-D solvers (capabilities.sd_tensor), the
// default first: lr+ls, lr, exact.
const std::vector<std::string>& sparse_sd_solver_names();
void require_sparse_sd_solver(const std::string& name);

// What the solve did besides the record: the counts the record's options attribute stores and
// AssociationSummary (engine/pipeline/associator.hpp) reports.
struct SparseSDSolveReport {
  int32_t components = 0, fallback_components = 0;
  std::size_t largest_component_entries = 0;
  // Components too large for the dense sub-tensor solved over their listed tuples
  // (engine/pipeline/sparse_sd_tuples.hpp), and the largest list.
  int32_t listed_components = 0;
  std::size_t largest_listed_tuples = 0;
  // The largest relative duality gap of a component, (objective − bound) / max(|objective|, 10⁻⁹)
  // (NaN when no component has a bound), and the components above 1 %; a fallback component has
  // no bound and counts among fallback_components.
  double largest_component_gap = 0.0;
  int32_t components_above_1pct_gap = 0;
  int64_t candidate_pairs = 0, gated_pairs = 0;  // index output before the gate, and gated in
};

// Solves every component in parallel and returns the record for /associations/<solver>/: the
// objective and lower bound are sums over the components (the bound is NaN when a component was
// solved by the fallback). The component c's solver gets the seed stream_key(seed, c).
AssociationRecord solve_sparse_sd_association(const SparseSDProblem& p, const std::string& solver,
                                              const nlohmann::json& solver_options, uint64_t seed,
                                              const SparseSDOptions& options,
                                              SparseSDSolveReport* report = nullptr);

// What associate_sparse_sd did besides the record, typed (the association interface reads these,
// never the record's options attribute).
struct SparseSDReport {
  SparseSDSolveReport solve;
  std::vector<int32_t> sensor_ids;           // the problem's sensors (SparseSDProblem::sensor_ids)
  std::vector<int32_t> empty_sensor_ids;     // chosen sensors without local tracks (tuple column -1)
  std::vector<UnfilteredSensor> unfiltered;  // sensors aligned without the lag terms (front_end.hpp)
  std::optional<SegmentSummary> segments;    // the segment pass, when options.segments.enabled
  std::vector<StageReport> stages;           // alignment, candidates, statistics, components, solve, segments
};

// build + solve (+ segments): the default path of the association interface
// (engine/pipeline/associator.hpp, which `associate` and `experiment recorded` call). The record's
// options attribute is written here, once, from the typed values: the request, the solve's counts,
// and (only when present, so other records are unchanged) empty_sensors, unfiltered_sensors and the
// segment counts.
AssociationRecord associate_sparse_sd(const TrackFile& file, const std::string& solver,
                                      const nlohmann::json& solver_options, uint64_t seed,
                                      const SparseSDOptions& options, SparseSDReport* report = nullptr);

}  // namespace trackassoc
