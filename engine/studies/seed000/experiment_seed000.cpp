#include "engine/studies/seed000/experiment_seed000.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/distributed/sharding.hpp"
#include "engine/pipeline/associator.hpp"
#include "engine/pipeline/metrics.hpp"
#include "engine/pipeline/pipeline.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "engine/studies/experiments.hpp"
#include "engine/studies/seed000/experiment_schedules.hpp"
#include "io/atomic_file.hpp"
#include "io/hdf5_wrapper.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {

void Seed000ExperimentOptions::validate() const {
  require(runs >= 1 && runs <= 100000, "--runs", "expected 1..100000");
  require(std::isfinite(process_noise) && process_noise > 0 && process_noise <= 100, "--process-noise",
          "expected σ_a in (0, 100] m/s²");
  require(!targets.empty(), "--targets", "expected at least one target count");
  for (int32_t t : targets) require(t >= 1 && t <= 200, "--targets", "expected 1..200");
  require(!forms.empty(), "--forms", "expected chain and/or all-pairs");
  for (const auto& f : forms)
    require(f == "chain" || f == "all-pairs", "--forms", "expected chain or all-pairs, found '" + f + "'");
  for (const auto& s : solvers)
    require(s == "hopfield-paper" || s == "hopfield" || s == "chnn" || s == "lr" || s == "exact", "--solvers",
            "expected hopfield-paper, hopfield, chnn, lr or exact, found '" + s + "'");
  require(!output.empty(), "--output", "expected a file name");
}

Scenario seed000_scenario(const Seed000ExperimentOptions& o, int32_t targets, bool correlated) {
  Scenario sc = load_scenario("seed000");
  sc.random_targets.count = targets;
  // Independent errors: constant-velocity targets, so no process noise is common to the filters.
  sc.random_targets.process_noise = correlated ? o.process_noise : 0.0;
  return sc;
}

PipelineOptions seed000_pipeline(const Seed000ExperimentOptions& o, bool correlated,
                                 const std::string& form) {
  PipelineOptions po = PipelineOptions::paper();  // the paper's gate and alignment
  po.cost.form = form == "all-pairs" ? CostForm::kAllPairs : CostForm::kChain;
  if (correlated) po.statistic.common_process_noise = o.process_noise;  // Bar-Shalom–Campo
  return po;
}

namespace {

// The paper's figures (seed 000 §4, Figs. 1–2 and text): Hopfield correct association rate; the
// relaxation algorithm about 6 points lower.
double paper_rate(int32_t targets, bool correlated) {
  if (targets == 10) return correlated ? 0.85 : 0.89;
  if (targets == 20) return correlated ? 0.76 : 0.80;
  return std::nan("");
}

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

}  // namespace

namespace {

// One Monte Carlo run of one configuration: every form and solver on one simulated file.
std::vector<Seed000Row> seed000_run(const Seed000ExperimentOptions& o, const Scenario& sc, int32_t targets,
                                    bool correlated, int32_t run) {
  std::vector<Seed000Row> rows;
  const SimulationResult sim = simulate(sc, o.seed, run);
  const TrackFile file = simulation_to_track_file(sc, sim);
  // The statistics do not depend on the cost form: computed once, the tensor per form, and every
  // solver through the association interface on that one problem (as `run`'s 3-D rows).
  const auto p = std::make_shared<AssociationProblem>(
      build_association_problem(file, seed000_pipeline(o, correlated, o.forms.front())));
  AssociatorOptions request;
  request.three_d = true;
  request.seed = o.seed + static_cast<uint64_t>(run);
  for (const auto& form : o.forms) {
    request.pipeline = seed000_pipeline(o, correlated, form);
    if (form != o.forms.front()) set_cost_tensor(*p, request.pipeline.cost);
    for (const auto& name : o.solvers) {
      request.solver = name;
      const AssociationRecord rec =
          make_three_sensor_associator(request, {p, nullptr})->associate(file).record;
      const AssociationMetrics m = evaluate_association(file.tracks, file.sensors, rec);
      Seed000Row row;
      row.targets = targets;
      row.correlated = correlated;
      row.form = form;
      row.run = run;
      row.solver = name;
      row.wall_s = rec.runtime_s;  // the solve alone (decoding and scoring excluded)
      row.objective = rec.objective;
      row.correct_rate = m.correct_rate;
      row.false_rate = m.false_rate;
      rows.push_back(row);
    }
  }
  return rows;
}

}  // namespace

