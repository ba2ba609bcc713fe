// Relative registration (kernels/registration/registration.hpp): biases injected into pairs of
// tracks made here are recovered within 2 standard errors; the ridge keeps an unobservable part
// bounded; a small case checked by hand; the covariance scale recovered.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "kernels/core/error.hpp"
#include "kernels/registration/registration.hpp"

namespace trackassoc {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct Truth {
  double range = 0, azimuth = 0;
  std::array<double, 3> site_offset{0, 0, 0};
};

// What sensor `site` (surveyed) with errors `e` reports of a target at p: polar from the true
// site, biases added, converted back about the surveyed site (the exact, nonlinear model).
std::array<double, 3> report(const std::array<double, 3>& site, const Truth& e,
                             const std::array<double, 3>& p) {
  const double sx = site[0] + e.site_offset[0], sy = site[1] + e.site_offset[1];
  const double r = std::hypot(p[0] - sx, p[1] - sy) + e.range;
  const double th = std::atan2(p[1] - sy, p[0] - sx) + e.azimuth;
  return {site[0] + r * std::cos(th), site[1] + r * std::sin(th), 0};
}

// 3 sensors, `targets` targets moving for `scans` scans; every pair of sensors observes every
// target every scan, with independent isotropic noise σ per report; C = 2σ²·I / cov_factor.
RegistrationObservations make_observations(const std::vector<std::array<double, 3>>& sites,
                                           const std::vector<Truth>& truth, int targets, int scans,
                                           double sigma, double spread, double cov_factor, uint32_t seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-spread, spread), heading(0, 2 * std::numbers::pi);
  std::normal_distribution<double> n(0.0, sigma);
  RegistrationObservations obs;
  obs.dim = 2;
  const double C[4] = {2 * sigma * sigma / cov_factor, 0, 0, 2 * sigma * sigma / cov_factor};
  for (int j = 0; j < targets; ++j) {
    const double x0 = u(gen), y0 = u(gen), h = heading(gen);
    for (int k = 0; k < scans; ++k) {
      const std::array<double, 3> p{x0 + 200.0 * k * std::cos(h), y0 + 200.0 * k * std::sin(h), 0};
      std::vector<std::array<double, 3>> rep;
      for (std::size_t s = 0; s < sites.size(); ++s) {
        auto q = report(sites[s], truth[s], p);
        q[0] += n(gen);
        q[1] += n(gen);
        rep.push_back(q);
      }
      for (int a = 0; a < 3; ++a)
        for (int b = a + 1; b < 3; ++b)
          obs.add(a, b, j * 10 + a * 3 + b, std::span<const double>(rep[a].data(), 2),
                  std::span<const double>(rep[b].data(), 2), {}, {}, C);
    }
  }
  return obs;
}

const std::vector<std::array<double, 3>> kSites{{-100e3, 10e3, 0}, {70e3, -90e3, 0}, {60e3, 110e3, 0}};

TEST(Registration, InjectedRangeAzimuthAndSiteErrorsAreRecoveredWithinTwoStandardErrors) {
  // Sensor 0 is the reference (no error); 1 and 2 carry range, azimuth and site errors.
  std::vector<Truth> truth(3);
  truth[1] = {-120.0, -0.6 * kDeg, {0, 0, 0}};
  truth[2] = {190.0, 0.5 * kDeg, {250, -150, 0}};
  const RegistrationObservations obs = make_observations(kSites, truth, 30, 20, 60.0, 40e3, 1.0, 11);
  RegistrationOptions o;
  const RegistrationEstimate e = fit_registration(obs, kSites, o);
  ASSERT_EQ(e.k(), 4);  // range, azimuth, site x, site y
  EXPECT_EQ(e.parameter_names[1], "azimuth_bias");
  for (int s = 1; s < 3; ++s) {
    const double want[4] = {truth[s].range, truth[s].azimuth, truth[s].site_offset[0],
                            truth[s].site_offset[1]};
    for (int j = 0; j < 4; ++j) {
      const double est = e.bias[s * 4 + j], se = e.standard_error[s * 4 + j];
      EXPECT_GT(se, 0.0);
      EXPECT_LT(std::abs(est - want[j]), 2.0 * se)
          << "sensor " << s << " " << e.parameter_names[j] << ": " << est << " vs " << want[j] << " ± " << se;
    }
  }
  // The reference stays at zero, and the Wald statistic sees the errors.
  for (int j = 0; j < 4; ++j) EXPECT_EQ(e.bias[j], 0.0);
  int32_t dof = 0;
  EXPECT_GT(e.wald(dof), 100.0);
  EXPECT_EQ(dof, 8);
  // The reported covariances are right here: scale ≈ 1 for every pair.
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      if (a != b) {
        EXPECT_NEAR(e.covariance_scale[a * 3 + b], 1.0, 0.1) << a << "," << b;
      }
}

