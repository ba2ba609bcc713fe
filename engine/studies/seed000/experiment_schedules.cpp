#include "engine/studies/seed000/experiment_schedules.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/distributed/sharding.hpp"
#include "engine/pipeline/pipeline.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "engine/solvers/hopfield_json.hpp"
#include "engine/studies/experiments.hpp"
#include "io/atomic_file.hpp"
#include "io/hdf5_wrapper.hpp"
#include "io/instance_text.hpp"
#include "kernels/assignment/heuristic_solvers.hpp"
#include "kernels/assignment/lagrangian_relaxation.hpp"
#include "kernels/assignment/local_search.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"
#include "kernels/hopfield/hopfield.hpp"

namespace trackassoc {

void SchedulesExperimentOptions::validate() const {
  require(runs >= 0, "--runs", "expected >= 0");
  require(decomplib_per_size >= 0 && decomplib_per_size <= 10, "--decomplib-per-size", "expected 0..10");
  require(restarts >= 1, "--restarts", "expected >= 1");
  for (int32_t n : tracking_sizes) require(n >= 1 && n <= 200, "--sizes", "expected sizes in 1..200");
  for (int32_t n : decomplib_sizes)
    require(n == 10 || n == 20 || n == 30 || n == 40, "--decomplib-sizes",
            "DecompLib has n = 10, 20, 30, 40");
  require(!output.empty(), "--output", "expected a file name");
  const std::vector<std::string> known = schedules_method_names();
  for (const auto& m : methods)
    if (std::find(known.begin(), known.end(), m) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "'" : ", '") + k + "'";
      throw InputError("--methods: unknown method '" + m + "'; expected one of " + list);
    }
}

ReferencedInstance seed000_tracking_instance(int32_t n, uint64_t seed, int32_t run) {
  Scenario sc = load_scenario("seed000");
  sc.random_targets.count = n;
  const SimulationResult sim = simulate(sc, seed, run);
  const TrackFile file = simulation_to_track_file(sc, sim);
  AssociationProblem p = build_association_problem(file, PipelineOptions::paper());
  ReferencedInstance inst;
  inst.family = "tracking";
  inst.name = "seed000 n=" + std::to_string(n) + " run " + std::to_string(run);
  inst.cost = std::move(p.tensor);
  const Solution3 lr = solve_lagrangian3(inst.cost, LagrangianOptions{});
  inst.reference = lr.summary.lower_bound;
  inst.reference_is_optimum = false;
  return inst;
}

namespace {

using Clock = std::chrono::steady_clock;
struct Method {
  std::string name;
  enum Kind { kNetwork, kGreedy, kGreedyLocalSearch, kLagrangian } kind = kNetwork;
  HopfieldOptions options;
};

std::vector<Method> methods(int32_t restarts) {
  std::vector<Method> m;
  // The discrete network's schedule s, or (continuous) the continuous network, sync or async.
  auto net = [&](const std::string& name, HopfieldSchedule s, HopfieldEnergy e, bool polish = false,
                 bool cont_async = false, bool continuous = false) {
    HopfieldOptions o;
    o.network = continuous ? HopfieldNetwork::kContinuous : HopfieldNetwork::kDiscrete;
    o.schedule = s;
    o.energy = e;
    o.restarts = restarts;
    o.polish = polish;
    o.continuous_async = cont_async;
    m.push_back({name, Method::kNetwork, o});
  };
  net("async/full", HopfieldSchedule::kAsync, HopfieldEnergy::kFullPlane);
  net("sync/full", HopfieldSchedule::kSync, HopfieldEnergy::kFullPlane);
  net("diagonal/full", HopfieldSchedule::kDiagonal, HopfieldEnergy::kFullPlane);
  net("async/printed", HopfieldSchedule::kAsync, HopfieldEnergy::kPrinted);
  net("sync/printed", HopfieldSchedule::kSync, HopfieldEnergy::kPrinted);
  net("continuous/sync", HopfieldSchedule::kAsync, HopfieldEnergy::kFullPlane, false, false, true);
  net("continuous/async", HopfieldSchedule::kAsync, HopfieldEnergy::kFullPlane, false, true, true);
  net("async/full+polish", HopfieldSchedule::kAsync, HopfieldEnergy::kFullPlane, true);
  // Without the mean-field start: what the energies alone do from the greedy and the empty state.
  {
    HopfieldOptions o;
    o.init = HopfieldInit::kGreedy;
    o.order = HopfieldOrder::kSliceRandom;
    o.restarts = restarts;
    m.push_back({"async/full greedy-start", Method::kNetwork, o});
    o.init = HopfieldInit::kZero;
    m.push_back({"async/full empty-start", Method::kNetwork, o});
  }
  m.push_back({"paper (printed, Eq. 11 weights)", Method::kNetwork, hopfield_preset("hopfield-paper")});
  m.push_back({"greedy", Method::kGreedy, {}});
  m.push_back({"greedy+ls", Method::kGreedyLocalSearch, {}});
  m.push_back({"lr", Method::kLagrangian, {}});
  return m;
}

}  // namespace

