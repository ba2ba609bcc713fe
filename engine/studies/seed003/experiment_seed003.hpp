// The seed 003 (TTCSN) density experiment (seed 003 §3.2, Figs. 5–8): for track densities 5…80,
// `runs` Monte Carlo scenes each (Seed003Options scenario, scenes disjoint from the training data),
// associate the two radars' tracks with every method and record the correct association rate, the
// decision recall and precision, and the wall time.
//
// Methods: "ttcsn" (Siamese BiLSTM, embed once + thresholded LAP), "weighted" (weighted statistical
// test + gated LAP) and "nn" (nearest neighbour), engine/studies/seed003/seed003_baselines.hpp, plus any
// extra pair models given (the LSTM and BiLSTM on concatenated pairs, trained with train-siamese
// --architecture lstm|bilstm), scored pair by pair and assigned by the same thresholded LAP.
// Decision metrics per scene: TP = assigned pairs of the same target, FP = other assigned pairs,
// FN = same-target pairs left unassigned; recall = TP/(TP+FN), precision = TP/(TP+FP).
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "engine/distributed/communicator.hpp"
#include "engine/studies/seed003/dataset_seed003.hpp"
#include "engine/studies/seed003/seed003_baselines.hpp"

namespace trackassoc {

struct Seed003ExperimentOptions {
  std::vector<int> densities{5, 10, 20, 40, 60, 80};
  int runs = 10;
  uint64_t seed = 3;
  double probability_threshold = 0.5;
  Seed003Options scenario;  // motion and radars; its `seed` is replaced by `seed`
  void validate() const;
};

struct Seed003MethodCurve {
  std::string method;
  // [density][run]
  std::vector<std::vector<double>> accuracy, recall, precision, seconds;
};

struct Seed003ExperimentResult {
  std::vector<int> densities;
  std::vector<Seed003MethodCurve> methods;
  double wall_time_s = 0.0;
};

ClassicalBaselineOptions baseline_options_for(const Seed003Options& scenario);

struct NamedPairModel {
  std::string name;
  const SiameseModel<float>* model;
};

// In this process; the overload with `comm` shards the scenes over its ranks (rank 0 returns the
// result of one process, the others only `densities`).
Seed003ExperimentResult run_seed003_experiment(const SiameseModel<float>& model,
                                               const Seed003ExperimentOptions& options,
                                               const std::vector<NamedPairModel>& extra_models = {});
Seed003ExperimentResult run_seed003_experiment(const SiameseModel<float>& model,
                                               const Seed003ExperimentOptions& options,
                                               const std::vector<NamedPairModel>& extra_models,
                                               distributed::Communicator& comm);

// The files of `trackassoc experiment seed003`: the Siamese model (train-siamese), the optional
// baselines on concatenated pairs (--architecture lstm | bilstm), the optional data set whose test
// split gives the pair metrics, and the result file.
struct Seed003StudyFiles {
  std::string model, lstm_model, bilstm_model, data, output;
};

// The whole study, its scenes sharded over the ranks of distributed::world() (every rank reads the
// models; rank 0 alone prints and writes): reads the models (InputError when a file holds another
// architecture), flies the scenes as the model's training data were when its training JSON records the
// generator, prints the pair test table (when `data` is given: TTCSN, the weighted test gated at χ²₂(0.99)
// and the baselines, each as a confusion count over the test pairs) and one table per metric vs density to
// `out`, and writes `output` atomically:
//   /  attrs format = "trackassoc", schema_version = 1
//   /experiment/seed003/  attrs options (JSON: runs, seed, threshold, scenario, model),
//       model_training (the model's training JSON), pair_test_metrics (JSON), wall_time_s;
//       densities (D int32); <method>/{accuracy, recall, precision, seconds} (D×R float64)
Seed003ExperimentResult run_seed003_study(const Seed003StudyFiles& files, Seed003ExperimentOptions options,
                                          std::ostream& out);

}  // namespace trackassoc
