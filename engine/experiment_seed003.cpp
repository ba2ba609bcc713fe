// The seed 003 density experiment (see experiment_seed003.hpp).
#include "engine/experiment_seed003.hpp"

#include <chrono>
#include <cmath>
#include <numbers>

#include "engine/metrics.hpp"
#include "engine/siamese_pipeline.hpp"
#include "kernels/error.hpp"

namespace trackassoc {

void Seed003ExperimentOptions::validate() const {
  require(!densities.empty(), "Seed003ExperimentOptions.densities", "must not be empty");
  for (int d : densities)
    require(d >= 1 && d <= 100000, "Seed003ExperimentOptions.densities", "each must be in [1, 1e5]");
  require(runs >= 1, "Seed003ExperimentOptions.runs", "must be >= 1");
  require(probability_threshold > 0 && probability_threshold < 1,
          "Seed003ExperimentOptions.probability_threshold", "must be in (0, 1)");
  scenario.validate();
}

ClassicalBaselineOptions baseline_options_for(const Seed003Options& s) {
  ClassicalBaselineOptions b;
  const double sb = s.sigma_bearing_deg * std::numbers::pi / 180.0;
  b.radar1 = {s.radar1_x, s.radar1_y, s.sigma_range, sb};
  b.radar2 = {s.radar2_x, s.radar2_y, s.sigma_range, sb};
  return b;
}

namespace {

// The correct association rate through `evaluate`'s function (engine/metrics.hpp): the scene as
// /tracks rows (one per local track; evaluate_association reads only sensor, track and truth) and
// left_to_right as /associations tuples, pairs and singles, as `associate --solver siamese` writes.
double evaluated_rate(const std::vector<int32_t>& l2r, const Seed003Scene& sc) {
  TrackTable tracks;
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(tracks.dim());
  const Eigen::MatrixXd P = Eigen::MatrixXd::Identity(tracks.dim(), tracks.dim());
  for (int s = 0; s < 2; ++s) {
    const std::vector<int32_t>& target = s == 0 ? sc.target1 : sc.target2;
    for (std::size_t k = 0; k < target.size(); ++k)
      tracks.push_back(s, static_cast<int32_t>(k), 0.0, x, P, target[k]);
  }
  std::vector<Sensor> sensors(2);
  sensors[0].id = 0;
  sensors[1].id = 1;
  AssociationRecord rec;
  rec.num_sensors = 2;
  std::vector<char> used(sc.target2.size(), 0);
  for (std::size_t i = 0; i < l2r.size(); ++i) {
    rec.tuples.insert(rec.tuples.end(), {static_cast<int32_t>(i), l2r[i]});
    if (l2r[i] >= 0) used[l2r[i]] = 1;
  }
  for (std::size_t j = 0; j < used.size(); ++j)
    if (!used[j]) rec.tuples.insert(rec.tuples.end(), {-1, static_cast<int32_t>(j)});
  rec.cost.assign(rec.tuples.size() / 2, 0.0);
  return evaluate_association(tracks, sensors, rec).correct_rate;
}

void score(const std::vector<int32_t>& l2r, const Seed003Scene& sc, double& acc, double& recall,
           double& precision) {
  acc = evaluated_rate(l2r, sc);
  int64_t tp = 0, fp = 0;
  for (std::size_t i = 0; i < l2r.size(); ++i)
    if (l2r[i] >= 0) (sc.target2[l2r[i]] == sc.target1[i] ? tp : fp)++;
  const int64_t positives = static_cast<int64_t>(l2r.size());  // every target is seen by both radars
  recall = positives ? double(tp) / double(positives) : 1.0;
  precision = tp + fp ? double(tp) / double(tp + fp) : 1.0;
}

}  // namespace

Seed003ExperimentResult run_seed003_experiment(const SiameseModel<float>& model,
                                               const Seed003ExperimentOptions& o,
                                               const std::vector<NamedPairModel>& extra) {
  using clock = std::chrono::steady_clock;
  o.validate();
  const auto start = clock::now();
  Seed003Options scenario = o.scenario;
  scenario.seed = o.seed;
  const ClassicalBaselineOptions base = baseline_options_for(scenario);
  Seed003ExperimentResult r;
  r.densities = o.densities;
  std::vector<std::string> names{"ttcsn", "weighted", "nn"};
  for (const auto& e : extra) names.push_back(e.name);
  for (const auto& n : names) {
    Seed003MethodCurve c;
    c.method = n;
    const std::size_t D = o.densities.size(), R = static_cast<std::size_t>(o.runs);
    c.accuracy.assign(D, std::vector<double>(R));
    c.recall = c.precision = c.seconds = c.accuracy;
    r.methods.push_back(std::move(c));
  }
  SiameseAssociationOptions so;
  so.probability_threshold = o.probability_threshold;
  for (std::size_t d = 0; d < o.densities.size(); ++d)
    for (int run = 0; run < o.runs; ++run) {
      // Scene streams: a distinct run number per (density, run).
      const Seed003Scene sc =
          simulate_seed003_scene(scenario, o.densities[d], static_cast<uint64_t>(d) * 100000 + run);
      for (int m = 0; m < static_cast<int>(names.size()); ++m) {
        const auto t0 = clock::now();
        std::vector<int32_t> l2r;
        if (m == 0)
          l2r = associate_siamese(model, sc.radar1, sc.radar2, so).left_to_right;
        else if (m == 1)
          l2r = associate_weighted_test(sc.radar1, sc.radar2, base);
        else if (m == 2)
          l2r = associate_nearest_neighbour(sc.radar1, sc.radar2, base);
        else
          l2r = associate_siamese(*extra[m - 3].model, sc.radar1, sc.radar2, so).left_to_right;
        Seed003MethodCurve& c = r.methods[m];
        c.seconds[d][run] = std::chrono::duration<double>(clock::now() - t0).count();
        score(l2r, sc, c.accuracy[d][run], c.recall[d][run], c.precision[d][run]);
      }
    }
  r.wall_time_s = std::chrono::duration<double>(clock::now() - start).count();
  return r;
}

}  // namespace trackassoc