std::vector<std::string> schedules_method_names() {
  std::vector<std::string> names;
  for (const Method& m : methods(1)) names.push_back(m.name);
  return names;
}

namespace {

ScheduleRow run_method(const Method& m, const ReferencedInstance& inst, uint64_t seed) {
  ScheduleRow row;
  row.family = inst.family;
  row.instance = inst.name;
  row.method = m.name;
  row.n = std::max({inst.cost.n1, inst.cost.n2, inst.cost.n3});
  row.reference = inst.reference;
  const auto t0 = Clock::now();
  Solution3 s;
  switch (m.kind) {
    case Method::kNetwork: {
      const HopfieldResult r = solve_hopfield(inst.cost, m.options, seed);
      s = r.solution;
      row.raw_validity = r.raw_validity_rate;
      double sw = 0;
      for (const auto& rr : r.restarts) sw += static_cast<double>(rr.sweeps + rr.mean_field_steps);
      row.sweeps = sw / std::max<std::size_t>(1, r.restarts.size());
      break;
    }
    case Method::kGreedy:
      s = solve_greedy3(inst.cost);
      break;
    case Method::kGreedyLocalSearch: {
      const Solution3 g = solve_greedy3(inst.cost);
      s = solve_local_search3(inst.cost, g.tuples);
      row.sweeps = static_cast<double>(s.summary.sweeps);
      break;
    }
    case Method::kLagrangian:
      s = solve_lagrangian3(inst.cost, LagrangianOptions{});
      row.sweeps = static_cast<double>(s.summary.iterations);
      break;
  }
  row.wall_s = seconds_since(t0);
  row.valid = is_valid_assignment(inst.cost, s.tuples);
  row.objective = assignment_cost(inst.cost, s.tuples);
  row.gap = (row.objective - inst.reference) / std::max(std::abs(inst.reference), 1e-9);
  return row;
}

}  // namespace

// A row as it travels between ranks (engine/distributed/codec.hpp).
constexpr auto wire_codec(std::type_identity<ScheduleRow>) {
  return distributed::codec<ScheduleRow>(
      "schedules row", &ScheduleRow::family, &ScheduleRow::instance, &ScheduleRow::method, &ScheduleRow::n,
      &ScheduleRow::objective, &ScheduleRow::reference, &ScheduleRow::gap, &ScheduleRow::raw_validity,
      &ScheduleRow::sweeps, &ScheduleRow::wall_s, &ScheduleRow::valid);
}

