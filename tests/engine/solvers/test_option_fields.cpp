// Options declared once (engine/solvers/option_fields.hpp) and the enum <-> name tables
// (kernels/core/enum_names.hpp): every declared field round-trips (JSON → struct → the same JSON, with
// the struct members checked one by one), a wrong type, a value out of the member's range and an
// unknown key each give the message users have always seen, every enumerator round-trips through
// its name and a wrong name lists the valid ones; the help listing names every field.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "engine/pipeline/fuzzy_pipeline.hpp"
#include "engine/pipeline/pipeline_sd.hpp"
#include "engine/pipeline/siamese_track_file.hpp"
#include "engine/solvers/chnn_pseudo_solver.hpp"
#include "engine/solvers/hopfield_json.hpp"
#include "engine/solvers/relaxation_solvers.hpp"
#include "engine/studies/seed001/experiment_seed001.hpp"
#include "kernels/core/error.hpp"
#include "kernels/learning/siamese.hpp"
#include "kernels/statistics/cost_tensor.hpp"

namespace trackassoc {
namespace {

using nlohmann::json;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

// ---------------------------------------------------------------- the enum tables

// The names of the table in order, and each name parsed back to its enumerator.
template <class E>
void expect_names(const std::vector<std::pair<E, std::string>>& expected) {
  const auto table = enum_names(E{});
  ASSERT_EQ(table.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(table[i].name, expected[i].second);
    EXPECT_EQ(enum_name(expected[i].first), expected[i].second);
    EXPECT_EQ(parse_enum<E>(expected[i].second, "x"), expected[i].first) << expected[i].second;
  }
}

TEST(EnumNames, EveryEnumeratorRoundTripsThroughItsName) {
  expect_names<HopfieldInit>({{HopfieldInit::kZero, "zero"},
                              {HopfieldInit::kRandom, "random"},
                              {HopfieldInit::kGreedy, "greedy"},
                              {HopfieldInit::kMeanField, "mean_field"}});
  expect_names<HopfieldOrder>({{HopfieldOrder::kRandom, "random"},
                               {HopfieldOrder::kSliceRandom, "slice_random"},
                               {HopfieldOrder::kCost, "cost"}});
  expect_names<HopfieldEnergy>(
      {{HopfieldEnergy::kFullPlane, "full_plane"}, {HopfieldEnergy::kPrinted, "printed"}});
  expect_names<HopfieldRepair>({{HopfieldRepair::kGreedy, "greedy"}, {HopfieldRepair::kLap, "lap"}});
  expect_names<StepRule>({{StepRule::kPolyak, "polyak"},
                          {StepRule::kDiminishing, "diminishing"},
                          {StepRule::kDeflected, "deflected"}});
  expect_names<SynthesisFunction>({{SynthesisFunction::kPowerMean, "power-mean"},
                                   {SynthesisFunction::kGeometricMean, "geometric-mean"},
                                   {SynthesisFunction::kWeightedMean, "weighted-mean"},
                                   {SynthesisFunction::kWeightedPowerMean, "weighted-power-mean"},
                                   {SynthesisFunction::kMinMaxMean, "min-max-mean"}});
  expect_names<ReliabilityWeighting>({{ReliabilityWeighting::kNone, "none"},
                                      {ReliabilityWeighting::kTemporaryTrack, "temporary"},
                                      {ReliabilityWeighting::kSystemTrack, "system"},
                                      {ReliabilityWeighting::kProduct, "product"}});
  expect_names<PairArchitecture>({{PairArchitecture::kSiamese, "siamese"},
                                  {PairArchitecture::kConcatLstm, "lstm"},
                                  {PairArchitecture::kConcatBiLstm, "bilstm"}});
  expect_names<AlphaBetaGainMode>(
      {{AlphaBetaGainMode::kFixed, "fixed"}, {AlphaBetaGainMode::kKalata, "kalata"}});
  expect_names<FusionMethod>({{FusionMethod::kFuzzy, "fuzzy"}, {FusionMethod::kFtaa, "ftaa"}});
  expect_names<PacketSource>({{PacketSource::kTrack, "track"}, {PacketSource::kPlot, "plot"}});
  expect_names<BearingReading>(
      {{BearingReading::kErratum, "erratum"}, {BearingReading::kLiteral, "literal"}});
  expect_names<AlignmentMethod>(
      {{AlignmentMethod::kTwoSided, "two-sided"}, {AlignmentMethod::kForward, "forward"}});
  expect_names<GateMethod>(
      {{GateMethod::kCalibrated, "calibrated"}, {GateMethod::kChiSquareSum, "chi2-sum"}});
  expect_names<CostForm>({{CostForm::kChain, "chain"}, {CostForm::kAllPairs, "all-pairs"}});
}

TEST(EnumNames, AWrongNameListsTheValidOnes) {
  EXPECT_EQ(error_of([] { parse_enum<HopfieldInit>("zeros", "init"); }),
            "init: expected zero, random, greedy or mean_field, found 'zeros'");
  EXPECT_EQ(error_of([] { parse_enum<HopfieldEnergy>("Printed", "energy"); }),
            "energy: expected full_plane or printed, found 'Printed'");
  // Notes follow their names.
  EXPECT_EQ(error_of([] { parse_enum<SynthesisFunction>("eq11", "synthesis"); }),
            "synthesis: expected power-mean (Eq. 9), geometric-mean (Eq. 10), weighted-mean (Eq. 11), "
            "weighted-power-mean (Eq. 12) or min-max-mean (Eq. 13), found 'eq11'");
  EXPECT_EQ(error_of([] { parse_enum<FusionMethod>("", "--solver"); }),
            "--solver: expected fuzzy or ftaa, found ''");
}

// ---------------------------------------------------------------- Hopfield

// Every key of HopfieldOptions set to a value other than the "hopfield" preset's (header comment of
// engine/solvers/hopfield_json.hpp: 30 keys), valid together.
json every_hopfield_key() {
  return json::parse(R"({
    "energy": "printed", "schedule": "sync", "restarts": 3, "max_sweeps": 42, "init": "greedy",
    "init_density": 0.5, "greedy_noise": 0.375, "order": "slice_random", "anneal_E_factor": 2.5,
    "anneal_sweeps": 7, "temperature": 0.25, "damping": 0.75, "continuous_async": true, "dt": 0.125,
    "tau": 0.5, "u0_start": 0.75, "u0_end": 0.0625, "gain_anneal_steps": 11, "noise": 0.03125,
    "self_excitation": 0.5, "tolerance": 0.001, "mean_field_steps": 13, "repair": "lap", "trace": true,
    "polish": true, "A": 2.0, "B": 3.0, "C": 4.0, "D": 0.5, "E": 1.5})");
}

TEST(OptionFields, EveryHopfieldFieldRoundTrips) {
  const json in = every_hopfield_key();
  ASSERT_EQ(in.size(), 30u);
  bool polish = false;
  const HopfieldOptions o = hopfield_options_from_json("hopfield", in, polish);
  EXPECT_EQ(o.energy, HopfieldEnergy::kPrinted);
  EXPECT_EQ(o.schedule, HopfieldSchedule::kSync);
  EXPECT_EQ(o.restarts, 3);
  EXPECT_EQ(o.max_sweeps, 42);
  EXPECT_EQ(o.init, HopfieldInit::kGreedy);
  EXPECT_EQ(o.init_density, 0.5);
  EXPECT_EQ(o.greedy_noise, 0.375);
  EXPECT_EQ(o.order, HopfieldOrder::kSliceRandom);
  EXPECT_EQ(o.anneal_E_factor, 2.5);
  EXPECT_EQ(o.anneal_sweeps, 7);
  EXPECT_EQ(o.temperature, 0.25);
  EXPECT_EQ(o.damping, 0.75);
  EXPECT_TRUE(o.continuous_async);
  EXPECT_EQ(o.dt, 0.125);
  EXPECT_EQ(o.tau, 0.5);
  EXPECT_EQ(o.u0_start, 0.75);
  EXPECT_EQ(o.u0_end, 0.0625);
  EXPECT_EQ(o.gain_anneal_steps, 11);
  EXPECT_EQ(o.noise, 0.03125);
  EXPECT_EQ(o.self_excitation, 0.5);
  EXPECT_EQ(o.tolerance, 0.001);
  EXPECT_EQ(o.mean_field_steps, 13);
  EXPECT_EQ(o.repair, HopfieldRepair::kLap);
  EXPECT_TRUE(o.trace);
  EXPECT_TRUE(o.polish);
  EXPECT_TRUE(polish);
  EXPECT_FALSE(o.auto_weights);
  EXPECT_EQ(o.weights.A, 2.f);
  EXPECT_EQ(o.weights.B, 3.f);
  EXPECT_EQ(o.weights.C, 4.f);
  EXPECT_EQ(o.weights.D, 0.5f);
  EXPECT_EQ(o.weights.E, 1.5f);
  // Written back: the same 30 keys and values; read again: the same JSON.
  const json out = hopfield_options_to_json(o);
  EXPECT_EQ(out, in) << out.dump();
  EXPECT_EQ(hopfield_options_to_json(hopfield_options_from_json("hopfield", out, polish)), in);
}

TEST(OptionFields, HopfieldWeightsGivenInPartKeepTheAutomaticOnes) {
  bool polish = false;
  // Automatic: A = B = C = 1, D = 0, E = 1.4985 (engine/solvers/hopfield_json.hpp); C given alone.
  const HopfieldOptions o = hopfield_options_from_json("hopfield", json{{"C", 2.5}}, polish);
  EXPECT_FALSE(o.auto_weights);
  EXPECT_EQ(o.weights.A, 1.f);
  EXPECT_EQ(o.weights.B, 1.f);
  EXPECT_EQ(o.weights.C, 2.5f);
  EXPECT_EQ(o.weights.D, 0.f);
  EXPECT_EQ(o.weights.E, 1.4985f);
  // Automatic weights are not written (reading them would switch the automatic weights off).
  const json defaults = hopfield_options_to_json(hopfield_preset("hopfield"));
  EXPECT_EQ(defaults.size(), 25u);
  EXPECT_FALSE(defaults.contains("A"));
  EXPECT_EQ(defaults.at("restarts"), 8);
  EXPECT_EQ(defaults.at("init"), "mean_field");
  // hopfield-paper's printed weights are written: A = B = C = 300, D = 200, E = 1100.
  const json paper = hopfield_options_to_json(hopfield_preset("hopfield-paper"));
  EXPECT_EQ(paper.size(), 30u);
  EXPECT_EQ(paper.at("D"), 200.0);
  EXPECT_EQ(paper.at("E"), 1100.0);
}

TEST(OptionFields, ChnnScheduleIsItsEulerStepOrder) {
  bool polish = false;
  const HopfieldOptions o = hopfield_options_from_json("chnn", json{{"schedule", "async"}}, polish);
  EXPECT_EQ(o.network, HopfieldNetwork::kContinuous);
  EXPECT_TRUE(o.continuous_async);
  const json out = hopfield_options_to_json(o);
  EXPECT_EQ(out.at("schedule"), "async");
  const HopfieldOptions back = hopfield_options_from_json("chnn", out, polish);
  EXPECT_EQ(back.network, HopfieldNetwork::kContinuous);
  EXPECT_TRUE(back.continuous_async);
  EXPECT_EQ(hopfield_options_to_json(hopfield_preset("chnn")).at("schedule"), "sync");
}

TEST(OptionFields, HopfieldErrorsNameSolverAndKey) {
  bool polish = false;
  auto err = [&](const json& j) {
    return error_of([&] { hopfield_options_from_json("hopfield", j, polish); });
  };
  EXPECT_EQ(err(json{{"restarts", "8"}}), "solver 'hopfield' options: 'restarts' must be a number");
  EXPECT_EQ(err(json{{"restarts", 2.5}}), "solver 'hopfield' options: 'restarts' must be an integer");
  EXPECT_EQ(err(json{{"restarts", 5000000000}}),
            "solver 'hopfield' options: 'restarts' = 5000000000 is out of range for the field "
            "(-2147483648 to 2147483647)");
  EXPECT_EQ(err(json{{"trace", 1}}), "solver 'hopfield' options: 'trace' must be true or false");
  EXPECT_EQ(err(json{{"init", 0}}), "solver 'hopfield' options: 'init' must be a string");
  EXPECT_EQ(err(json{{"init", "zeros"}}),
            "solver 'hopfield' options: init: expected zero, random, greedy or mean_field, found 'zeros'");
  EXPECT_EQ(err(json::array()), "solver 'hopfield' options: expected a JSON object");
  // The member's own range is validate()'s (restarts 1..100000).
  EXPECT_EQ(err(json{{"restarts", 0}}), "solver 'hopfield' options: restarts: expected 1..100000");
  const std::string unknown = err(json{{"restart", 2}});
  EXPECT_EQ(unknown.rfind(
                "solver 'hopfield' options: unknown key 'restart' (did you mean 'restarts'?); known keys: "
                "energy, schedule, restarts, max_sweeps, init, ",
                0),
            0u)
      << unknown;
  EXPECT_NE(unknown.find(", A, B, C, D, E"), std::string::npos) << unknown;
}

TEST(OptionFields, HelpListsEveryHopfieldField) {
  const auto& fields = hopfield_option_fields();
  const std::string help = fields.help(hopfield_preset("hopfield"));
  std::istringstream lines(help);
  std::vector<std::string> rows;
  for (std::string line; std::getline(lines, line);) rows.push_back(line);
  // A header, then one row per field, each starting with its key; as many fields as keys written.
  ASSERT_EQ(fields.fields().size(), every_hopfield_key().size());
  ASSERT_EQ(rows.size(), 1 + fields.fields().size()) << help;
  EXPECT_EQ(rows[0].rfind("  key", 0), 0u);
  for (std::size_t i = 0; i < fields.fields().size(); ++i) {
    const std::string& key = fields.fields()[i].key;
    EXPECT_EQ(rows[1 + i].rfind("  " + key + " ", 0), 0u) << rows[1 + i];
    EXPECT_TRUE(every_hopfield_key().contains(key)) << key;
  }
  // restarts: default 8 of the preset, range 1..100000; init lists its names; A is unset (automatic).
  EXPECT_NE(rows[3].find(" 8 "), std::string::npos) << rows[3];
  EXPECT_NE(rows[3].find("1..100000"), std::string::npos) << rows[3];
  EXPECT_NE(rows[5].find("zero, random, greedy or mean_field"), std::string::npos) << rows[5];
  EXPECT_NE(rows[26].find(" - "), std::string::npos) << rows[26];
}

// ---------------------------------------------------------------- relaxation solvers

TEST(OptionFields, LagrangianFieldsRoundTrip) {
  const json in = json::parse(R"({"max_iterations": 17, "relative_gap_tolerance": 0.25,
      "absolute_gap_tolerance": 0.5, "time_limit_s": 3.5, "step_rule": "deflected", "theta": 1.5,
      "theta_patience": 4, "min_theta": 0.125, "max_rounds": 9})");
  const LagrangianOptions o = lagrangian_options(in, "lr+ls", true);
  EXPECT_EQ(o.max_iterations, 17);
  EXPECT_EQ(o.relative_gap_tolerance, 0.25);
  EXPECT_EQ(o.absolute_gap_tolerance, 0.5);
  EXPECT_EQ(o.time_limit_s, 3.5);
  EXPECT_EQ(o.step_rule, StepRule::kDeflected);
  EXPECT_EQ(o.theta, 1.5);
  EXPECT_EQ(o.theta_patience, 4);
  EXPECT_EQ(o.min_theta, 0.125);
  EXPECT_EQ(o.local_search_options.max_rounds, 9);
  EXPECT_TRUE(o.local_search);
  EXPECT_EQ(lagrangian_option_fields(true).write(o), in);
  // lr has no max_rounds; the infinite default time limit is not written (JSON has no inf).
  json lr = in;
  lr.erase("max_rounds");
  EXPECT_EQ(lagrangian_option_fields(false).write(lagrangian_options(lr, "lr", false)), lr);
  EXPECT_FALSE(lagrangian_option_fields(false).write(LagrangianOptions{}).contains("time_limit_s"));
  EXPECT_EQ(
      error_of([&] { lagrangian_options(in, "lr", false); }),
      "solver 'lr' options: unknown key 'max_rounds'; known keys: max_iterations, relative_gap_tolerance, "
      "absolute_gap_tolerance, time_limit_s, step_rule, theta, theta_patience, min_theta");
  EXPECT_EQ(error_of([] {
              lagrangian_options(json{{"step_rule", "newton"}}, "lr", false);
            }),
            "solver 'lr' options: step_rule: expected polyak, diminishing or deflected, found 'newton'");
  EXPECT_EQ(error_of([] {
              lagrangian_options(json{{"max_iterations", 5000000000}}, "lr", false);
            }),
            "solver 'lr' options: 'max_iterations' = 5000000000 is out of range for the field "
            "(-2147483648 to 2147483647)");
}

