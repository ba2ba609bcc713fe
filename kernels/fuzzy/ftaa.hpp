// The traditional fuzzy track association algorithm, FTAA (He You et al., "Information fusion
// theory with applications", 2010, ch. on track association; the baseline of seed 001 §1 and §4).
//
// Local tracks are associated with local tracks of other sensors, and a pair is only declared
// associated after m ≥ M successful fuzzy decisions, and separated after D ≥ D_max failures
// (seed 001 §1: "generally m ≥ 6, D ≥ 6, so at least 6 decisions are needed"). The seed does not
// restate the details; this implementation, streaming like the fusion centre of
// kernels/fuzzy/fuzzy_association.hpp and with the same fuzzy factors, memberships and synthesis:
//   - each local track's state at its latest packet: the plot and the velocity differenced from
//     the previous plot (the same two-plot estimate as a temporary track);
//   - when a packet of local track a (sensor l) arrives, for every other sensor l', the local track
//     b* of l' with the largest synthesis S(a, b) (b predicted to the packet time at constant
//     velocity, u1 ≤ gate) is this scan's fuzzy decision; it succeeds when S ≥ threshold;
//   - pair quality: a success increments m(a, b*) and clears its failure count; a pair whose m
//     reaches `association_quality` is firmly associated. Any other pair of a with a track of l'
//     fails: a tentative pair is dropped (m must be reached in consecutive successes), a firm one
//     counts D consecutive failures and is separated at D = `separation_quality`;
//   - system tracks are the connected components of the firm pairs; the fused state of a's
//     system track is the unweighted mean (the traditional method treats the nodes as equally
//     reliable) of its members' latest states predicted to the packet time. No smoothing.
// Complexity: O(L) per packet for L live local tracks, plus the component walk (its size).
#pragma once

#include <cstdint>
#include <span>

#include "kernels/fuzzy/fuzzy_association.hpp"

namespace trackassoc {

struct FtaaOptions {
  FactorScales scales;
  SynthesisOptions synthesis;   // Eq. 11 with a = (0.55, 0.35, 0.1), as the proposed method
  double gate = 800.0;          // [m], on u1
  double threshold = 0.5;       // a scan's decision succeeds when S ≥ threshold
  int association_quality = 6;  // M: consecutive successes to associate (seed 001 §1: m ≥ 6)
  int separation_quality = 6;   // D_max: consecutive failures to separate (D ≥ 6)
  double track_timeout = 0.0;   // [s]; local tracks silent for longer are ignored; 0 = never
  void validate() const;
};

// Runs FTAA over all packets in arrival order (kernels/fuzzy/fuzzy_association.hpp arrival_order).
// FusionOutput::system_track is the component id: the smallest dense local index in it.
// Also returns, per dense local track, its final system track (−1 if it never had a state).
struct FtaaResult {
  FusionOutput fusion;
  std::vector<int32_t> final_system_track;  // per local track
  int64_t firm_pairs = 0;                   // firm pairs at the end
};
FtaaResult run_ftaa(const PacketSpans& packets, std::size_t num_sensors, std::size_t num_local,
                    const FtaaOptions& options);

}  // namespace trackassoc