// A row as it travels between ranks (engine/distributed/codec.hpp).
constexpr auto wire_codec(std::type_identity<Seed000Row>) {
  return distributed::codec<Seed000Row>("seed000 row", &Seed000Row::targets, &Seed000Row::correlated,
                                        &Seed000Row::form, &Seed000Row::run, &Seed000Row::solver,
                                        &Seed000Row::correct_rate, &Seed000Row::false_rate,
                                        &Seed000Row::objective, &Seed000Row::wall_s);
}

std::vector<Seed000Row> run_seed000_experiment(const Seed000ExperimentOptions& o, std::ostream* progress) {
  return run_seed000_experiment(o, progress, distributed::world());
}

// The runs of every configuration, flattened in the order one process visits them (target count,
// then independent before correlated, then run), are sharded over the ranks (docs/design.md §8): a run
// draws from (seed, run) only, so the rows do not depend on the ranks.
std::vector<Seed000Row> run_seed000_experiment(const Seed000ExperimentOptions& o, std::ostream* progress,
                                               distributed::Communicator& comm) {
  o.validate();
  struct Config {
    int32_t targets;
    bool correlated;
    Scenario scenario;
  };
  std::vector<Config> configs;
  for (int32_t targets : o.targets)
    for (bool correlated : {false, true}) {
      configs.push_back({targets, correlated, seed000_scenario(o, targets, correlated)});
      if (progress)
        *progress << targets << " targets, " << (correlated ? "correlated" : "independent")
                  << " errors: " << o.runs << " runs\n";
    }
  const int64_t items = static_cast<int64_t>(configs.size()) * o.runs;
  return distributed::sharded_items<Seed000Row>(
      comm, items,
      [&](int64_t i) {
        const Config& c = configs[i / o.runs];
        return seed000_run(o, c.scenario, c.targets, c.correlated, static_cast<int32_t>(i % o.runs));
      },
      [&](int64_t i) {
        const Config& c = configs[i / o.runs];
        return "seed000 run " + std::to_string(i % o.runs) + " of " + std::to_string(c.targets) +
               " targets, " + (c.correlated ? "correlated" : "independent") + " errors";
      });
}