TEST(Registration, PolarOnlyModelRecoversRangeAndAzimuthTightly) {
  std::vector<Truth> truth(3);
  truth[1] = {-120.0, -0.6 * kDeg, {0, 0, 0}};
  truth[2] = {60.0, 0.3 * kDeg, {0, 0, 0}};
  const RegistrationObservations obs = make_observations(kSites, truth, 30, 20, 60.0, 30e3, 1.0, 5);
  RegistrationOptions o;
  o.site_offset = false;
  const RegistrationEstimate e = fit_registration(obs, kSites, o);
  ASSERT_EQ(e.k(), 2);
  for (int s = 1; s < 3; ++s) {
    EXPECT_LT(std::abs(e.bias[s * 2] - truth[s].range), 2.0 * e.standard_error[s * 2]);
    EXPECT_LT(std::abs(e.bias[s * 2 + 1] - truth[s].azimuth), 2.0 * e.standard_error[s * 2 + 1]);
    EXPECT_LT(e.standard_error[s * 2], 20.0);             // metres
    EXPECT_LT(e.standard_error[s * 2 + 1], 0.05 * kDeg);  // a twelfth of the bias or better
  }
}

TEST(Registration, CovarianceScaleFromNormalisedResiduals) {
  std::vector<Truth> truth(3);
  truth[1] = {80.0, 0.2 * kDeg, {0, 0, 0}};
  // Covariances reported 4 times too small: the scale is ≈ 4.
  const RegistrationObservations obs = make_observations(kSites, truth, 20, 20, 50.0, 30e3, 4.0, 9);
  RegistrationOptions o;
  o.huber = 100.0;  // no down-weighting: the plain mean of the normalised residuals
  const RegistrationEstimate e = fit_registration(obs, kSites, o);
  EXPECT_NEAR(e.covariance_scale[0 * 3 + 1], 4.0, 0.4);
  EXPECT_NEAR(e.covariance_scale[1 * 3 + 2], 4.0, 0.4);
}

TEST(Registration, TheRidgeKeepsAnUnobservableComponentBounded) {
  // One target standing still: a translation and (range, azimuth) biases explain the same offset,
  // so their split is not determined by the data.
  RegistrationObservations obs;
  obs.dim = 2;
  const double C[4] = {100.0, 0, 0, 100.0};
  for (int k = 0; k < 50; ++k) {
    const double a[2] = {0.0, 0.0}, b[2] = {-80.0, 30.0};
    obs.add(0, 1, 0, a, b, {}, {}, C);
  }
  const std::vector<std::array<double, 3>> sites{{-100e3, 0, 0}, {0, -100e3, 0}};
  RegistrationOptions o;  // default priors: 300 m, 1°, 1 km
  const RegistrationEstimate e = fit_registration(obs, sites, o);
  // Bounded by the prior: every parameter within a few prior σ, and its standard error is of
  // the prior's size (the data do not shrink it), not zero.
  EXPECT_LT(std::abs(e.bias[4 + 0]), 3 * o.prior_range);
  EXPECT_LT(std::abs(e.bias[4 + 2]), 3 * o.prior_site_offset);
  EXPECT_GT(e.standard_error[4 + 2], 0.3 * o.prior_site_offset);
  EXPECT_LT(e.standard_error[4 + 2], 1.01 * o.prior_site_offset);
  // The offset itself is explained: sensor 1 sees the target along +y (rel = (0, 100 km)), so
  // d = x_0 − x_1 = −J_1 b_1 = (100 km·Δθ + o_x, −Δr + o_y) must be (80, −30).
  EXPECT_NEAR(100e3 * e.bias[4 + 1] + e.bias[4 + 2], 80.0, 5.0);
  EXPECT_NEAR(-e.bias[4 + 0] + e.bias[4 + 3], -30.0, 5.0);
  // Without the ridge (a prior 10^6 times wider) the same split is free: the standard error of
  // the site offset is orders of magnitude larger.
  RegistrationOptions wide = o;
  wide.prior_range = wide.prior_site_offset = 3e8;
  wide.prior_azimuth = 1e3;
  const RegistrationEstimate f = fit_registration(obs, sites, wide);
  EXPECT_GT(f.standard_error[4 + 2], 1e3 * e.standard_error[4 + 2]);
}

