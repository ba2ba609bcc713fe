// Two parallel "current" statistical filters F1 and F2 tuned by a back-propagation network,
// batched (seed 002 §1, after Jing Zhongliang 1995; docs/design.md §4.2).
//
// Algorithm, per track and scan:
//   1. F1 (CS filter with a large acceleration variance, a_max = 100 m/s²) predicts.
//   2. F2 (by default the same CS filter: same α and a_max) predicts its state and Φ P Φᵀ.
//   3. The network inputs are seed 002 Eqs. 3–5, summed over the axes:
//        U1 = Σ_a (x̂1_a − x̂2_a)² / Σ_a (s1_aa + s2_aa),   s_i = P_i,pp(k+1|k) + R   (position)
//        U2 = Σ_a (v̂1_a − v̂2_a)² / Σ_a (P1,vv + P2,vv)                              (velocity)
//        U3 = Σ_a (â1_a − â2_a)² / Σ_a (P1,aa + P2,aa)                              (acceleration)
//      with F2's covariance taken at its previous noise scale (the tuning in force).
//   4. y = network(U/(1+U)) ∈ (0, 1) scales F2's system variance: P2 = Φ P2 Φᵀ + y·Q2.
//   5. Both filters are updated with the measurement; F2's estimate is the output.
// Reading of seed 002 §1 (session 2): "F1's acceleration variance takes a large value to keep a fast
// response; F2's acceleration variance is adjusted automatically by the network output", "a value
// in [0 1] that modifies F2's system variance". F2 has no setting of its own in the paper, so F2's
// variance is y × the large (F1) CS variance: y = 1 makes F2 = F1. (Session 1 gave F2 a separate,
// smaller a_max = 50 before scaling: an extra unpublished parameter. Neither reading reproduces
// Table 1, see experiment_seed002.hpp.)
// The network is a kernels/learning/bp_network.hpp BpNetwork (trained by the caller, see
// trained_cs_network()). Layout: two order-3 KinematicBanks in Matriplex blocks; cost about twice
// a CS bank, O(N·D³/8) vector operations per step, blocks split across oneTBB (deterministic).
#pragma once

#include <span>
#include <vector>

#include "kernels/filters/cs_filter.hpp"
#include "kernels/filters/kalman_bank.hpp"
#include "kernels/learning/bp_network.hpp"

namespace trackassoc {

struct CsParallelOptions {
  CsOptions f1 = fast_filter_defaults();  // F1: large acceleration variance
  CsOptions f2 = fast_filter_defaults();  // F2: the same CS filter, its Q scaled by the network
  std::size_t grain_blocks = 64;
  void validate() const;  // throws InputError naming the field
  static CsOptions fast_filter_defaults() {
    CsOptions o;
    o.a_max = 100.0;
    o.a_neg_max = -100.0;
    return o;
  }
};

class CsParallelBank {
 public:
  CsParallelBank(int spatial_dim, std::size_t tracks, const BpNetwork& network)
      : f1(spatial_dim, 3, tracks), f2(spatial_dim, 3, tracks), scale(tracks, 1.0), network(network) {}
  std::size_t size() const { return f2.size(); }
  KinematicBank f1, f2;       // F2 is the estimate
  std::vector<double> scale;  // last network output per track (F2's noise scale)
  BpNetwork network;
};

// Advances all tracks one scan; `out` receives F2's innovation statistics.
FilterStepSummary cs_parallel_step(CsParallelBank& bank, double dt, const PositionScan& scan,
                                   const CsParallelOptions& options, InnovationOutput out = {});

}  // namespace trackassoc