TEST(OptionFields, ExactAndPolishFieldsRoundTrip) {
  const json in = json::parse(
      R"({"time_limit_s": 2.5, "max_nodes": 123456789012, "node_subgradient_iterations": 3,
          "reduced_cost_fixing": false, "root_max_iterations": 77})");
  BranchAndBoundOptions b;
  exact_option_fields().read(in, b, "exact");
  EXPECT_EQ(b.time_limit_s, 2.5);
  EXPECT_EQ(b.max_nodes, 123456789012);
  EXPECT_EQ(b.node_subgradient_iterations, 3);
  EXPECT_FALSE(b.reduced_cost_fixing);
  EXPECT_EQ(b.root.max_iterations, 77);
  EXPECT_EQ(exact_option_fields().write(b), in);

  const json sd = json::parse(R"({"time_limit_s": 0.5, "max_nodes": 1000})");
  const ExactSDOptions e = exact_sd_options(sd, "exact");
  EXPECT_EQ(e.time_limit_s, 0.5);
  EXPECT_EQ(e.max_nodes, 1000);
  EXPECT_EQ(exact_sd_option_fields().write(e), sd);
  EXPECT_EQ(error_of([] {
              exact_sd_options(json{{"node_subgradient_iterations", 3}}, "exact");
            }),
            "solver 'exact' options: unknown key 'node_subgradient_iterations'; known keys: time_limit_s, "
            "max_nodes");

  const json polish = json::parse(R"({"max_rounds": 5, "base": {"restarts": 2}})");
  PolishOptions p;
  polish_option_fields().read(polish, p, "hopfield+ls");
  EXPECT_EQ(p.local_search.max_rounds, 5);
  EXPECT_EQ(p.base, json({{"restarts", 2}}));
  EXPECT_EQ(polish_option_fields().write(p), polish);
}

