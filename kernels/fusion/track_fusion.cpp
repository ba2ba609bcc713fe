// Track-to-track fusion rules: see the header for the equations and references.
#include "kernels/fusion/track_fusion.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "kernels/core/error.hpp"
#include "kernels/core/golden_section.hpp"

namespace trackassoc {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

void check_inputs(std::span<const VectorXd> x, std::span<const MatrixXd> P, const char* who) {
  require(!x.empty() && x.size() == P.size(), who,
          "expected N >= 1 states and as many covariances, got " + std::to_string(x.size()) + " and " +
              std::to_string(P.size()));
  const Eigen::Index d = x[0].size();
  for (std::size_t i = 0; i < x.size(); ++i)
    require(x[i].size() == d && P[i].rows() == d && P[i].cols() == d, who,
            "estimate " + std::to_string(i) + " does not have dimension " + std::to_string(d));
}

// P⁻¹ by Cholesky; InputError when P is not positive definite.
MatrixXd spd_inverse(const MatrixXd& P, const std::string& what) {
  const Eigen::LLT<MatrixXd> llt(P);
  if (llt.info() != Eigen::Success) throw InputError(what + " is not positive definite");
  return llt.solve(MatrixXd::Identity(P.rows(), P.cols()));
}

MatrixXd symmetrised(const MatrixXd& M) { return 0.5 * (M + M.transpose()); }

// The fused estimate from information matrices Y_i = P_i⁻¹ and vectors y_i = Y_i x_i weighted by
// ω_i (1 for the naive rule).
FusedEstimate combine_information(std::span<const MatrixXd> Y, std::span<const VectorXd> y,
                                  std::span<const double> omega, const char* who) {
  MatrixXd M = MatrixXd::Zero(Y[0].rows(), Y[0].cols());
  VectorXd v = VectorXd::Zero(y[0].size());
  for (std::size_t i = 0; i < Y.size(); ++i) {
    const double w = omega.empty() ? 1.0 : omega[i];
    M += w * Y[i];
    v += w * y[i];
  }
  FusedEstimate f;
  f.P = symmetrised(spd_inverse(M, std::string(who) + ": the fused information matrix"));
  f.x = f.P * v;
  return f;
}

double criterion_of(const MatrixXd& M, CiCriterion c) {
  // M = P(ω)⁻¹. tr P and det P; det via log det for range, then exp.
  const Eigen::LLT<MatrixXd> llt(M);
  if (llt.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
  if (c == CiCriterion::kTrace) return llt.solve(MatrixXd::Identity(M.rows(), M.cols())).trace();
  return std::exp(-2.0 * llt.matrixLLT().diagonal().array().log().sum());
}

// Minimiser of a convex f on [0, 1] by golden-section search to an interval of `tol`.
template <class F>
double golden_section(F&& f, double tol) {
  const auto [a, b] = golden_section_bracket(f, 0.0, 1.0, tol, std::numeric_limits<int>::max());
  // The ends are candidates too: a convex f may be minimal at ω = 0 or 1.
  double best = 0.5 * (a + b), fbest = f(best);
  for (double e : {0.0, 1.0}) {
    const double fe = f(e);
    if (fe < fbest) best = e, fbest = fe;
  }
  return best;
}

}  // namespace

void CiOptions::validate() const {
  require(criterion == CiCriterion::kTrace || criterion == CiCriterion::kDeterminant, "CiOptions.criterion",
          "unknown criterion");
  require(std::isfinite(tolerance) && tolerance > 0.0 && tolerance <= 0.1, "CiOptions.tolerance",
          "must be in (0, 0.1], got " + std::to_string(tolerance));
  require(max_sweeps >= 1 && max_sweeps <= 100000, "CiOptions.max_sweeps",
          "must be in [1, 100000], got " + std::to_string(max_sweeps));
}

FusedEstimate fuse_naive(std::span<const VectorXd> x, std::span<const MatrixXd> P) {
  check_inputs(x, P, "fuse_naive");
  std::vector<MatrixXd> Y(x.size());
  std::vector<VectorXd> y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    Y[i] = spd_inverse(P[i], "fuse_naive: P_" + std::to_string(i));
    y[i] = Y[i] * x[i];
  }
  return combine_information(Y, y, {}, "fuse_naive");
}

FusedEstimate fuse_bar_shalom_campo(const VectorXd& x1, const MatrixXd& P1, const VectorXd& x2,
                                    const MatrixXd& P2, const MatrixXd& P12) {
  const VectorXd xs[] = {x1, x2};
  const MatrixXd Ps[] = {P1, P2};
  check_inputs(xs, Ps, "fuse_bar_shalom_campo");
  require(P12.rows() == P1.rows() && P12.cols() == P1.cols(), "fuse_bar_shalom_campo",
          "P12 does not have the dimension of P1");
  const MatrixXd U = P1 + P2 - P12 - P12.transpose();  // Eq. 9's denominator
  const Eigen::LLT<MatrixXd> llt(U);
  if (llt.info() != Eigen::Success)
    throw InputError("fuse_bar_shalom_campo: P1 + P2 - P12 - P21 is not positive definite");
  const MatrixXd Gt = llt.solve((P1 - P12).transpose());  // U⁻¹ (P1 − P12)ᵀ; gain G = (P1 − P12) U⁻¹
  FusedEstimate f;
  f.x = x1 + Gt.transpose() * (x2 - x1);                            // Eq. 9
  f.P = symmetrised(P1 - Gt.transpose() * (P1 - P12.transpose()));  // Eq. 10
  return f;
}