std::string seed000_summary_table(const std::vector<Seed000Row>& rows, const Seed000ExperimentOptions& o) {
  std::ostringstream os;
  char line[256];
  std::snprintf(line, sizeof line, "%-8s %-12s %-10s %-15s %9s %8s %11s %14s %10s\n", "targets", "errors",
                "cost", "solver", "correct", "(paper)", "vs lr [pt]", "<=1 % of exact", "time [ms]");
  os << line << std::string(103, '-') << "\n";
  using Key = std::tuple<int32_t, bool, std::string, int32_t>;
  std::map<Key, double> exact;  // objective of the exact solver per (targets, errors, form, run)
  for (const auto& r : rows)
    if (r.solver == "exact") exact[{r.targets, r.correlated, r.form, r.run}] = r.objective;
  // mean rate per (targets, errors, form, solver), for the notes below
  std::map<std::tuple<int32_t, bool, std::string, std::string>, double> mean;
  int lr_optimal = 0, lr_runs = 0;
  for (int32_t targets : o.targets)
    for (bool correlated : {false, true})
      for (const auto& form : o.forms) {
        std::map<std::string, double> rate_sum, time_sum;
        std::map<std::string, int> count, within;
        for (const auto& r : rows) {
          if (r.targets != targets || r.correlated != correlated || r.form != form) continue;
          rate_sum[r.solver] += r.correct_rate;
          time_sum[r.solver] += r.wall_s;
          ++count[r.solver];
          const auto ex = exact.find({r.targets, r.correlated, r.form, r.run});
          if (ex == exact.end()) continue;
          const bool ok = r.objective <= ex->second + 0.01 * std::abs(ex->second) + 1e-9;
          within[r.solver] += ok;
          if (r.solver == "lr") {
            ++lr_runs;
            lr_optimal += r.objective <= ex->second + 1e-6 * (1.0 + std::abs(ex->second));
          }
        }
        const double lr_rate = count.count("lr") ? rate_sum["lr"] / count["lr"] : std::nan("");
        for (const auto& name : o.solvers) {
          if (!count.count(name)) continue;
          const double rate = rate_sum[name] / count[name];
          mean[{targets, correlated, form, name}] = rate;
          const bool hop = name.rfind("hopfield", 0) == 0 || name == "chnn";
          // The paper's Hopfield figure, and its relaxation ≈ 6 points below, on the chain form.
          const double paper = form != "chain"            ? std::nan("")
                               : name == "hopfield-paper" ? paper_rate(targets, correlated)
                               : name == "lr"             ? paper_rate(targets, correlated) - 0.06
                                                          : std::nan("");
          const std::string opt =
              exact.empty() ? "" : std::to_string(within[name]) + "/" + std::to_string(count[name]);
          const std::string vs =
              hop && !std::isnan(lr_rate) ? fmt("%+.1f (~+6)", 100 * (rate - lr_rate)) : "";
          std::snprintf(line, sizeof line, "%-8d %-12s %-10s %-15s %8.1f%% %8s %11s %14s %10.2f\n", targets,
                        correlated ? "correlated" : "independent", form.c_str(), name.c_str(), 100 * rate,
                        std::isnan(paper) ? "" : fmt("%.0f%%", 100 * paper).c_str(), vs.c_str(), opt.c_str(),
                        1e3 * time_sum[name] / count[name]);
          os << line;
        }
      }
  os << "\npaper (seed 000 §4): Hopfield correct association ≈ 89 % (10 targets, independent), 85 % "
        "(correlated), 80 % / 76 % (20 targets); Hopfield ≈ 6 points above the relaxation algorithm.\n"
        "Scoring: the decoded tuples of `associate`, scored by `evaluate` (a target is correct when one "
        "tuple holds exactly its three tracks).\n"
        "Why ours differs from the paper:\n";
  if (lr_runs > 0)
    os << "  - Hopfield above relaxation: not reproduced. Our lr reaches the exact optimum in " << lr_optimal
       << " of " << lr_runs
       << " runs, so no solver can beat it on the objective; a 3-D solver differs from lr only where it "
          "misses the optimum.\n";
  os << "  - Chain cost (Eq. 3): b_ijk = λ_ij + λ_jk separates into two 2-D assignments (docs/design.md "
        "§4.3), so "
        "the optimum is two LAPs;\n    the all-pairs form adds λ_ik and is where the 3-D solvers differ.\n";
  for (int32_t targets : o.targets) {
    const auto i = mean.find({targets, false, o.forms.front(), o.solvers.front()});
    const auto c = mean.find({targets, true, o.forms.front(), o.solvers.front()});
    if (i == mean.end() || c == mean.end()) continue;
    os << "  - Correlated vs independent, " << targets << " targets (" << o.solvers.front() << ", "
       << o.forms.front() << "): " << fmt("%+.1f", 100 * (c->second - i->second))
       << " points (paper −4). The correlated case is made by common process noise σ_a = " << o.process_noise
       << " m/s² and\n    associated with the Bar-Shalom–Campo cross-covariance; the independent case has "
          "constant-velocity targets.\n";
  }
  os << "  - Why the correlated case loses more than the paper's 4 points: the Bar-Shalom–Campo statistic is "
        "calibrated (true pairs' λ\n    averages 0.98·n·D, against 0.79·n·D when the correlation is "
        "ignored), "
        "so the χ²(n·D) gate of the summed statistic,\n    which treats the scan terms of filtered tracks as "
        "independent, now rejects the true pairs it used to keep by luck\n    (README, seed 000 row; "
        "`associate --gate-method calibrated` keeps 94-99 %).\n"
        "  - All-pairs below chain: a tuple is kept whole only when all three of its pairs are in that gate, "
        "against two for the chain.\n";
  os << "  - Absolute rates: the paper leaves the target area, the motion model, the filter start and the "
        "ambiguity handling to its ref. [8];\n    ours are in the `seed000` scenario's description (50 km "
        "square, 100-400 m/s, 30 scans of 2 s).\n";
  return os.str();
}