TEST(OptionFields, ChnnPseudoFieldsRoundTrip) {
  const json in = json::parse(R"({"A": 0.5, "B": 2.0, "C": 3.0, "D": 0.25, "dt": 0.01, "tau": 0.0,
      "u0": 0.1, "max_steps": 500, "tolerance": 0.01, "noise": 0.0, "gated": false, "lambda_margin": 0.5,
      "reference": 2, "leftover_passes": 0})");
  ChnnPseudoSolverOptions o;
  chnn_pseudo_option_fields().read(in, o, "chnn-pseudo");
  EXPECT_EQ(o.network.A, 0.5);
  EXPECT_EQ(o.network.B, 2.0);
  EXPECT_EQ(o.network.C, 3.0);
  EXPECT_EQ(o.network.D, 0.25);
  EXPECT_EQ(o.network.dt, 0.01);
  EXPECT_EQ(o.network.tau, 0.0);
  EXPECT_EQ(o.network.u0, 0.1);
  EXPECT_EQ(o.network.max_steps, 500);
  EXPECT_EQ(o.network.tolerance, 0.01);
  EXPECT_EQ(o.network.noise, 0.0);
  EXPECT_FALSE(o.gated);
  EXPECT_EQ(o.lambda_margin, 0.5);
  EXPECT_EQ(o.reference, 2);
  EXPECT_EQ(o.network.leftover_passes, 0);
  EXPECT_EQ(chnn_pseudo_option_fields().write(o), in);
  EXPECT_EQ(error_of([&] {
              chnn_pseudo_option_fields().read(json{{"gated", "yes"}}, o, "chnn-pseudo");
            }),
            "solver 'chnn-pseudo' options: 'gated' must be true or false");
}