// One item per instance, in the order one process visits them (tracking sizes × runs, then the
// DecompLib files), dealt to the ranks round robin (docs/design.md §8): a tracking instance (and its
// reference) is built by the rank that runs it, from (seed, size, run) alone; the DecompLib files
// are read by every rank first, so a bad file fails every rank alike.
std::vector<ScheduleRow> run_schedules_experiment(const SchedulesExperimentOptions& o,
                                                  std::ostream* progress) {
  o.validate();
  std::vector<ReferencedInstance> decomplib;
  if (o.decomplib_per_size > 0 && !o.decomplib_dir.empty()) {
    const auto optima = read_known_optima(o.decomplib_dir + "/ap3.opt");
    for (int32_t n : o.decomplib_sizes)
      for (int32_t k = 1; k <= o.decomplib_per_size; ++k) {
        const std::string name = "ap3." + std::to_string(n) + "." + std::to_string(k);
        ReferencedInstance inst;
        inst.family = "decomplib";
        inst.name = name;
        inst.cost = read_3dap_instance(o.decomplib_dir + "/" + name + ".txt");
        const auto it = optima.find(name);
        require(it != optima.end(), o.decomplib_dir + "/ap3.opt", "no optimum for " + name);
        inst.reference = it->second;
        inst.reference_is_optimum = true;
        decomplib.push_back(std::move(inst));
      }
  }
  std::vector<Method> ms = methods(o.restarts);
  if (!o.methods.empty())
    std::erase_if(ms, [&](const Method& m) {
      return std::find(o.methods.begin(), o.methods.end(), m.name) == o.methods.end();
    });
  const int64_t tracking = static_cast<int64_t>(o.tracking_sizes.size()) * o.runs;
  const int64_t items = tracking + static_cast<int64_t>(decomplib.size());
  auto describe = [&](int64_t i) {
    return i < tracking ? "schedules run " + std::to_string(i % o.runs) + " of " +
                              std::to_string(o.tracking_sizes[i / o.runs]) + " targets"
                        : "schedules " + decomplib[i - tracking].name;
  };
  return distributed::sharded_items<ScheduleRow>(
      distributed::world(), items,
      [&](int64_t i) {
        const ReferencedInstance inst = i < tracking
                                            ? seed000_tracking_instance(o.tracking_sizes[i / o.runs], o.seed,
                                                                        static_cast<int32_t>(i % o.runs))
                                            : decomplib[i - tracking];
        if (progress) *progress << "[" << (i + 1) << "/" << items << "] " << inst.name << "\n";
        std::vector<ScheduleRow> rows;
        for (const Method& m : ms) rows.push_back(run_method(m, inst, o.seed));
        return rows;
      },
      describe);
}