TEST(Registration, HandCheckedTranslationOfTwoSensors) {
  // d = x_0 − x_1 = o_1 (sensor 1 reports x − o_1). Observations (10, −4) with C = I and (14, 0)
  // with C = diag(4, 1), prior σ = 10 (weight 0.01):
  //   o_x = (10·1 + 14·0.25) / (1 + 0.25 + 0.01) = 13.5 / 1.26,  o_y = (−4 + 0) / (1 + 1 + 0.01).
  RegistrationObservations obs;
  obs.dim = 2;
  const double x0[2] = {0, 0}, x1a[2] = {-10, 4}, x1b[2] = {-14, 0};
  const double C1[4] = {1, 0, 0, 1}, C2[4] = {4, 0, 0, 1};
  obs.add(0, 1, 0, x0, x1a, {}, {}, C1);
  obs.add(0, 1, 1, x0, x1b, {}, {}, C2);
  RegistrationOptions o;
  o.polar = false;
  o.prior_site_offset = 10.0;
  o.huber = 1e6;
  const std::vector<std::array<double, 3>> sites{{0, 0, 0}, {0, 0, 0}};
  const RegistrationEstimate e = fit_registration(obs, sites, o);
  ASSERT_EQ(e.k(), 2);
  EXPECT_NEAR(e.bias[2], 13.5 / 1.26, 1e-12);
  EXPECT_NEAR(e.bias[3], -4.0 / 2.01, 1e-12);
  // The model standard error is 1/√(information); the reported one is never below it.
  EXPECT_GE(e.standard_error[2], std::sqrt(1.0 / 1.26) - 1e-12);
  EXPECT_GE(e.standard_error[3], std::sqrt(1.0 / 2.01) - 1e-12);
  // Huber: a third, wild observation (1000, 0) pulls with a bounded force when h = 3. Least
  // squares would give (13.5 + 1000) / 2.26 ≈ 448; the converged M-estimate stays within a couple
  // of metres of the inliers' 10 and 14 (each of the three pulls with at most h = 3 σ).
  const double x1c[2] = {-1000, 0};
  obs.add(0, 1, 2, x0, x1c, {}, {}, C1);
  o.huber = 3.0;
  o.iterations = 100;
  const RegistrationEstimate h = fit_registration(obs, sites, o);
  EXPECT_LT(h.bias[2], 16.0);
  EXPECT_GT(h.bias[2], 13.5 / 1.26);
}

TEST(Registration, BadInputNamesTheField) {
  RegistrationObservations obs;
  const double x[2] = {0, 0}, C[4] = {1, 0, 0, 1};
  obs.add(0, 5, 0, x, x, {}, {}, C);
  const std::vector<std::array<double, 3>> sites(2);
  EXPECT_THROW(fit_registration(obs, sites, RegistrationOptions{}), InputError);
  RegistrationOptions o;
  o.huber = -1;
  try {
    o.validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("huber"), std::string::npos);
  }
}

}  // namespace
}  // namespace trackassoc