// ---------------------------------------------------------------- siamese and fuzzy (written to HDF5)

TEST(OptionFields, SiameseTrackFileFieldsRoundTrip) {
  const json in = json::parse(
      R"({"sensors": [3, 1], "points": "plot", "threshold": 0.75, "time_origin": -12.5, "batch_tracks": 8})");
  const SiameseTrackFileOptions o = siamese_track_file_options(in);
  EXPECT_EQ(o.sensors, (std::vector<int32_t>{3, 1}));
  EXPECT_EQ(o.points, PacketSource::kPlot);
  EXPECT_EQ(o.association.probability_threshold, 0.75);
  EXPECT_EQ(o.time_origin, -12.5);
  EXPECT_EQ(o.association.batch_tracks, 8);
  EXPECT_EQ(o.to_json(), in);
  // The defaults as the /associations options attribute has always held them.
  EXPECT_EQ(SiameseTrackFileOptions{}.to_json().dump(),
            R"({"batch_tracks":64,"points":"track","sensors":[],"threshold":0.5,"time_origin":0.0})");
  EXPECT_EQ(error_of([] {
              siamese_track_file_options(json{{"sensors", {1, 2, 3}}});
            }),
            "solver 'siamese' options: 'sensors' must be two /sensors ids (int32), e.g. [0, 1]");
  EXPECT_EQ(error_of([] {
              siamese_track_file_options(json{{"points", "plots"}});
            }),
            "solver 'siamese' options: points: expected track or plot, found 'plots'");
}

