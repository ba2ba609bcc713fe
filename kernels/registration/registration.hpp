// Relative sensor registration by weighted least squares with a ridge prior (docs/design.md §4.10).
//
// Problem. Each sensor s reports positions with a systematic error: x_reported ≈ x + J_s(x)·b_s,
// linearised about the reported position. With the sensor's site p_s known (/sensors/position),
// rel = x − p_s, r = |rel|, ρ = horizontal range, the columns of J_s are, in the order of b_s:
//   range bias Δr        rel / r                                  (along the line of sight)
//   azimuth bias Δθ      (−rel_y, rel_x, 0)                       (a rotation about the site; θ is
//                                                                  counter-clockwise from +x)
//   elevation bias Δφ    (−rel_z·rel_x/ρ, −rel_z·rel_y/ρ, ρ)      (3-D only)
//   site offset o        −I (d columns)                           (the true site is p_s + o: the
//                                                                  sensor reports x − o)
//   clock offset Δt      −v                                       (a report stamped t is of the
//                                                                  target at t − Δt; v the
//                                                                  observation's velocity: the
//                                                                  stage passes central
//                                                                  differences of positions, since
//                                                                  a filter's reported velocity
//                                                                  errors correlate with its
//                                                                  position errors, docs/design.md
//                                                                  §4.10)
// so the columns are RegistrationOptions' choice: polar biases (needs the sites), a site offset
// (the translation, and the whole model when no site is known), a clock offset.
// Only relative registration is observable without truth: b of the reference sensor is held at 0
// and every other sensor's b is relative to it.
//
// Data: pair observations at common times of two local tracks a (sensor s) and b (sensor t) taken
// to be the same target: d = x̂_a − x̂_b ≈ J_s b_s − J_t b_t + e, e ~ N(0, C), C = P_a + P_b (the
// position blocks). The fit minimises
//   Σ_obs w·(d − J_s b_s + J_t b_t)ᵀ C⁻¹ (d − J_s b_s + J_t b_t) + Σ_s b_sᵀ Λ b_s,
// Λ = diag(1/σ_prior²), the ridge (a Gaussian prior of zero bias), so that a component the data do
// not determine (a site offset against range and azimuth biases in a narrow sector, a clock offset
// of targets that all fly one way) stays bounded by its prior instead of drifting. The weights w
// are Huber's (w = 1 for a normalised residual m = √(rᵀC⁻¹r) ≤ h, h/m above), by iteratively
// reweighted least squares, so a wrongly paired observation pulls with a bounded force.
//
// Standard errors. The scan errors of filtered tracks are correlated over many scans and the
// reported C may be off by a factor, so the model covariance H⁻¹ (H = Σ AᵀwC⁻¹A + Λ) is too
// optimistic on real tracks. The covariance reported is the larger (per diagonal entry) of H⁻¹
// and the cluster-robust sandwich H⁻¹ (Σ_c g_c g_cᵀ + Λ) H⁻¹, a cluster c being one pair of
// tracks and g_c = Σ_{obs ∈ c} Aᵀ w C⁻¹ r its score (Liang and Zeger 1986): correct for any
// correlation within a pair and any covariance scale, and the prior's σ for unobservable parts.
// Covariance scale per pair of sensors: the mean of rᵀC⁻¹r / d over their observations after the
// fit (1 when the reported covariances are right and the errors independent between the sensors).
//
// References: Okello and Ristic, "Maximum likelihood registration for multiple dissimilar
// sensors", IEEE T-AES 39(3), 2003 (the EML relative-registration model and its linearisation);
// Fortunati, Farina, Gini, Graziano, Greco, Giompapa, "Least squares estimation and Cramér-Rao type
// lower bounds for relative sensor registration process", IEEE T-SP 59(3), 2011 (relative LS
// registration, what is observable); Levedahl, "An explicit pattern matching assignment algorithm",
// SPIE 4728, 2002 (global nearest pattern: association and bias together); Tian, Wang, Shan, Yang,
// "Analytic performance prediction of track-to-track association with biased data in multi-sensor
// multi-target tracking scenarios", Sensors 13(9):12244, 2013 (how translational biases degrade
// GNN association, the reason for the joint stage engine/pipeline/registration_stage.hpp).
//
// Complexity: O(N·(2k)²·d) to accumulate N observations with k parameters per sensor, plus
// O((S·k)³) per IRLS iteration for the solve; S·k is small (≤ 5 sensors × 7 parameters typically).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace trackassoc {