FusedEstimate fuse_with_cross_covariance(std::span<const VectorXd> x, const MatrixXd& joint) {
  require(!x.empty(), "fuse_with_cross_covariance", "expected N >= 1 states");
  const Eigen::Index d = x[0].size(), n = static_cast<Eigen::Index>(x.size());
  require(joint.rows() == n * d && joint.cols() == n * d, "fuse_with_cross_covariance",
          "the joint covariance must be " + std::to_string(n * d) + "x" + std::to_string(n * d));
  VectorXd X(n * d);
  MatrixXd H(n * d, d);
  for (Eigen::Index i = 0; i < n; ++i) {
    require(x[i].size() == d, "fuse_with_cross_covariance", "states of different dimensions");
    X.segment(i * d, d) = x[i];
    H.block(i * d, 0, d, d).setIdentity();
  }
  const Eigen::LLT<MatrixXd> llt(joint);
  if (llt.info() != Eigen::Success)
    throw InputError("fuse_with_cross_covariance: the joint error covariance is not positive definite");
  const MatrixXd SinvH = llt.solve(H);  // Σ⁻¹ H
  FusedEstimate f;
  f.P = symmetrised(spd_inverse(H.transpose() * SinvH, "fuse_with_cross_covariance: Hᵀ Σ⁻¹ H"));
  f.x = f.P * (SinvH.transpose() * X);
  return f;
}

double ci_criterion_value(std::span<const MatrixXd> P, std::span<const double> omega, CiCriterion criterion) {
  require(P.size() == omega.size() && !P.empty(), "ci_criterion_value", "one weight per covariance");
  MatrixXd M = MatrixXd::Zero(P[0].rows(), P[0].cols());
  for (std::size_t i = 0; i < P.size(); ++i) M += omega[i] * spd_inverse(P[i], "ci_criterion_value: P");
  return criterion_of(M, criterion);
}

FusedEstimate fuse_covariance_intersection(std::span<const VectorXd> x, std::span<const MatrixXd> P,
                                           const CiOptions& options) {
  options.validate();
  check_inputs(x, P, "fuse_covariance_intersection");
  const std::size_t n = x.size();
  std::vector<MatrixXd> Y(n);
  std::vector<VectorXd> y(n);
  for (std::size_t i = 0; i < n; ++i) {
    Y[i] = spd_inverse(P[i], "fuse_covariance_intersection: P_" + std::to_string(i));
    y[i] = Y[i] * x[i];
  }
  std::vector<double> omega(n, 1.0 / static_cast<double>(n));
  int sweeps = 0;
  if (n == 2) {
    omega[0] =
        golden_section([&](double w) { return criterion_of(w * Y[0] + (1.0 - w) * Y[1], options.criterion); },
                       options.tolerance);
    omega[1] = 1.0 - omega[0];
  } else if (n > 2) {
    // Two-coordinate descent on the simplex with the maximal violating pair (SMO): i with the
    // smallest ∂J/∂ω (it wants weight), j with the largest among ω_j > 0; s = ω_i + ω_j is shared
    // by golden section, ω_i = s·u. Optimal when the gap ∂J/∂ω_j − ∂J/∂ω_i ≤ tolerance (KKT of a
    // convex function on the simplex), or when a step moves ω by no more than the tolerance. ∂ tr P/∂ω_k =
    // −tr(P Y_k P) (taken relative to tr P), and for det the equivalent log det P: ∂/∂ω_k = −tr(P Y_k).
    const Eigen::Index d = Y[0].rows();
    const bool trace = options.criterion == CiCriterion::kTrace;
    const int max_steps = options.max_sweeps * static_cast<int>(n);
    std::vector<double> grad(n);
    for (sweeps = 0; sweeps < max_steps; ++sweeps) {
      MatrixXd M = MatrixXd::Zero(d, d);
      for (std::size_t k = 0; k < n; ++k) M += omega[k] * Y[k];
      const MatrixXd P = spd_inverse(M, "fuse_covariance_intersection: the fused information matrix");
      const double scale = trace ? P.trace() : 1.0;
      for (std::size_t k = 0; k < n; ++k)
        grad[k] = -(trace ? (P * Y[k] * P).trace() : (P * Y[k]).trace()) / scale;
      std::size_t i = 0, j = n;
      for (std::size_t k = 1; k < n; ++k)
        if (grad[k] < grad[i]) i = k;
      for (std::size_t k = 0; k < n; ++k)
        if (k != i && omega[k] > 0.0 && (j == n || grad[k] > grad[j])) j = k;
      if (j == n || grad[j] - grad[i] <= options.tolerance) break;
      const double s = omega[i] + omega[j];
      const MatrixXd rest = M - omega[i] * Y[i] - omega[j] * Y[j];
      const double u = golden_section(
          [&](double v) {
            return criterion_of(rest + s * v * Y[i] + s * (1.0 - v) * Y[j], options.criterion);
          },
          options.tolerance);
      const double moved = std::fabs(s * u - omega[i]);
      omega[i] = s * u;
      omega[j] = s - omega[i];
      if (moved <= options.tolerance) break;  // converged to the golden section's resolution
    }
  }
  FusedEstimate f = combine_information(Y, y, omega, "fuse_covariance_intersection");
  f.omega = std::move(omega);
  f.sweeps = sweeps;
  return f;
}

}  // namespace trackassoc
