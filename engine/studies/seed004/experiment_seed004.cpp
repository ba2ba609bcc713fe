#include "engine/studies/seed004/experiment_seed004.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "engine/distributed/sharding.hpp"
#include "engine/pipeline/metrics.hpp"
#include "engine/pipeline/pipeline_sd.hpp"
#include "engine/report/text_table.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "engine/solvers/chnn_pseudo_solver.hpp"
#include "engine/studies/experiments.hpp"
#include "engine/studies/seed000/experiment_schedules.hpp"
#include "io/atomic_file.hpp"
#include "io/hdf5_wrapper.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"

namespace trackassoc {

void Seed004ExperimentOptions::validate() const {
  require(!scenarios.empty(), "seed004.scenarios", "needs at least one scenario");
  require(runs >= 1, "seed004.runs", "must be >= 1, got " + std::to_string(runs));
  require(p_miss >= 0.0 && p_miss < 1.0, "seed004.p_miss", "must be in [0, 1)");
  require(exact_time_limit_s > 0.0, "seed004.exact_time_limit_s", "must be > 0");
  const std::set<std::string> known{"chnn-eq12", "chnn-eq12-single", "chnn-eq7", "lr", "lr+ls", "exact"};
  for (const auto& s : solvers)
    require(known.count(s) == 1, "seed004.solvers",
            "unknown solver '" + s + "'; expected chnn-eq12, chnn-eq12-single, chnn-eq7, lr, lr+ls or exact");
}

int32_t drop_sensor_target_tracks(TrackFile& file, double p_miss, uint64_t seed, int32_t run) {
  if (p_miss <= 0.0) return 0;
  std::set<std::pair<int32_t, int32_t>> tracks;  // (sensor, local track)
  for (std::size_t r = 0; r < file.tracks.size(); ++r)
    tracks.insert({file.tracks.sensor[r], file.tracks.track[r]});
  std::set<std::pair<int32_t, int32_t>> drop;
  CounterRng rng(seed, static_cast<uint64_t>(run), 0x5EED0040);
  for (const auto& t : tracks)  // ordered, so the draw is deterministic
    if (rng.uniform() < p_miss) drop.insert(t);
  TrackTable kept(file.tracks.layout);
  const TrackTable& in = file.tracks;
  for (std::size_t r = 0; r < in.size(); ++r) {
    if (drop.count({in.sensor[r], in.track[r]})) continue;
    kept.push_back(in.sensor[r], in.track[r], in.t[r], in.state_at(r), in.cov_at(r), in.truth[r]);
  }
  file.tracks = std::move(kept);
  return static_cast<int32_t>(drop.size());
}

namespace {

// One Monte Carlo run of one scenario: every solver on one simulated file. The paper's setting:
// chain form, the χ²(n·D) gate at 0.99, forward alignment.
std::vector<Seed004Row> seed004_run(const Seed004ExperimentOptions& o, const std::string& name,
                                    const Scenario& scenario, int32_t run) {
  const PipelineOptions pipeline = PipelineOptions::paper();
  std::vector<Seed004Row> rows;
  TrackFile file = simulation_to_track_file(scenario, simulate(scenario, o.seed, run));
  drop_sensor_target_tracks(file, o.p_miss, o.seed, run);
  const SDProblem problem = build_sd_problem(file, pipeline);
  const std::set<int32_t> targets(file.tracks.truth.begin(), file.tracks.truth.end());
  for (const auto& solver : o.solvers) {
    Seed004Row row;
    row.scenario = name;
    row.run = run;
    row.solver = solver;
    row.targets = static_cast<int32_t>(targets.size());
    SolutionSD sol;
    if (solver.rfind("chnn", 0) == 0) {
      ChnnPseudoResult raw;
      nlohmann::json opts{{"gated", solver != "chnn-eq7"}};
      if (solver == "chnn-eq12-single") opts["leftover_passes"] = 0;
      sol = solve_chnn_sd(sd_problem_view(problem), opts, o.seed + run, &raw);
      row.steps = raw.steps;
      row.neurons = raw.neurons;
      row.converged = raw.converged;
    } else {
      const nlohmann::json opts = solver == "exact" ? nlohmann::json{{"time_limit_s", o.exact_time_limit_s}}
                                                    : nlohmann::json::object();
      sol = solve_sd(problem, solver, opts, o.seed + run);
      row.converged = sol.summary.termination == Termination::kOptimal;
    }
    // Score through the same record and metrics as `associate --sd` + `evaluate`.
    AssociationRecord rec;
    append_tuples(problem, sol, rec);
    row.correct_rate = evaluate_association(file.tracks, file.sensors, rec).correct_rate;
    row.objective = sol.summary.objective;
    row.lower_bound = sol.summary.lower_bound;
    row.wall_s = sol.summary.wall_time_s;
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

// A row as it travels between ranks (engine/distributed/codec.hpp).
constexpr auto wire_codec(std::type_identity<Seed004Row>) {
  return distributed::codec<Seed004Row>("seed004 row", &Seed004Row::scenario, &Seed004Row::targets,
                                        &Seed004Row::run, &Seed004Row::solver, &Seed004Row::correct_rate,
                                        &Seed004Row::objective, &Seed004Row::lower_bound, &Seed004Row::wall_s,
                                        &Seed004Row::steps, &Seed004Row::neurons, &Seed004Row::converged);
}

// The runs of every scenario, in the order of one process, sharded over the process's ranks
// (docs/design.md §8; engine/distributed/sharding.hpp): a run draws from (seed, run) only.
std::vector<Seed004Row> run_seed004_experiment(const Seed004ExperimentOptions& o, std::ostream* progress) {
  o.validate();
  std::vector<Scenario> scenarios;
  for (const auto& name : o.scenarios) scenarios.push_back(load_scenario(name));  // all errors first
  auto& comm = distributed::world();
  const int64_t items = static_cast<int64_t>(scenarios.size()) * o.runs;
  int64_t done = 0;
  auto rows = distributed::sharded_items<Seed004Row>(
      comm, items,
      [&](int64_t i) {
        const auto s = static_cast<std::size_t>(i / o.runs);
        const auto run = static_cast<int32_t>(i % o.runs);
        auto r = seed004_run(o, o.scenarios[s], scenarios[s], run);
        if (progress) *progress << "\rseed004: run " << ++done << "/" << items << std::flush;
        return r;
      },
      [&](int64_t i) {
        return "seed004 run " + std::to_string(i % o.runs) + " of scenario " + o.scenarios[i / o.runs];
      });
  if (progress) *progress << "\n";
  return rows;
}

namespace {

struct Mean {
  double rate = 0, wall = 0, steps = 0, neurons = 0;
  int n = 0, converged = 0, targets = 0;
};

std::map<std::pair<std::string, std::string>, Mean> means(const std::vector<Seed004Row>& rows) {
  std::map<std::pair<std::string, std::string>, Mean> m;
  for (const auto& r : rows) {
    Mean& x = m[{r.scenario, r.solver}];
    x.rate += r.correct_rate;
    x.wall += r.wall_s;
    x.steps += static_cast<double>(r.steps);
    x.neurons += static_cast<double>(r.neurons);
    x.converged += r.converged;
    x.targets = std::max(x.targets, r.targets);
    ++x.n;
  }
  for (auto& [k, x] : m) {
    x.rate /= x.n;
    x.wall /= x.n;
    x.steps /= x.n;
    x.neurons /= x.n;
  }
  return m;
}

}  // namespace

std::string seed004_summary_table(const std::vector<Seed004Row>& rows, const Seed004ExperimentOptions& o) {
  const auto m = means(rows);
  report::TextTable table({"scenario", "targets", "solver", "correct", "time [ms]", "Euler steps", "neurons",
                           "converged/proven", "paper"});
  for (const auto& sc : o.scenarios)
    for (const auto& solver : o.solvers) {
      auto it = m.find({sc, solver});
      if (it == m.end()) continue;
      const Mean& x = it->second;
      const bool chnn = solver.rfind("chnn", 0) == 0;
      table.add({sc, std::to_string(x.targets), solver, report::fmt(100 * x.rate, "%.1f") + " %",
                 report::fmt(1e3 * x.wall, "%.2f"), chnn ? report::fmt(x.steps, "%.0f") : "-",
                 chnn ? report::fmt(x.neurons, "%.0f") : "-",
                 std::to_string(x.converged) + "/" + std::to_string(x.n),
                 solver.rfind("chnn-eq12", 0) == 0 && sc == "seed004_25" ? "~90 %" : "-"});
    }
  std::ostringstream os;
  os << "seed 004 study: " << o.runs << " runs per scenario, p_miss " << o.p_miss << " (means over runs)\n";
  table.print(os);
  os << "Paper (Bai, Gao 2014, Fig. 3): nearly 90 % correct association in the dense case; Table 1 (lost in "
        "the "
        "text): Eq. 12's gating makes the network converge faster.\n";
  return os.str();
}

void write_seed004_outputs(const std::vector<Seed004Row>& rows, const Seed004ExperimentOptions& o) {
  std::vector<int32_t> scenario, targets, run, solver, converged, steps, neurons;
  std::vector<double> rate, objective, bound, wall;
  for (const auto& r : rows) {
    scenario.push_back(static_cast<int32_t>(std::find(o.scenarios.begin(), o.scenarios.end(), r.scenario) -
                                            o.scenarios.begin()));
    targets.push_back(r.targets);
    run.push_back(r.run);
    solver.push_back(
        static_cast<int32_t>(std::find(o.solvers.begin(), o.solvers.end(), r.solver) - o.solvers.begin()));
    converged.push_back(r.converged);
    rate.push_back(r.correct_rate);
    objective.push_back(r.objective);
    bound.push_back(r.lower_bound);
    wall.push_back(r.wall_s);
    steps.push_back(static_cast<int32_t>(r.steps));
    neurons.push_back(static_cast<int32_t>(r.neurons));
  }
  write_atomically(o.output, [&](const std::string& tmp) {
    h5::File f = h5::File::create(tmp);
    const h5::Group root = f.root();
    write_experiment_header(root, "seed004");
    root.write_attribute("seed", o.seed);
    root.write_attribute("p_miss", o.p_miss);
    const h5::Group g = root.create_group("seed004");
    g.write_attribute("scenarios", nlohmann::json(o.scenarios).dump());
    g.write_attribute("solvers", nlohmann::json(o.solvers).dump());
    g.write_attribute("paper",
                      std::string("nearly 90 % correct association in the dense 25-target case (Fig. 3); "
                                  "Eq. 12 gating speeds convergence (Table 1)"));
    const hsize_t K = rows.size();
    g.write_dataset("scenario", scenario, {K});
    g.write_dataset("targets", targets, {K});
    g.write_dataset("run", run, {K});
    g.write_dataset("solver", solver, {K});
    g.write_dataset("converged", converged, {K});
    g.write_dataset("correct_rate", rate, {K});
    g.write_dataset("objective", objective, {K});
    g.write_dataset("lower_bound", bound, {K});
    g.write_dataset("wall_time_s", wall, {K});
    g.write_dataset("euler_steps", steps, {K});
    g.write_dataset("neurons", neurons, {K});
    f.close();
  });
  if (o.plot.empty()) return;
  // Correct rate vs mean solve time (log x): one point per (solver, scenario).
  const auto m = means(rows);
  std::vector<SvgSeries> series;
  for (const auto& solver : o.solvers) {
    SvgSeries s;
    s.label = solver;
    for (const auto& sc : o.scenarios) {
      auto it = m.find({sc, solver});
      if (it == m.end()) continue;
      s.x.push_back(std::max(1e-3, 1e3 * it->second.wall));
      s.y.push_back(100 * it->second.rate);
    }
    series.push_back(std::move(s));
  }
  const std::string svg =
      svg_scatter("seed 004: correct association vs solve time (4 sensors; 5 and 25 targets)",
                  "mean solve time [ms]", "correct association [%]", series, true);
  write_atomically(o.plot, [&](const std::string& tmp) {
    std::ofstream out(tmp);
    out << svg;
    if (!out) throw InputError(o.plot + ": cannot write");
  });
}

}  // namespace trackassoc
