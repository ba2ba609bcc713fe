// Joint registration and association (engine/pipeline/registration_stage.hpp) on simulated files:
// the injected registration recovered within 2 standard errors through the whole stage, the
// association it gives against the one without it, a file without errors left exactly as without
// the stage, a significant but immaterial estimate not re-associated (step 3b, its effect worked out
// by hand), and /registration written and read back.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>

#include "engine/pipeline/associator.hpp"
#include "engine/pipeline/metrics.hpp"
#include "engine/pipeline/registration_stage.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "io/hdf5_wrapper.hpp"
#include "kernels/core/error.hpp"
#include "kernels/statistics/chi_square.hpp"

namespace trackassoc {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// recorded_3s's geometry without its recording model (every sensor sees every target); sensor 0
// is clean, 1 and 2 carry range and azimuth biases (and a site error on 2).
Scenario biased(bool errors) {
  Scenario sc = load_scenario("recorded_3s");
  sc.recording = RecordingSpec{};
  sc.random_targets.count = 20;
  sc.sensor_errors.clear();
  if (errors) {
    sc.sensor_errors.resize(3);
    sc.sensor_errors[1].range_bias = -150.0;
    sc.sensor_errors[1].azimuth_bias = -0.6 * kDeg;
    sc.sensor_errors[2].range_bias = 190.0;
    sc.sensor_errors[2].azimuth_bias = 0.5 * kDeg;
  }
  return sc;
}

AssociationOutcome run_default(const TrackFile& file, bool registration, int32_t reference = 0) {
  AssociatorOptions o;
  o.registration.enabled = registration;
  o.registration.reference_sensor = reference;
  return make_associator(o)->associate(file);
}

TEST(RegistrationStage, RecoversTheInjectedBiasesAndRestoresTheAssociation) {
  const Scenario sc = biased(true);
  const TrackFile file = simulation_to_track_file(sc, simulate(sc, 1));
  const AssociationOutcome with = run_default(file, true), without = run_default(file, false);
  ASSERT_TRUE(with.registration.has_value());
  const RegistrationRecord& r = *with.registration;
  EXPECT_TRUE(r.applied);
  EXPECT_EQ(r.reference_sensor, 0);
  EXPECT_GE(r.rounds, 2);
  const std::size_t k = r.parameters.size();
  ASSERT_EQ(r.parameters[0], "range_bias");
  ASSERT_EQ(r.parameters[1], "azimuth_bias");
  for (int s = 1; s < 3; ++s) {
    const double want[2] = {sc.sensor_errors[s].range_bias, sc.sensor_errors[s].azimuth_bias};
    for (int j = 0; j < 2; ++j) {
      const double est = r.estimate[s * k + j], se = r.standard_error[s * k + j];
      EXPECT_LT(std::abs(est - want[j]), 2.0 * se)
          << "sensor " << s << " " << r.parameters[j] << " " << est << " vs " << want[j] << " +- " << se;
    }
    // Informative, not just the prior: the azimuth bias to better than half of itself; the range
    // bias shares its line-of-sight direction with the site offset in this narrow sector, so its
    // standard error only drops below the range prior's 300 m.
    EXPECT_LT(r.standard_error[s * k + 1], 0.5 * std::abs(sc.sensor_errors[s].azimuth_bias));
    EXPECT_LT(r.standard_error[s * k + 0], 300.0);
  }
  const AssociationMetrics a = evaluate_association(file.tracks, file.sensors, with.record);
  const AssociationMetrics b = evaluate_association(file.tracks, file.sensors, without.record);
  EXPECT_GE(a.correct, b.correct + 3) << "with " << a.correct << ", without " << b.correct;
  EXPECT_GE(a.correct_rate, 0.95);
  EXPECT_EQ(a.false_tuples, 0);
}

TEST(RegistrationStage, NoClockOffsetWhereThereIsNone) {
  // recorded_bias_dense: range and azimuth biases, no clock error, every target flying one way.
  // The clock column regresses the position differences on velocities; on the tracks' reported
  // velocities, whose errors the filters correlate with their position errors, the fit found
  // −3.7 s (median over 30 runs, standard errors ≈ 0.35 s) balanced by kilometre site offsets.
  const Scenario sc = load_scenario("recorded_bias_dense");
  int32_t estimates = 0;
  for (int run = 0; run < 3; ++run) {
    const TrackFile file = simulation_to_track_file(sc, simulate(sc, 1, run));
    const AssociationOutcome out = run_default(file, true, -1);
    ASSERT_TRUE(out.registration.has_value());
    const RegistrationRecord& r = *out.registration;
    ASSERT_TRUE(r.applied) << "run " << run;
    const std::size_t k = r.parameters.size();
    const std::size_t clock =
        std::find(r.parameters.begin(), r.parameters.end(), "clock_offset") - r.parameters.begin();
    ASSERT_LT(clock, k);
    for (std::size_t s = 0; s < 3; ++s) {
      if (static_cast<int32_t>(s) == r.reference_sensor) continue;
      const double est = r.estimate[s * k + clock], se = r.standard_error[s * k + clock];
      EXPECT_LT(std::abs(est), std::max(2.0 * se, 0.5))
          << "run " << run << " sensor " << s << ": " << est << " +- " << se << " s";
      ++estimates;
    }
  }
  EXPECT_EQ(estimates, 6);
}

TEST(RegistrationStage, AFileWithoutErrorsIsAssociatedExactlyAsWithoutTheStage) {
  const Scenario sc = biased(false);
  const TrackFile file = simulation_to_track_file(sc, simulate(sc, 2));
  const AssociationOutcome with = run_default(file, true, -1), without = run_default(file, false, -1);
  ASSERT_TRUE(with.registration.has_value());
  EXPECT_FALSE(with.registration->applied);
  EXPECT_EQ(with.registration->rounds, 1);
  EXPECT_EQ(with.record.tuples, without.record.tuples);
  EXPECT_EQ(with.record.target, without.record.target);
  // The Wald statistic is of the order of its degrees of freedom.
  EXPECT_LT(with.registration->wald, 10.0 * with.registration->wald_dof);
}

TEST(RegistrationStage, RegistrationIsWrittenToTheFileAndReadBack) {
  const Scenario sc = biased(true);
  TrackFile file = simulation_to_track_file(sc, simulate(sc, 3));
  const AssociationOutcome out = run_default(file, true);
  store_outcome(file, out);
  const std::string path =
      (std::filesystem::temp_directory_path() / "trackassoc_registration_test.h5").string();
  write_track_file(path, file);
  const TrackFile back = read_track_file_in_process(path);
  ASSERT_TRUE(back.registration.has_value());
  EXPECT_EQ(back.registration->estimate, out.registration->estimate);
  EXPECT_EQ(back.registration->parameters, out.registration->parameters);
  EXPECT_EQ(back.registration->association, out.record.name);
  EXPECT_TRUE(std::isfinite(out.registration->effect));  // step 3b ran: the error is material
  EXPECT_EQ(back.registration->effect, out.registration->effect);
  // The reference was named (0), so `fuse` estimates in its frame: the typed flag survives the file.
  EXPECT_TRUE(out.registration->reference_named);
  EXPECT_TRUE(back.registration->reference_named);
  // Chosen by the stage (-1): stored and read back as not named.
  TrackFile chosen = file;
  store_outcome(chosen, run_default(file, true, -1));
  const std::string chosen_path = path + ".chosen.h5";
  write_track_file(chosen_path, chosen);
  const TrackFile chosen_back = read_track_file_in_process(chosen_path);
  std::filesystem::remove(chosen_path);
  ASSERT_TRUE(chosen_back.registration.has_value());
  EXPECT_FALSE(chosen_back.registration->reference_named);
  // A stored options attribute whose reference_sensor is not an integer reads as not named.
  chosen.registration->options_json = R"({"reference_sensor": "0"})";
  write_track_file(chosen_path, chosen);
  const TrackFile odd_back = read_track_file_in_process(chosen_path);
  std::filesystem::remove(chosen_path);
  EXPECT_FALSE(odd_back.registration->reference_named);
  const h5::File f = h5::File::open_read_only(path);
  const h5::Group g = f.root().open_group("registration");
  std::vector<hsize_t> dims;
  EXPECT_EQ(g.read_doubles("range_bias", 1, dims).size(), 3u);
  EXPECT_EQ(g.read_doubles("azimuth_bias_se", 1, dims).size(), 3u);
  EXPECT_EQ(g.read_doubles("covariance_scale", 2, dims).size(), 9u);
  EXPECT_EQ(g.read_integer_attribute("reference_sensor"), 0);
  std::filesystem::remove(path);
}

// Step 3b's effect, worked out by hand: a translation model (J = −I), 3 sensors, reference 0.
// Sensor 1 is off by b₁ = (30, 40) m, sensor 2 by b₂ = (300, 0) m. Three pairs of tracks of sensors
// 1 and 0 (2 scans each, C = 100² I): m = −b₁, mᵀC⁻¹m = 2500 / 10⁴ = 0.25. One pair of sensors 2
// and 1 (2 scans, C = 200² I): m = −b₂ + b₁ = (−270, 40), mᵀC⁻¹m = 74 500 / 40 000 = 1.8625.
// δ₁ = (6 · 0.25 + 2 · 1.8625) / 8 = 0.653125 from 4 pairs, δ₂ = 1.8625 from 1 pair: with k = 2
// parameters only sensor 1 (4 > 2 pairs) counts, so the largest is δ₁.
TEST(RegistrationStage, TheEffectIsTheCorrectionInSigmasOfItsPairs) {
  RegistrationOptions model;
  model.polar = false;
  model.site_offset = true;
  model.clock_offset = false;
  model.reference_sensor = 0;
  RegistrationEstimate e;
  e.sensors = 3;
  e.dim = 2;
  e.reference = 0;
  e.parameter_names = registration_parameter_names(model, 2);
  ASSERT_EQ(e.k(), 2);
  e.bias = {0, 0, 30, 40, 300, 0};
  RegistrationObservations obs;
  obs.dim = 2;
  const std::vector<double> x = {1000.0, 2000.0}, v = {0.0, 0.0};
  const std::vector<double> c1 = {1e4, 0, 0, 1e4}, c2 = {4e4, 0, 0, 4e4};
  for (int64_t pair = 0; pair < 3; ++pair)
    for (int scan = 0; scan < 2; ++scan) obs.add(1, 0, pair, x, x, v, v, c1);
  for (int scan = 0; scan < 2; ++scan) obs.add(2, 1, 7, x, x, v, v, c2);
  const std::vector<std::array<double, 3>> sites(3, std::array<double, 3>{0, 0, 0});
  const RegistrationEffect effect = registration_effect(obs, e, model, sites);
  ASSERT_EQ(effect.delta.size(), 3u);
  EXPECT_NEAR(effect.delta[1], 0.653125, 1e-12);
  EXPECT_NEAR(effect.delta[2], 1.8625, 1e-12);
  EXPECT_NEAR(effect.delta[0], 0.25, 1e-12);  // the reference's pairs, never counted
  EXPECT_EQ(effect.pairs, (std::vector<int64_t>{3, 4, 1}));
  EXPECT_NEAR(effect.largest, 0.653125, 1e-12);
}

// A file without registration errors, tested at a level every estimate passes (significance
// 0.999): the estimate is "significant" but moves no pair by a σ, so the stage must not re-associate
// (without step 3b it did: rounds ≥ 2). The biased file's estimate is material and is applied.
TEST(RegistrationStage, ASignificantButImmaterialEstimateIsNotReassociated) {
  const Scenario clean = biased(false);
  const TrackFile file = simulation_to_track_file(clean, simulate(clean, 2));
  AssociatorOptions o;
  o.registration.significance = 0.999;
  const AssociationOutcome immaterial = make_associator(o)->associate(file);
  ASSERT_TRUE(immaterial.registration.has_value());
  const RegistrationRecord& r = *immaterial.registration;
  EXPECT_GT(r.wald, chi_square_quantile(0.001, r.wald_dof));  // significant at this level
  ASSERT_TRUE(std::isfinite(r.effect));
  EXPECT_LT(r.effect, 1.0);
  EXPECT_EQ(r.rounds, 1);
  EXPECT_FALSE(r.applied);
  EXPECT_EQ(immaterial.record.tuples, run_default(file, false, -1).record.tuples);
  // The Wald test alone (min_effect 0) re-associates the same file.
  o.registration.min_effect = 0.0;
  EXPECT_GE(make_associator(o)->associate(file).registration->rounds, 2);
  // A real registration error: material, re-associated and applied.
  const Scenario sc = biased(true);
  const AssociationOutcome material = run_default(simulation_to_track_file(sc, simulate(sc, 1)), true);
  ASSERT_TRUE(material.registration.has_value());
  EXPECT_GT(material.registration->effect, 1.0);
  EXPECT_GE(material.registration->rounds, 2);
  EXPECT_TRUE(material.registration->applied);
}

TEST(RegistrationStage, OptionsNameABadMinimumEffect) {
  for (const double bad : {-0.5, std::nan(""), std::numeric_limits<double>::infinity()}) {
    RegistrationStageOptions o;
    o.min_effect = bad;
    try {
      o.validate();
      ADD_FAILURE() << "min_effect " << bad << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("registration.min_effect"), std::string::npos) << e.what();
    }
  }
  RegistrationStageOptions zero;
  zero.min_effect = 0.0;
  EXPECT_NO_THROW(zero.validate());
  EXPECT_EQ(zero.to_json().at("min_effect").get<double>(), 0.0);
}

}  // namespace
}  // namespace trackassoc
