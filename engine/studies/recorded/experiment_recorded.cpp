// Experiment `recorded`; see engine/studies/recorded/experiment_recorded.hpp.
#include "engine/studies/recorded/experiment_recorded.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/pipeline/associator.hpp"
#include "engine/pipeline/metrics.hpp"
#include "engine/pipeline/pipeline.hpp"
#include "engine/report/text_table.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "engine/studies/experiments.hpp"
#include "engine/studies/seed000/experiment_schedules.hpp"
#include "io/atomic_file.hpp"
#include "io/hdf5_wrapper.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

extern char** environ;

namespace trackassoc {
namespace {

const std::vector<std::string> kMethods{"default",  "unregistered", "exact",
                                        "chi2-sum", "3d-exact",     "3d-nogate"};
// Stone Soup as shipped (only timestamps two tracks share), then the same associators on the tracks
// predicted onto a common grid with its KalmanPredictor (bench/stonesoup_resample.py).
const std::vector<std::string> kPeerMethods{"stonesoup-one2one", "stonesoup-counting",
                                            "stonesoup-one2one-resampled", "stonesoup-counting-resampled"};

RecordedRow score(const std::string& scenario, const std::string& method, int32_t run, const TrackFile& file,
                  const AssociationRecord& rec, double time_s) {
  const AssociationMetrics m = evaluate_association(file.tracks, file.sensors, rec);
  RecordedRow r;
  r.scenario = scenario;
  r.method = method;
  r.run = run;
  r.sensors = static_cast<int32_t>(file.sensors.size());
  r.targets = m.targets;
  r.correct = m.correct;
  r.false_associations = m.false_associations;
  r.missed = m.missed;
  r.linked_tuples = m.linked_tuples;
  r.false_tuples = m.false_tuples;
  r.time_s = time_s;
  return r;
}

// Every method through the association interface (engine/pipeline/associator.hpp).
AssociationRecord associate_method(const TrackFile& file, const std::string& method, uint64_t seed,
                                   double& time_s) {
  const auto t0 = std::chrono::steady_clock::now();
  AssociatorOptions request;  // "default": `associate`'s default request (registration, segments, stitching)
  request.seed = seed;
  if (method == "3d-nogate" || method == "3d-exact") {
    // The three-sensor all-pairs tensor, solved exactly: with the calibrated gate (3d-exact), or
    // with no gate on the summed statistic (3d-nogate, the reference of the dense cases).
    request.three_d = true;
    request.solver = "exact";
    request.solver_options = {{"time_limit_s", 10.0}};
    if (method == "3d-nogate") {
      request.pipeline.statistic.gate = GateMethod::kChiSquareSum;
      request.pipeline.statistic.gate_probability = 1.0;
    }
  } else if (method != "default") {  // the default path as recorded: no registration, no stitching
    request.registration.enabled = false;
    request.stitching.enabled = false;
    if (method == "exact") {
      request.solver = "exact";
      request.solver_options = {{"time_limit_s", 5.0}};
    }
    if (method == "chi2-sum") {  // the gate and alignment of seed 000, before issue 20
      request.pipeline.statistic.gate = GateMethod::kChiSquareSum;
      request.pipeline.alignment.method = AlignmentMethod::kForward;
      request.pipeline.alignment.process_noise = 1.0;
    }
  }
  AssociationRecord rec = make_associator(request)->associate(file).record;
  time_s = seconds_since(t0);
  rec.name = method;
  return rec;
}

// Runs `argv` (no shell), stdout and stderr to `log`; returns the exit status (−1: not started).
int run_program(const std::vector<std::string>& argv, const std::string& log) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, args[0], &fa, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The peer's rows from its --json output (bench/stonesoup_t2t.py).
std::vector<RecordedRow> peer_rows(const std::string& scenario, int32_t run, const TrackFile& file,
                                   const std::string& json_path) {
  std::ifstream in(json_path);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  std::vector<RecordedRow> rows;
  if (j.is_discarded()) return rows;
  for (const auto& name : kPeerMethods) {  // {"stonesoup-one2one": {...}, "stonesoup-counting": {...}, ...}
    const nlohmann::json a = j.is_object() && j.contains(name) ? j.at(name) : nlohmann::json();
    if (!a.is_object() || !a.contains("targets")) continue;
    RecordedRow r;
    r.scenario = scenario;
    r.method = name;
    r.run = run;
    r.sensors = static_cast<int32_t>(file.sensors.size());
    r.targets = a.value("targets", 0);
    r.correct = static_cast<int32_t>(std::lround(a.value("correct_rate", 0.0) * r.targets));
    r.false_associations = static_cast<int32_t>(std::lround(a.value("false_rate", 0.0) * r.targets));
    r.missed = r.targets - r.correct - r.false_associations;
    r.false_tuples = a.value("false_tuples", 0);
    r.linked_tuples = a.value("linked_tuples", 0);
    r.time_s = a.value("assoc_time_s", 0.0);
    rows.push_back(r);
  }
  return rows;
}

std::string pct(int32_t k, int32_t n) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", n > 0 ? 100.0 * k / n : 0.0);
  return buf;
}

}  // namespace

