// Cross-covariance of two local tracks of one target from common process noise (Bar-Shalom 1981;
// Bar-Shalom & Campo 1986; Bar-Shalom, Li, Kirubarajan 2001 §8.4): the correlated-error form of
// the sequential statistic (seed 000 §2–§4, "节点间误差相关"; kernels/statistics/association_statistic.hpp).
//
// Two Kalman filters that track the same target see the same process noise w(k), so their
// estimation errors e_a, e_b are correlated even when their measurement noises are independent:
//
//   e(k) = A(k)·[F e(k−1) + w(k)] − K(k) v(k),   A(k) = I − K(k)H
//   P_ab(k) = A_a(k)·[F P_ab(k−1) Fᵀ + Q]·A_b(k)ᵀ,   P_ab(0) = 0                      (BSC recursion)
//
// A track file carries P(k|k) but not the gain. For a CV filter with the known F and Q, the gain
// follows from two consecutive reported covariances:
//
//   P(k|k) = A(k)·P(k|k−1),   P(k|k−1) = F P(k−1|k−1) Fᵀ + Q   ⇒   A(k) = P(k|k)·P(k|k−1)⁻¹,
//
// exact when the common times are the filters' update times (synchronous sensors; at a common time
// without a new report P(k) = P(k|k−1) and A = I, a pure prediction). Q is the piecewise-constant
// white acceleration model of the local filters (kernels/filters/kalman_bank.hpp,
// kinematic_process_noise): per axis σ_a²·[Δ⁴/4 Δ³/2; Δ³/2 Δ²]. The recursion starts at 0 at a
// pair's first common time (independently initialised tracks); over a gap in either track it
// restarts at 0, which underestimates the correlation there.
//
// Cost: A(k) once per aligned cell, O(Σ spans·D³); the recursion per pair and time, O(D³), in the
// statistic's pair loop (kernels/statistics/association_statistic.cpp) and in track fusion
// (cross_covariance_series; engine/fusion/track_fuser.hpp, the Bar-Shalom–Campo rule).
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc {

// Per cell of `x` (AlignedTracks::cell(track, k)), A(k) as a full row-major D×D matrix; the
// identity where the track is invalid at k or k−1 (or k − 1 is before its span). Throws InputError when F
// P(k−1) Fᵀ + Q is not positive definite.
std::vector<double> gain_complements(const AlignedTracks& x, double sigma_a);

// One step of the recursion: P_ab(k) = A_a(k)·[F P_ab(k−1) Fᵀ + Q]·A_b(k)ᵀ (any Eigen matrix types).
template <class MatA, class MatB, class Mat>
Mat cross_covariance_step(const MatA& A_a, const MatB& A_b, const Mat& F, const Mat& Q, const Mat& P_ab) {
  return A_a * (F * P_ab * F.transpose() + Q) * A_b.transpose();
}

// P_ab(k) of row ia of `a` and row ib of `b` at every common time, row-major D×D per time (zeros
// where either track is invalid): 0 at the first common time where both exist and after every gap,
// then the recursion above. gain_a, gain_b are gain_complements(a | b, sigma_a).
std::vector<double> cross_covariance_series(const AlignedTracks& a, int32_t ia,
                                            std::span<const double> gain_a, const AlignedTracks& b,
                                            int32_t ib, std::span<const double> gain_b, double sigma_a);

// F and Q of the CV model (state = position[m], velocity[m]) over Δ for σ_a (as above).
void cv_transition(int dim, double dt, double sigma_a, Eigen::MatrixXd& F, Eigen::MatrixXd& Q);

}  // namespace trackassoc
