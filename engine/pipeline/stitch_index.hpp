// The candidate search of fragment stitching (engine/pipeline/track_stitching.hpp), indexed: for
// one group's end, the group starts that its gap statistic could gate, without looking at every
// start of its time window.
//
// The bound. For an end a (row, time t_a) and a start b (time t_b, gap g = t_b − t_a, h = |g|),
// the pre-gate of join_cost refuses the pair when |e_p|² > γ·tr(S_pp) (γ = χ²_D of
// gate_probability, q = σ_a² of the manoeuvring model; it refuses only pairs whose m² is outside
// the gate), where, both ends predicted h/2 to the gap's midpoint by constant velocity,
//     e_p = (p_a − p_b) + (g/2)(v_a + v_b),   tr(S_pp) = T_a(g) + T_b(g),
//     T(g) = Σ_i [P_ii ± g P_i,v_i + (g²/4) P_v_i,v_i + q |g/2|³/3]   (i over the d positions).
// Each T is at most the monotone τ(h) = A + h B + (h²/4) C + d q h³/24, with A = Σ P_ii,
// B = Σ |P_i,v_i|, C = max(0, Σ P_v_i,v_i), so a pair the pre-gate keeps has
//     |p_a − p_b| ≤ (h/2)(|v_a| + |v_b|) + √(γ (τ_a(h) + τ_b(h))),
// a sum of each side's terms at h, growing with h. (It is the pre-gate itself for still targets
// whose covariance has no velocity part and no correlation.)
//
// The index. The starts (their rows in time order, as the stitching sorts them) in a k-d tree over
// (time, position): a node keeps its points' time span, their bounding box, and the largest A, B,
// C and |v| among them, which bound its starts' terms. A query for end a descends into the nodes
// whose span meets a's window [t_a − max_overlap_s, t_a + max_gap_s] and whose box is within the
// bound of p_a (with the node's terms and h the largest gap its span allows within the window),
// and tests each start of a leaf with its own terms and gap. The bound is widened by a
// relative 10⁻⁷ (and an absolute 10⁻⁷ of the scene's scale) against rounding, so a start the
// query leaves out is one the pre-gate refuses: the joins are exactly those of the scan of the
// whole window. Starts or ends with a non-finite coefficient are never pruned.
// A node is split at the median along the longest of its sides, time measured at the bound per
// second of a mean start over the longest gap.
// Cost: O(n log n) to build, memory ~100 bytes a start; a query visits the tree's nodes near its
// window and reach instead of the n starts of the window (in a wide scene, a few starts instead
// of thousands: docs/design.md §4.10).
#pragma once

#include <cstdint>
#include <vector>

#include "io/track_file.hpp"

namespace trackassoc {

class StitchStartIndex {
 public:
  // `rows`: the start reports, their times t.t[rows[p]] non-decreasing in p. q = σ_a² and `gate`
  // (γ) of the pre-gate; the window of an end at t is [t − max_overlap_s, t + max_gap_s].
  StitchStartIndex(const TrackTable& t, const std::vector<std::size_t>& rows, double q, double gate,
                   double max_overlap_s, double max_gap_s);

  // Appends to `out` (cleared first), in increasing order, every position p whose start lies in the
  // window of end row `end` (t.t[rows[p]] ≥ t_end − max_overlap_s and ≤ t_end + max_gap_s, as a
  // binary search over the sorted times finds them) and whose pair with `end` the bound above does
  // not exclude. The table must be the one the index was built on.
  void query(const TrackTable& t, std::size_t end, std::vector<int32_t>& out) const;

  // The positions of the window alone, [first, last): first is the number of starts before it
  // (track_stitching.cpp counts with it the starts whose representative precedes the window).
  std::pair<int32_t, int32_t> window(double t_end) const;

 private:
  struct Reach {  // one report's side of the bound
    double t = 0.0, x[3] = {0.0, 0.0, 0.0};
    double a = 0.0, b = 0.0, c = 0.0, speed = 0.0;
    int32_t position = 0;
  };
  struct Node {
    double t_lo = 0.0, t_hi = 0.0, lo[3] = {0.0, 0.0, 0.0}, hi[3] = {0.0, 0.0, 0.0};
    double a = 0.0, b = 0.0, c = 0.0, speed = 0.0;  // the largest of its points'
    int32_t begin = 0, end = 0, left = -1, right = -1;
  };
  Reach reach_of(const TrackTable& t, std::size_t row, int32_t position) const;
  double tau(double a, double b, double c, double h) const;
  // The bound on |p_a − p_b| (widened) for end e and a start of coefficients a, b, c, speed at gap h.
  double reach(const Reach& e, double a, double b, double c, double speed, double h) const;
  int32_t build(int32_t begin, int32_t end, double time_scale);
  void visit(int32_t node, const Reach& e, double t_lo, double t_hi, std::vector<int32_t>& out) const;

  int d_ = 2;
  double q_ = 0.0, gate_ = 0.0, overlap_ = 0.0, gap_ = 0.0, margin_ = 0.0;
  std::vector<double> times_;       // by position: the sorted start times
  std::vector<Reach> points_;       // the tree's points, in leaf order
  std::vector<Node> nodes_;         // nodes_[0] the root when points_ is not empty
  std::vector<int32_t> unbounded_;  // positions with a non-finite coefficient, increasing
};

}  // namespace trackassoc