void RecordedExperimentOptions::validate() const {
  require(!scenarios.empty(), "experiment recorded: --scenarios", "expected at least one scenario");
  require(runs >= 1 && runs <= 10000, "experiment recorded: --runs", "expected 1..10000");
  require(!methods.empty(), "experiment recorded: --methods", "expected at least one method");
  for (const auto& m : methods)
    if (std::find(kMethods.begin(), kMethods.end(), m) == kMethods.end())
      throw InputError("experiment recorded: --methods: unknown method '" + m +
                       "' (default, unregistered, exact, chi2-sum, 3d-exact, 3d-nogate)");
  require(!files_dir.empty(), "experiment recorded: --files", "expected a folder");
}

std::vector<RecordedRow> run_recorded_experiment(const RecordedExperimentOptions& o, std::ostream* progress) {
  o.validate();
  std::vector<Scenario> scenarios;
  for (const auto& name : o.scenarios) scenarios.push_back(load_scenario(name));  // all errors first
  std::filesystem::create_directories(o.files_dir);
  bool peer = o.peer && !o.peer_script.empty();
  std::string peer_note;
  if (peer) {  // can the peer run at all? (Stone Soup importable with Debian's Python)
    const std::string log = o.files_dir + "/peer-check.log";
    const int rc = run_program({o.python, o.peer_script, "--check"}, log);
    if (rc != 0) {
      peer = false;
      std::cerr << "note: Stone Soup is not available (" << o.python << " " << o.peer_script
                << " --check exited " << rc << ", see " << log << "); its columns are left out\n";
    }
  }
  std::vector<RecordedRow> rows;
  for (std::size_t s = 0; s < scenarios.size(); ++s)
    for (int32_t run = 0; run < o.runs; ++run) {
      const Scenario& sc = scenarios[s];
      const TrackFile file = simulation_to_track_file(sc, simulate(sc, o.seed, run));
      // A scenario given as a JSON path names its files by the file's name, in --files.
      const std::string path = o.files_dir + "/" + std::filesystem::path(o.scenarios[s]).filename().string() +
                               "_run" + std::to_string(run) + ".h5";
      write_track_file(path, file);
      for (const auto& method : o.methods) {
        if (method.rfind("3d-", 0) == 0 && file.sensors.size() != 3) continue;
        double t = 0.0;
        if (method == "default") {  // as `associate`: recycled numbers split first, scored on the split keys
          const auto t0 = std::chrono::steady_clock::now();
          TrackFile split = file;
          split_recorded_keys(split, AssociatorOptions{});  // the default request's split
          const double split_s = seconds_since(t0);
          const AssociationRecord rec =
              associate_method(split, method, o.seed + static_cast<uint64_t>(run), t);
          rows.push_back(score(o.scenarios[s], method, run, split, rec, t + split_s));
          continue;
        }
        const AssociationRecord rec = associate_method(file, method, o.seed + static_cast<uint64_t>(run), t);
        rows.push_back(score(o.scenarios[s], method, run, file, rec, t));
      }
      if (peer) {
        const std::string json = path + ".stonesoup.json";
        const int rc = run_program({o.python, o.peer_script, path, "--cov", "sum", "--json", json},
                                   path + ".stonesoup.log");
        if (rc == 0)
          for (auto& r : peer_rows(o.scenarios[s], run, file, json)) rows.push_back(r);
        else
          std::cerr << "note: Stone Soup failed on " << path << " (exit " << rc << ", see " << path
                    << ".stonesoup.log)\n";
      }
      if (progress) *progress << "\r" << o.scenarios[s] << " run " << run + 1 << "/" << o.runs << std::flush;
    }
  if (progress) *progress << "\n";
  return rows;
}

