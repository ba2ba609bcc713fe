// Fusion of registered reports (engine/fusion/track_fuser.hpp, "Registration"): on a hand-made
// two-sensor file with a known translation the fused state is the hand-computed fusion of the
// corrected reports (and of the reports as recorded when the correction is off, belongs to
// another association or was not applied); on a simulated file with injected range and azimuth
// biases the fused position RMSE against /truth is lower with the correction than without.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>

#include "engine/fusion/fused_accuracy.hpp"
#include "engine/fusion/track_fuser.hpp"
#include "engine/pipeline/associator.hpp"
#include "engine/registration/registered_reports.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

using Eigen::Matrix2d;
using Eigen::Matrix4d;
using Eigen::Vector2d;
using Eigen::Vector4d;

// Sensor 0 (the reference) and sensor 1 both report one target every 1 s over 0-10 s; sensor 1's
// site is off by o = (300, −200) m, so it reports the target shifted by −o. Positions unknown: the
// registration is a translation, site_offset_x/_y.
const Vector2d kOffset(300.0, -200.0);

Vector4d truth_at(double t) { return Vector4d(1000.0 + 100.0 * t, 2000.0 - 50.0 * t, 100.0, -50.0); }

Matrix4d p0() { return Vector4d(400.0, 400.0, 25.0, 25.0).asDiagonal(); }
Matrix4d p1() {
  Matrix4d P = Vector4d(900.0, 100.0, 16.0, 9.0).asDiagonal();
  P(0, 1) = P(1, 0) = 60.0;
  return P;
}
// The registration's covariance of (o_x, o_y).
Matrix2d offset_covariance() { return (Matrix2d() << 2500.0, 400.0, 400.0, 1600.0).finished(); }

// `named`: the association named sensor 0 as its reference (fuse estimates in its frame); else
// the stage chose it, and fuse estimates in the sensors' average frame.
TrackFile translated_file(bool applied, const std::string& association, bool named = true) {
  TrackFile f;
  f.sensors.resize(2);
  f.sensors[0].id = 0, f.sensors[1].id = 7;
  f.recording.sensors_unknown = "position";
  f.tracks = TrackTable(StateLayout::kXY_VXVY);
  for (int i = 0; i <= 10; ++i) {
    const double t = i;
    // Small, fixed report errors so the two sensors disagree beyond the offset too.
    const Vector4d e0(10.0 * std::sin(t), -8.0 * std::cos(t), 1.0, -0.5),
        e1(-6.0, 12.0 * std::sin(2 * t), 0.5, 1.0);
    f.tracks.push_back(0, 3, t, truth_at(t) + e0, p0(), 1);
    Vector4d x1 = truth_at(t) + e1;
    x1.head<2>() -= kOffset;
    f.tracks.push_back(7, 4, t, x1, p1(), 1);
  }
  AssociationRecord a;
  a.name = "default";
  a.num_sensors = 2;
  a.tuples = {3, 4};
  a.cost = {0.0};
  f.associations.push_back(a);
  RegistrationRecord r;
  r.reference_sensor = 0;
  r.sensor = {0, 7};
  r.parameters = {"site_offset_x", "site_offset_y"};
  r.estimate = {0.0, 0.0, kOffset.x(), kOffset.y()};
  const Matrix2d V = offset_covariance();
  r.standard_error = {0.0, 0.0, std::sqrt(V(0, 0)), std::sqrt(V(1, 1))};
  r.covariance = {0, 0, 0, 0, V(0, 0), V(0, 1), V(1, 0), V(1, 1)};
  r.covariance_scale.assign(4, 1.0);
  r.pair_observations.assign(4, 11);
  r.applied = applied;
  r.association = association;
  r.reference_named = named;
  r.options_json = named ? R"({"reference_sensor": 0})" : R"({"reference_sensor": -1})";
  f.registration = r;
  return f;
}

// The naive (information-weighted) fusion of the two reports at time index i, sensor 1's report
// corrected by +o and its position covariance widened by V when `corrected`. In the average frame
// (`average`; a translation weighs both sensors alike) the frame is the midpoint: sensor 0's report
// moves by −o/2 and sensor 1's by +o/2 (the widening stays sensor 1's V).
Vector4d hand_fused(const TrackFile& f, int i, bool corrected, Matrix4d* P = nullptr, bool average = false) {
  Vector4d x0, x1;
  for (int c = 0; c < 4; ++c) x0[c] = f.tracks.state[c][2 * i], x1[c] = f.tracks.state[c][2 * i + 1];
  Matrix4d P1 = p1();
  if (corrected) {
    x1.head<2>() += average ? Vector2d(0.5 * kOffset) : kOffset;
    if (average) x0.head<2>() -= 0.5 * kOffset;
    P1.topLeftCorner<2, 2>() += offset_covariance();
  }
  const Matrix4d Y = p0().inverse() + P1.inverse();
  const Matrix4d Pf = Y.inverse();
  if (P) *P = Pf;
  return Pf * (p0().inverse() * x0 + P1.inverse() * x1);
}

void expect_fused(const FusedTrackRecord& rec, const TrackFile& f, bool corrected, bool average = false) {
  ASSERT_EQ(rec.size(), 11u);
  for (int i = 0; i <= 10; ++i) {
    ASSERT_DOUBLE_EQ(rec.t[i], i);
    Matrix4d P;
    const Vector4d want = hand_fused(f, i, corrected, &P, average);
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(rec.state[c][i], want[c], 1e-6) << "t " << i << " component " << c;
    for (int r = 0; r < 4; ++r)
      for (int c = r; c < 4; ++c) EXPECT_NEAR(rec.cov[packed_index(4, r, c)][i], P(r, c), 1e-6 * P(r, r));
  }
}