struct RegistrationOptions {
  int32_t reference_sensor = 0;               // index of the sensor held at zero bias
  bool polar = true;                          // range, azimuth (and elevation in 3-D) biases about the sites
  bool site_offset = true;                    // a translation per sensor (the whole model when !polar)
  bool clock_offset = false;                  // a clock offset per sensor (needs velocities)
  double prior_range = 300.0;                 // σ of the ridge prior on Δr [m]
  double prior_azimuth = 0.01745329251994;    // [rad] (1°)
  double prior_elevation = 0.00872664625997;  // [rad] (0.5°)
  double prior_site_offset = 1000.0;          // [m], per coordinate (docs/design.md §4.10)
  double prior_clock = 2.0;                   // [s]
  double huber = 3.0;                         // h, in normalised residual units (> 0)
  int32_t iterations = 4;                     // IRLS iterations (≥ 1)
  void validate() const;
};

// Pair observations, structure of arrays: observation i compares a track of sensor sensor_a[i]
// with one of sensor_b[i] at one time. Positions and velocities N×d, covariance N×d×d (row-major),
// the position block of P_a + P_b (or of the cross-covariance-corrected C).
struct RegistrationObservations {
  int32_t dim = 2;  // spatial dimension d: 2 or 3
  std::vector<int32_t> sensor_a, sensor_b;
  std::vector<int64_t> cluster;  // one id per pair of tracks (the sandwich's clusters)
  std::vector<double> position_a, position_b, velocity_a, velocity_b, covariance;
  std::size_t size() const { return sensor_a.size(); }
  // Appends one observation; v_a / v_b may be empty when the clock term is off.
  void add(int32_t a, int32_t b, int64_t pair, std::span<const double> x_a, std::span<const double> x_b,
           std::span<const double> v_a, std::span<const double> v_b, std::span<const double> c);
};

struct RegistrationSummary {
  int32_t iterations = 0;
  std::size_t observations = 0, clusters = 0;
  double objective = 0.0;  // the weighted sum of squares plus the prior term at the estimate
  double wall_time_s = 0.0;
};

struct RegistrationEstimate {
  int32_t sensors = 0, dim = 2, reference = 0;
  std::vector<std::string> parameter_names;  // k names, e.g. range_bias, azimuth_bias, site_offset_x
  std::vector<double> bias;                  // S×k, row-major; the reference's row is 0
  std::vector<double> standard_error;        // S×k; 0 for the reference
  std::vector<double> covariance;            // S×k×k, each sensor's block of the estimate's covariance
  std::vector<double> covariance_scale;      // S×S, symmetric; NaN where a pair has no observation
  std::vector<int64_t> pair_observations;    // S×S, observations per pair of sensors
  RegistrationSummary summary;
  int32_t k() const { return static_cast<int32_t>(parameter_names.size()); }
  // Sensor s's row b_s of `bias` (k) and its block V_s of `covariance` (k × k).
  Eigen::Map<const Eigen::VectorXd> sensor_bias(std::size_t s) const {
    return {bias.data() + s * static_cast<std::size_t>(k()), k()};
  }
  Eigen::Map<const Eigen::MatrixXd> sensor_covariance(std::size_t s) const {
    return {covariance.data() + s * static_cast<std::size_t>(k()) * k(), k(), k()};
  }
  // The Wald statistic bᵀ V⁻¹ b of every non-reference parameter together (V = the reported
  // covariance, block diagonal per sensor) and its degrees of freedom: large when the data show a
  // registration error, about dof when they do not.
  double wald(int32_t& dof) const;
};

// The parameter names of the model `o` chooses in d dimensions.
std::vector<std::string> registration_parameter_names(const RegistrationOptions& o, int32_t d);

// J_s at reported position x (velocity v, used by the clock column) for a sensor at `site`:
// d × k, in the order of registration_parameter_names.
Eigen::MatrixXd registration_jacobian(const RegistrationOptions& o, int32_t d,
                                      const std::array<double, 3>& site, std::span<const double> x,
                                      std::span<const double> v);

// Fits every sensor's registration relative to o.reference_sensor. `sites` has one entry per
// sensor (ignored unless o.polar). Throws InputError on bad options or observations naming
// sensors outside 0..S−1.
RegistrationEstimate fit_registration(const RegistrationObservations& observations,
                                      std::span<const std::array<double, 3>> sites,
                                      const RegistrationOptions& o);

}  // namespace trackassoc