TEST(OptionFields, FuzzyAndFtaaFieldsRoundTrip) {
  const json fz = json::parse(R"({"method": "fuzzy", "packet_period": 2.0, "packets": "plot",
      "u_max_position": 300.0, "u_max_speed": 30.0, "u_max_heading": 0.25, "synthesis": "power-mean",
      "weights": [0.5, 0.25, 0.25], "q": 3.0, "gate": 600.0, "track_timeout": 20.0, "weighting": "system",
      "min_degree": 0.125, "smoother": {"gains": "fixed", "alpha": 0.75, "beta": 0.5, "process_noise": 3.0,
      "measurement_noise": 50.0}})");
  const FuzzyPipelineOptions f = fuzzy_pipeline_options(FusionMethod::kFuzzy, fz);
  EXPECT_EQ(f.packet_period, 2.0);
  EXPECT_EQ(f.packet_source, PacketSource::kPlot);
  EXPECT_EQ(f.fuzzy.scales.position, 300.0);
  EXPECT_EQ(f.fuzzy.scales.speed, 30.0);
  EXPECT_EQ(f.fuzzy.scales.heading, 0.25);
  EXPECT_EQ(f.fuzzy.synthesis.function, SynthesisFunction::kPowerMean);
  EXPECT_EQ(f.fuzzy.synthesis.weights, (std::vector<double>{0.5, 0.25, 0.25}));
  EXPECT_EQ(f.fuzzy.synthesis.q, 3.0);
  EXPECT_EQ(f.fuzzy.gate, 600.0);
  EXPECT_EQ(f.fuzzy.track_timeout, 20.0);
  EXPECT_EQ(f.fuzzy.weighting, ReliabilityWeighting::kSystemTrack);
  EXPECT_EQ(f.fuzzy.min_degree, 0.125);
  EXPECT_EQ(f.fuzzy.smoother.gains, AlphaBetaGainMode::kFixed);
  EXPECT_EQ(f.fuzzy.smoother.alpha, 0.75);
  EXPECT_EQ(f.fuzzy.smoother.beta, 0.5);
  EXPECT_EQ(f.fuzzy.smoother.process_noise, 3.0);
  EXPECT_EQ(f.fuzzy.smoother.measurement_noise, 50.0);
  EXPECT_EQ(f.to_json(), fz);

  const json ft = json::parse(R"({"method": "ftaa", "packet_period": 0.0, "packets": "track",
      "u_max_position": 500.0, "u_max_speed": 50.0, "u_max_heading": 0.5, "synthesis": "weighted-mean",
      "weights": [0.5, 0.5, 0.0], "q": 2.0, "gate": 900.0, "track_timeout": 5.0, "threshold": 0.625,
      "association_quality": 4, "separation_quality": 3})");
  const FuzzyPipelineOptions a = fuzzy_pipeline_options(FusionMethod::kFtaa, ft);
  EXPECT_EQ(a.ftaa.scales.position, 500.0);
  EXPECT_EQ(a.ftaa.gate, 900.0);
  EXPECT_EQ(a.ftaa.track_timeout, 5.0);
  EXPECT_EQ(a.ftaa.threshold, 0.625);
  EXPECT_EQ(a.ftaa.association_quality, 4);
  EXPECT_EQ(a.ftaa.separation_quality, 3);
  EXPECT_EQ(a.to_json(), ft);
  EXPECT_EQ(fuzzy_pipeline_option_fields(FusionMethod::kFtaa).fields().size(), ft.size());
  EXPECT_EQ(fuzzy_pipeline_option_fields(FusionMethod::kFuzzy).fields().size(), fz.size());

  EXPECT_EQ(error_of([] {
              fuzzy_pipeline_options(FusionMethod::kFuzzy, json{{"method", "ftaa"}});
            }),
            "solver 'fuzzy' options: 'method' must be \"fuzzy\", the solver's own name");
  EXPECT_EQ(error_of([] {
              fuzzy_pipeline_options(FusionMethod::kFuzzy, json{{"smoother", 3}});
            }),
            "solver 'fuzzy' options: 'smoother' must be a JSON object");
  EXPECT_EQ(
      error_of([] {
        fuzzy_pipeline_options(FusionMethod::kFuzzy, json{{"smoother", {{"alpah", 1}}}});
      }),
      "solver 'fuzzy' options: unknown key 'smoother.alpah' (did you mean 'smoother.alpha'?); known keys: "
      "smoother.gains, smoother.alpha, smoother.beta, smoother.process_noise, smoother.measurement_noise");
  EXPECT_EQ(error_of([] {
              fuzzy_pipeline_options(FusionMethod::kFuzzy, json{{"smoother", {{"alpha", "1"}}}});
            }),
            "solver 'fuzzy' options: 'smoother.alpha' must be a number");
  EXPECT_EQ(error_of([] {
              fuzzy_pipeline_options(FusionMethod::kFtaa, json{{"weights", {0.5, "a"}}});
            }),
            "solver 'ftaa' options: 'weights[1]' must be a number");
}

}  // namespace
}  // namespace trackassoc