TEST(FuseRegistration, AKnownTranslationIsCorrectedBeforeFusing) {
  TrackFile f = translated_file(true, "default");
  const TrackFuserSummary s = fuse_track_file(f, "", "", {});
  EXPECT_TRUE(s.registered);
  expect_fused(f.fused.back(), f, true);
  EXPECT_TRUE(nlohmann::json::parse(f.fused.back().options_json).at("registration").get<bool>());
  // Corrected, the fused position is within a few metres of the truth; as recorded it carries
  // about half the 361 m offset (hand count: |o| = sqrt(300² + 200²)).
  const Vector4d c = hand_fused(f, 5, true), u = hand_fused(f, 5, false);
  EXPECT_LT((c.head<2>() - truth_at(5).head<2>()).norm(), 30.0);
  EXPECT_GT((u.head<2>() - truth_at(5).head<2>()).norm(), 100.0);
}

TEST(FuseRegistration, AReferenceTheStageChoseGivesTheSensorsAverageFrame) {
  // The same file, the reference chosen by the stage: neither sensor is known to be right, so the
  // fused track lies at the midpoint of the two frames, o/2 from the truth.
  TrackFile f = translated_file(true, "default", false);
  const TrackFuserSummary s = fuse_track_file(f, "", "", {});
  EXPECT_TRUE(s.registered);
  EXPECT_NE(s.registration.find("average frame"), std::string::npos) << s.registration;
  expect_fused(f.fused.back(), f, true, true);
}

TEST(FuseRegistration, ReportsAsRecordedWhenOffForeignOrNotApplied) {
  for (int which = 0; which < 3; ++which) {
    TrackFile f = translated_file(which != 2, which == 1 ? "other" : "default");
    TrackFuserOptions o;
    o.registration = which != 0;
    const TrackFuserSummary s = fuse_track_file(f, "", "", o);
    EXPECT_FALSE(s.registered) << which;
    expect_fused(f.fused.back(), f, false);
    EXPECT_FALSE(nlohmann::json::parse(f.fused.back().options_json).at("registration").get<bool>());
  }
}

TEST(FuseRegistration, AReferenceSensorNotInTheFileIsAnInputError) {
  const TrackFile f = translated_file(true, "default");
  AssociatorOptions o;
  o.registration.reference_sensor = 99;  // /sensors ids are 0 and 7
  try {
    make_associator(o)->associate(f);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--reference-sensor"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("99"), std::string::npos) << e.what();
  }
}

TEST(FuseRegistration, ARecordThatDoesNotFitTheFileIsAnInputError) {
  TrackFile f = translated_file(true, "default");
  f.registration->sensor = {0, 8};  // no row for /sensors id 7
  EXPECT_THROW(fuse_track_file(f, "", "", {}), InputError);
  f = translated_file(true, "default");
  f.registration->parameters = {"range_bias", "site_offset_y"};  // no model of the stage
  EXPECT_THROW(fuse_track_file(f, "", "", {}), InputError);
}

// recorded_3s's geometry, every sensor seeing every target; sensor 0 (the reference) is clean,
// sensors 1 and 2 carry range and azimuth biases. The default association, then fusion with and
// without the correction: the registered reports' fused RMSE is the lower.
TEST(FuseRegistration, InjectedBiasesFusedRmseIsLowerWithTheCorrection) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  Scenario sc = load_scenario("recorded_3s");
  sc.recording = RecordingSpec{};
  sc.random_targets.count = 20;
  sc.sensor_errors.assign(3, {});
  sc.sensor_errors[1].range_bias = -150.0;
  sc.sensor_errors[1].azimuth_bias = -0.6 * kDeg;
  sc.sensor_errors[2].range_bias = 190.0;
  sc.sensor_errors[2].azimuth_bias = 0.5 * kDeg;
  TrackFile file = simulation_to_track_file(sc, simulate(sc, 1));
  AssociatorOptions ao;
  ao.registration.reference_sensor = 0;
  const AssociationOutcome out = make_associator(ao)->associate(file);
  ASSERT_TRUE(out.registration && out.registration->applied);
  store_outcome(file, out);
  ASSERT_TRUE(file.truth.has_value());
  TrackFuserOptions on, off;
  off.registration = false;
  TrackFile a = file, b = file;
  ASSERT_TRUE(fuse_track_file(a, "", "", on).registered);
  ASSERT_FALSE(fuse_track_file(b, "", "", off).registered);
  const FusedAccuracy with = evaluate_fused(a.tracks, a.sensors, *a.truth, a.fused.back());
  const FusedAccuracy without = evaluate_fused(b.tracks, b.sensors, *b.truth, b.fused.back());
  ASSERT_EQ(with.fused_rows, without.fused_rows);  // one association, one time grid
  ASSERT_GT(with.fused_rows, 500);
  // The biases are 2-5 filtered sigmas at 100-140 km (0.5° ≈ 1 km); the clean sensor's own RMSE
  // bounds what a registration relative to it can reach.
  EXPECT_LT(with.fused_rmse, 0.8 * without.fused_rmse) << with.fused_rmse << " vs " << without.fused_rmse;
  std::cout << "fused RMSE with registration " << with.fused_rmse << " m, without " << without.fused_rmse
            << " m, sensor 0 " << with.sensor_rmse[0] << " m\n";
}

}  // namespace
}  // namespace trackassoc
