// trackassoc experiment seed003 [--model M.h5] [--data D.h5] --out R.h5: the seed 003 study
// (pair test metrics on the data set's test split; association accuracy and time vs track density).
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <tuple>

#include "engine/cli/common.hpp"
#include "engine/cli/table.hpp"
#include "engine/dataset_seed003.hpp"
#include "engine/experiment_seed003.hpp"
#include "io/atomic_file.hpp"
#include "io/hdf5_wrapper.hpp"
#include "io/siamese_model_file.hpp"
#include "kernels/association_statistic.hpp"
#include "kernels/siamese_training.hpp"

namespace trackassoc::cli {
namespace {

std::string pct(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f", 100.0 * v);
  return b;
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / double(v.size());
}

std::vector<double> flatten(const std::vector<std::vector<double>>& m) {
  std::vector<double> out;
  for (const auto& r : m) out.insert(out.end(), r.begin(), r.end());
  return out;
}

}  // namespace

void register_experiment_seed003(CLI::App& experiment) {
  struct Args {
    CommonOptions common;
    std::string model, data, output, lstm_model, bilstm_model;
    Seed003ExperimentOptions options;
  };
  auto args = std::make_shared<Args>();
  args->common.seed = 3;
  args->model = TRACKASSOC_DATA_DIR "/models/siamese_seed003.h5";
  auto* cmd = experiment.add_subcommand(
      "seed003", "Seed 003 (TTCSN) study: pair test metrics and association vs track density");
  cmd->add_option("--model", args->model, "Siamese model (from train-siamese; default: the shipped one)")
      ->capture_default_str();
  cmd->add_option("--lstm-model", args->lstm_model,
                  "Baseline: LSTM on concatenated pairs (train-siamese --architecture lstm)");
  cmd->add_option("--bilstm-model", args->bilstm_model,
                  "Baseline: BiLSTM on concatenated pairs (train-siamese --architecture bilstm)");
  cmd->add_option("--data", args->data,
                  "Data set: also report pair accuracy/recall/precision on its test split");
  cmd->add_option("--out,-o", args->output, "Result HDF5 file")->required();
  cmd->add_option("--runs", args->options.runs, "Monte Carlo runs per density")
      ->capture_default_str()
      ->check(at_least(1));
  cmd->add_option("--densities", args->options.densities, "Track densities (targets per scene)")
      ->capture_default_str()
      ->check(in_range(1, 1e5));
  cmd->add_option("--threshold", args->options.probability_threshold, "TTCSN pair probability threshold")
      ->capture_default_str()
      ->check(in_range(0, 1, true, true));
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    check_output_paths({{args->output, "--out"}});
    const LoadedSiameseModel loaded = read_siamese_model(args->model);
    require(loaded.model.shape.architecture == PairArchitecture::kSiamese, "--model",
            "must be a Siamese model");
    std::vector<LoadedSiameseModel> baselines;
    std::vector<NamedPairModel> extra;
    for (const auto& [name, path, arch] : {std::tuple<std::string, std::string, PairArchitecture>{
                                               "lstm", args->lstm_model, PairArchitecture::kConcatLstm},
                                           {"bilstm", args->bilstm_model, PairArchitecture::kConcatBiLstm}}) {
      if (path.empty()) continue;
      baselines.push_back(read_siamese_model(path));
      require(baselines.back().model.shape.architecture == arch, "--" + name + "-model",
              path + " is not a model of architecture " + name);
    }
    {
      std::size_t k = 0;
      for (const auto& [name, path] :
           {std::pair<std::string, std::string>{"lstm", args->lstm_model}, {"bilstm", args->bilstm_model}})
        if (!path.empty()) extra.push_back({name, &baselines[k++].model});
    }
    Seed003ExperimentOptions o = args->options;
    // The scenes are flown and observed as the model's training data were (radars, errors,
    // periods), when its training JSON records the generator (train-siamese does).
    const auto training = nlohmann::json::parse(loaded.training_json, nullptr, false);
    if (training.is_object() && training.contains("generator"))
      o.scenario = seed003_scene_of(training["generator"].dump(), o.scenario, args->model);
    o.seed = args->common.seed;
    o.validate();
    nlohmann::json pair_metrics = nlohmann::json::object();
    if (!args->data.empty()) {
      const Seed003Dataset d = read_seed003_dataset(args->data);
      const PairEvaluation s =
          evaluate_pairs(loaded.model, d.radar1, d.radar2, d.test, o.probability_threshold);
      // The weighted test needs the radars that made the data set's plots (its generator JSON).
      const Seed003Options made_by = seed003_scene_of(d.generator_json, o.scenario, args->data);
      const auto lam = weighted_statistic_pairs(d.radar1, d.radar2, d.test, baseline_options_for(made_by));
      const double gate = chi_square_quantile(0.99, 2);
      PairEvaluation w;
      for (std::size_t k = 0; k < lam.size(); ++k) {
        const bool p = lam[k] <= gate, a = d.test.label[k] == 1;
        (p && a ? w.true_positive : p ? w.false_positive : a ? w.false_negative : w.true_negative)++;
      }
      TextTable t(
          {"test pairs (" + std::to_string(d.test.size()) + ")", "accuracy %", "recall %", "precision %"});
      t.add({"TTCSN (ours)", pct(s.accuracy()), pct(s.recall()), pct(s.precision())});
      t.add({"weighted test (ours)", pct(w.accuracy()), pct(w.recall()), pct(w.precision())});
      for (const auto& e : extra) {
        const PairEvaluation b =
            evaluate_pairs(*e.model, d.radar1, d.radar2, d.test, o.probability_threshold);
        t.add({e.name + " concatenated (ours)", pct(b.accuracy()), pct(b.recall()), pct(b.precision())});
        pair_metrics[e.name] = {
            {"accuracy", b.accuracy()}, {"recall", b.recall()}, {"precision", b.precision()}};
      }
      t.add({"TTCSN (seed 003)", "99.1", "> 99", "-"});
      t.print(std::cout);
      std::cout << "\n";
      pair_metrics.update(
          {{"ttcsn", {{"accuracy", s.accuracy()}, {"recall", s.recall()}, {"precision", s.precision()}}},
           {"weighted", {{"accuracy", w.accuracy()}, {"recall", w.recall()}, {"precision", w.precision()}}}});
    }
    char scene[256];
    std::snprintf(
        scene, sizeof scene,
        "scenes: radars at (%.0f, %.0f) and (%.0f, %.0f) km, %.0f m / %.2f deg, periods %.0f / %.0f s "
        "(as the model's training data when its file records them)\n\n",
        o.scenario.radar1_x / 1e3, o.scenario.radar1_y / 1e3, o.scenario.radar2_x / 1e3,
        o.scenario.radar2_y / 1e3, o.scenario.sigma_range, o.scenario.sigma_bearing_deg, o.scenario.period1,
        o.scenario.period2);
    std::cout << scene;
    const Seed003ExperimentResult r = run_seed003_experiment(loaded.model, o, extra);
    for (const char* what : {"accuracy", "recall", "precision", "time"}) {
      std::vector<std::string> head{std::string(what) + (std::string(what) == "time" ? " [ms]" : " [%]")};
      for (int d : r.densities) head.push_back("n=" + std::to_string(d));
      TextTable t(head);
      for (const auto& c : r.methods) {
        std::vector<std::string> row{c.method};
        for (std::size_t d = 0; d < r.densities.size(); ++d) {
          const std::string w(what);
          const double v = w == "accuracy"    ? mean(c.accuracy[d])
                           : w == "recall"    ? mean(c.recall[d])
                           : w == "precision" ? mean(c.precision[d])
                                              : mean(c.seconds[d]) * 1000.0;
          char b[32];
          std::snprintf(b, sizeof b, w == "time" ? "%.2f" : "%.1f", w == "time" ? v : 100.0 * v);
          row.push_back(b);
        }
        t.add(row);
      }
      t.print(std::cout);
      std::cout << "\n";
    }
    std::cout
        << "seed 003 (Figs. 5-8): TTCSN highest accuracy at every density (up to 100 %), recall > 99 %,\n"
           "precision 15-20 points above LSTM/BiLSTM at high density; weighted test ~7 points below TTCSN "
           "at\n"
           "low density and falling; NN close to TTCSN at low density, falling fast; LSTM/BiLSTM\n"
           "robust to density, their time approaching TTCSN's at n = 80.\n";
    write_atomically(args->output, [&](const std::string& tmp) {
      h5::File f = h5::File::create(tmp);
      const h5::Group root = f.root();
      root.write_attribute("format", std::string("trackassoc"));
      root.write_attribute("schema_version", int32_t{1});
      const h5::Group g = root.create_group("experiment").create_group("seed003");
      nlohmann::json jo = {{"runs", o.runs},
                           {"seed", o.seed},
                           {"threshold", o.probability_threshold},
                           {"scenario", nlohmann::json::parse(o.scenario.to_json())},
                           {"model", args->model}};
      g.write_attribute("options", jo.dump());
      g.write_attribute("model_training", loaded.training_json);
      g.write_attribute("pair_test_metrics", pair_metrics.dump());
      g.write_attribute("wall_time_s", r.wall_time_s);
      const std::vector<int32_t> dens(r.densities.begin(), r.densities.end());
      g.write_dataset("densities", std::span<const int32_t>(dens), {dens.size()});
      const hsize_t D = r.densities.size(), R = static_cast<hsize_t>(o.runs);
      for (const auto& c : r.methods) {
        const h5::Group m = g.create_group(c.method);
        m.write_dataset("accuracy", std::span<const double>(flatten(c.accuracy)), {D, R});
        m.write_dataset("recall", std::span<const double>(flatten(c.recall)), {D, R});
        m.write_dataset("precision", std::span<const double>(flatten(c.precision)), {D, R});
        m.write_dataset("seconds", std::span<const double>(flatten(c.seconds)), {D, R});
      }
      f.close();
    });
    std::cout << "results -> " << args->output << " (" << r.wall_time_s << " s)\n";
  });
}

}  // namespace trackassoc::cli