namespace {

struct Aggregate {
  int count = 0, within = 0, valid = 0;
  double gap = 0, raw = 0, sweeps = 0, wall = 0, max_gap = 0;
  bool network = false;
};

std::string format(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

}  // namespace

std::string schedules_summary_table(const std::vector<ScheduleRow>& rows) {
  // Keep first-appearance order of (family, n) and of methods.
  std::vector<std::pair<std::string, int32_t>> groups;
  std::vector<std::string> method_order;
  std::map<std::tuple<std::string, int32_t, std::string>, Aggregate> agg;
  for (const auto& r : rows) {
    const auto g = std::make_pair(r.family, r.n);
    if (std::find(groups.begin(), groups.end(), g) == groups.end()) groups.push_back(g);
    if (std::find(method_order.begin(), method_order.end(), r.method) == method_order.end())
      method_order.push_back(r.method);
    Aggregate& a = agg[{r.family, r.n, r.method}];
    ++a.count;
    a.within += r.gap <= 0.01 + 1e-12;
    a.valid += r.valid;
    a.gap += r.gap;
    a.max_gap = std::max(a.max_gap, r.gap);
    a.network = r.raw_validity >= 0;
    a.raw += std::max(0.0, r.raw_validity);
    a.sweeps += r.sweeps;
    a.wall += r.wall_s;
  }
  std::ostringstream os;
  char line[256];
  for (const auto& g : groups) {
    os << "\n"
       << g.first << ", n = " << g.second
       << (g.first == "tracking" ? "  (gap to the LR lower bound)" : "  (gap to the known optimum)") << "\n";
    std::snprintf(line, sizeof line, "  %-32s %9s %9s %8s %7s %8s %9s %10s\n", "method", "mean gap",
                  "max gap", "<=1 %", "valid", "raw", "sweeps", "time [ms]");
    os << line << "  " << std::string(98, '-') << "\n";
    for (const auto& m : method_order) {
      const auto it = agg.find({g.first, g.second, m});
      if (it == agg.end()) continue;
      const Aggregate& a = it->second;
      const double c = a.count;
      std::snprintf(line, sizeof line, "  %-32s %8.3f%% %8.3f%% %3d/%-3d %6.0f%% %8s %9.1f %10.2f\n",
                    m.c_str(), 100 * a.gap / c, 100 * a.max_gap, a.within, a.count, 100.0 * a.valid / c,
                    a.network ? (format("%.0f", 100 * a.raw / c) + "%").c_str() : "-", a.sweeps / c,
                    1e3 * a.wall / c);
      os << line;
    }
  }
  return os.str();
}

void write_schedules_outputs(const std::vector<ScheduleRow>& rows, const SchedulesExperimentOptions& o) {
  std::vector<std::string> method_names, instance_names;
  auto index_of = [](std::vector<std::string>& v, const std::string& s) {
    auto it = std::find(v.begin(), v.end(), s);
    if (it == v.end()) {
      v.push_back(s);
      return static_cast<int32_t>(v.size() - 1);
    }
    return static_cast<int32_t>(it - v.begin());
  };
  std::vector<int32_t> method, instance, n, decomplib, valid;
  std::vector<double> objective, reference, gap, raw, sweeps, wall;
  for (const auto& r : rows) {
    method.push_back(index_of(method_names, r.method));
    instance.push_back(index_of(instance_names, r.instance));
    n.push_back(r.n);
    decomplib.push_back(r.family == "decomplib");
    valid.push_back(r.valid);
    objective.push_back(r.objective);
    reference.push_back(r.reference);
    gap.push_back(r.gap);
    raw.push_back(r.raw_validity);
    sweeps.push_back(r.sweeps);
    wall.push_back(r.wall_s);
  }
  write_atomically(o.output, [&](const std::string& tmp) {
    h5::File f = h5::File::create(tmp);
    const h5::Group root = f.root();
    write_experiment_header(root, "schedules");
    root.write_attribute("seed", o.seed);
    const h5::Group g = root.create_group("schedules");
    g.write_attribute("methods", nlohmann::json(method_names).dump());
    g.write_attribute("instances", nlohmann::json(instance_names).dump());
    g.write_attribute(
        "note", std::string("one row per (instance, method); gap = (objective - reference) / |reference|; "
                            "reference = LR lower bound (tracking) or known optimum (decomplib); "
                            "raw_validity = -1 for non-network methods"));
    const hsize_t K = rows.size();
    g.write_dataset("method", method, {K});
    g.write_dataset("instance", instance, {K});
    g.write_dataset("n", n, {K});
    g.write_dataset("decomplib", decomplib, {K});
    g.write_dataset("valid", valid, {K});
    g.write_dataset("objective", objective, {K});
    g.write_dataset("reference", reference, {K});
    g.write_dataset("gap", gap, {K});
    g.write_dataset("raw_validity", raw, {K});
    g.write_dataset("sweeps", sweeps, {K});
    g.write_dataset("wall_time_s", wall, {K});
    f.close();
  });
  if (!o.plot.empty()) {
    std::vector<SvgSeries> series;
    for (const auto& m : method_names) {
      SvgSeries s;
      s.label = m;
      for (const auto& r : rows)
        if (r.method == m) {
          s.x.push_back(std::max(r.wall_s, 1e-6));
          s.y.push_back(100 * r.gap);
        }
      series.push_back(std::move(s));
    }
    const std::string svg = svg_scatter("Hopfield schedules: gap vs wall time (all instances)",
                                        "wall time [s]", "gap to reference [%]", series, true);
    write_atomically(o.plot, [&](const std::string& tmp) {
      std::ofstream out(tmp);
      out << svg;
      if (!out) throw InputError(o.plot + ": cannot write");
    });
  }
}

}  // namespace trackassoc