void write_seed000_outputs(const std::vector<Seed000Row>& rows, const Seed000ExperimentOptions& o) {
  std::vector<int32_t> targets, correlated, form, run, solver;
  std::vector<double> rate, false_rate, objective, wall;
  for (const auto& r : rows) {
    targets.push_back(r.targets);
    correlated.push_back(r.correlated);
    form.push_back(static_cast<int32_t>(std::find(o.forms.begin(), o.forms.end(), r.form) - o.forms.begin()));
    run.push_back(r.run);
    solver.push_back(
        static_cast<int32_t>(std::find(o.solvers.begin(), o.solvers.end(), r.solver) - o.solvers.begin()));
    rate.push_back(r.correct_rate);
    false_rate.push_back(r.false_rate);
    objective.push_back(r.objective);
    wall.push_back(r.wall_s);
  }
  write_atomically(o.output, [&](const std::string& tmp) {
    h5::File f = h5::File::create(tmp);
    const h5::Group root = f.root();
    write_experiment_header(root, "seed000");
    root.write_attribute("seed", o.seed);
    root.write_attribute("process_noise", o.process_noise);
    const h5::Group g = root.create_group("seed000");
    g.write_attribute("solvers", nlohmann::json(o.solvers).dump());
    g.write_attribute("forms", nlohmann::json(o.forms).dump());
    g.write_attribute(
        "paper", std::string("Hopfield correct association ~89/85 % (10 targets, independent/correlated), "
                             "80/76 % (20 targets); ~6 points above relaxation"));
    const hsize_t K = rows.size();
    g.write_dataset("targets", targets, {K});
    g.write_dataset("correlated", correlated, {K});
    g.write_dataset("form", form, {K});
    g.write_dataset("run", run, {K});
    g.write_dataset("solver", solver, {K});
    g.write_dataset("correct_rate", rate, {K});
    g.write_dataset("false_rate", false_rate, {K});
    g.write_dataset("objective", objective, {K});
    g.write_dataset("wall_time_s", wall, {K});
    f.close();
  });
  if (o.plot.empty()) return;
  // x: configuration (1 = first target count independent, 2 = correlated, 3 = next count ...).
  std::vector<SvgSeries> series;
  for (const auto& form : o.forms)
    for (const auto& name : o.solvers) {
      SvgSeries s;
      s.label = name + " (" + form + ")";
      double x = 1;
      for (int32_t t : o.targets)
        for (bool c : {false, true}) {
          double sum = 0;
          int n = 0;
          for (const auto& r : rows)
            if (r.solver == name && r.form == form && r.targets == t && r.correlated == c) {
              sum += r.correct_rate;
              ++n;
            }
          if (n) {
            s.x.push_back(x);
            s.y.push_back(100 * sum / n);
          }
          x += 1;
        }
      series.push_back(std::move(s));
    }
  SvgSeries paper;
  paper.label = "paper (Hopfield)";
  double x = 1;
  for (int32_t t : o.targets)
    for (bool c : {false, true}) {
      const double pr = paper_rate(t, c);
      if (!std::isnan(pr)) {
        paper.x.push_back(x);
        paper.y.push_back(100 * pr);
      }
      x += 1;
    }
  series.push_back(paper);
  std::string xlabel = "configuration:";
  int idx = 1;
  for (int32_t t : o.targets)
    for (bool c : {false, true})
      xlabel += " " + std::to_string(idx++) + "=" + std::to_string(t) + (c ? "c" : "i");
  const std::string svg =
      svg_scatter("seed 000 Monte Carlo: correct association rate",
                  xlabel + " (i/c = independent/correlated)", "correct association [%]", series, false);
  write_atomically(o.plot, [&](const std::string& tmp) {
    std::ofstream out(tmp);
    out << svg;
    if (!out) throw InputError(o.plot + ": cannot write");
  });
}

}  // namespace trackassoc