std::string recorded_summary_table(const std::vector<RecordedRow>& rows, const RecordedExperimentOptions& o) {
  struct Sum {
    int32_t targets = 0, correct = 0, false_a = 0, missed = 0, linked = 0, false_t = 0, n = 0;
    std::vector<double> times;
  };
  std::map<std::pair<std::string, std::string>, Sum> sums;
  std::vector<std::string> methods = o.methods;
  methods.insert(methods.end(), kPeerMethods.begin(), kPeerMethods.end());
  for (const auto& r : rows) {
    Sum& s = sums[{r.scenario, r.method}];
    s.targets += r.targets;
    s.correct += r.correct;
    s.false_a += r.false_associations;
    s.missed += r.missed;
    s.linked += r.linked_tuples;
    s.false_t += r.false_tuples;
    s.times.push_back(r.time_s);
    ++s.n;
  }
  report::TextTable t({"scenario", "method", "targets", "correct %", "false %", "missed %", "false tuples",
                       "median time [ms]", "default's speed-up"});
  for (const auto& sc : o.scenarios) {
    double default_ms = std::numeric_limits<double>::quiet_NaN();
    for (const auto& m : methods) {
      auto it = sums.find({sc, m});
      if (it == sums.end()) continue;
      Sum& s = it->second;
      std::sort(s.times.begin(), s.times.end());
      const double med = 1e3 * s.times[s.times.size() / 2];
      if (m == "default") default_ms = med;
      char ms[32], ratio[32];
      std::snprintf(ms, sizeof ms, "%.1f", med);
      std::snprintf(ratio, sizeof ratio, "%.1fx", med / default_ms);
      t.add({sc, m, std::to_string(s.targets), pct(s.correct, s.targets), pct(s.false_a, s.targets),
             pct(s.missed, s.targets), std::to_string(s.false_t) + " of " + std::to_string(s.linked), ms,
             m == "default" || std::isnan(default_ms) ? "" : ratio});
    }
  }
  std::ostringstream os;
  os << "experiment recorded: " << o.runs << " run(s) per scenario, seed " << o.seed
     << "; rates over the targets tracked by >= 2 sensors (all runs pooled); the speed-up column is this "
        "method's time over the default's\n";
  t.print(os);
  return os.str();
}

void write_recorded_outputs(const std::vector<RecordedRow>& rows, const RecordedExperimentOptions& o) {
  std::vector<std::string> methods = o.methods;
  methods.insert(methods.end(), kPeerMethods.begin(), kPeerMethods.end());
  std::vector<int32_t> scenario, method, run, sensors, targets, correct, false_a, missed, linked, false_t;
  std::vector<double> time;
  for (const auto& r : rows) {
    scenario.push_back(static_cast<int32_t>(std::find(o.scenarios.begin(), o.scenarios.end(), r.scenario) -
                                            o.scenarios.begin()));
    method.push_back(
        static_cast<int32_t>(std::find(methods.begin(), methods.end(), r.method) - methods.begin()));
    run.push_back(r.run);
    sensors.push_back(r.sensors);
    targets.push_back(r.targets);
    correct.push_back(r.correct);
    false_a.push_back(r.false_associations);
    missed.push_back(r.missed);
    linked.push_back(r.linked_tuples);
    false_t.push_back(r.false_tuples);
    time.push_back(r.time_s);
  }
  write_atomically(o.output, [&](const std::string& tmp) {
    h5::File f = h5::File::create(tmp);
    const h5::Group root = f.root();
    write_experiment_header(root, "recorded");
    root.write_attribute("seed", o.seed);
    const h5::Group g = root.create_group("recorded");
    g.write_attribute("scenarios", nlohmann::json(o.scenarios).dump());
    g.write_attribute("methods", nlohmann::json(methods).dump());
    g.write_attribute("files", o.files_dir);
    const hsize_t K = rows.size();
    g.write_dataset("scenario", scenario, {K});
    g.write_dataset("method", method, {K});
    g.write_dataset("run", run, {K});
    g.write_dataset("sensors", sensors, {K});
    g.write_dataset("targets", targets, {K});
    g.write_dataset("correct", correct, {K});
    g.write_dataset("false", false_a, {K});
    g.write_dataset("missed", missed, {K});
    g.write_dataset("linked_tuples", linked, {K});
    g.write_dataset("false_tuples", false_t, {K});
    g.write_dataset("time_s", time, {K});
    f.close();
  });
  if (o.plot.empty()) return;
  // Correct rate vs association time (log x): one point per (method, scenario), runs pooled.
  std::vector<SvgSeries> series;
  for (const auto& m : methods) {
    SvgSeries s;
    s.label = m;
    for (const auto& sc : o.scenarios) {
      int32_t tg = 0, c = 0, n = 0;
      double t = 0.0;
      for (const auto& r : rows)
        if (r.scenario == sc && r.method == m) tg += r.targets, c += r.correct, t += r.time_s, ++n;
      if (n == 0 || tg == 0) continue;
      s.x.push_back(std::max(1e-2, 1e3 * t / n));
      s.y.push_back(100.0 * c / tg);
    }
    if (!s.x.empty()) series.push_back(std::move(s));
  }
  const std::string svg =
      svg_scatter("recorded family: correct association vs association time (one point per scenario)",
                  "association time per file [ms]", "correct association [%]", series, true);
  write_atomically(o.plot, [&](const std::string& tmp) { std::ofstream(tmp) << svg; });
}

}  // namespace trackassoc
