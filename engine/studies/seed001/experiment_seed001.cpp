#include "engine/studies/seed001/experiment_seed001.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <ostream>

#include "engine/distributed/sharding.hpp"
#include "engine/pipeline/metrics.hpp"
#include "engine/report/text_table.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

FtaaOptions Seed001Options::paper_ftaa() {
  FtaaOptions f;
  f.association_quality = 6;  // seed 001 §1: "generally m ≥ 6, D ≥ 6"
  f.separation_quality = 6;
  f.gate = 800.0;  // §4: tracking gate radius 800 m
  return f;
}

namespace {

constexpr double kSigmaRange[4] = {50.0, 100.0, 50.0, 120.0};  // σr per node [m] (§4)
constexpr double kReliability[4] = {1.0, 0.8, 1.0, 0.6};       // ω per node (§4)

// Per-axis variance of node l's converted plot at range R (the trace of
// R = J diag(σr², σθ²) Jᵀ over 2, kernels/filters/kalman_converted.hpp).
double node_plot_variance(BearingReading reading, int l, double R) {
  const double sb = seed001_sigma_bearing(reading)[l];
  return 0.5 * (kSigmaRange[l] * kSigmaRange[l] + R * R * sb * sb);
}

}  // namespace

std::array<double, 4> seed001_sigma_bearing(BearingReading reading) {
  const double deg = std::numbers::pi / 180.0;
  // Erratum: σθ1 = 0.1° (the printed 1° contradicts the reliabilities; header comment).
  const double node1 = reading == BearingReading::kErratum ? 0.1 : 1.0;
  return {node1 * deg, 0.12 * deg, 0.1 * deg, 0.12 * deg};
}

double seed001_plot_sigma(BearingReading reading, double range) {
  double v = 0.0;
  for (int l = 0; l < 4; ++l) v += node_plot_variance(reading, l, range) / 4.0;
  return std::sqrt(v);
}

AlphaBetaOptions seed001_smoother(const Seed001Options& o) {
  AlphaBetaOptions ab;
  ab.gains = AlphaBetaGainMode::kKalata;
  ab.process_noise = o.smoother_process_noise;
  ab.measurement_noise = seed001_plot_sigma(o.bearing_reading, o.design_range);
  ab.expanding_memory_start = true;
  return ab;
}

Seed001Model seed001_model(const Seed001Options& o) {
  Seed001Model m;
  const AlphaBetaOptions ab = o.design_smoother ? seed001_smoother(o) : o.fuzzy.smoother;
  m.plot_sigma = ab.measurement_noise;
  m.steady_gains = alpha_beta_gains(ab, 1.0);
  double var[4];
  for (int l = 0; l < 4; ++l) var[l] = node_plot_variance(o.bearing_reading, l, o.design_range);
  const double T4 = o.packet_period, T = o.packet_period / 4.0;
  const int first = static_cast<int>(std::llround(T4 / T));  // first temporary track: node 1 at 4 s
  const int steps = static_cast<int>(std::floor(o.duration / T + 1e-9));
  // Proposed: one system track's covariance through the bank's own gains.
  AlphaBetaBank bank(2, 0, ab);
  const double zero[2] = {0.0, 0.0};
  bank.add_track(zero, zero);
  double pp = var[0], pv = var[0] / T4, vv = 2.0 * var[0] / (T4 * T4);
  double sum_p = std::sqrt(2.0 * pp), sum_f = std::sqrt(2.0 * var[0]);
  const int firm_step = first + o.ftaa.association_quality * first;
  for (int k = first + 1; k <= steps; ++k) {
    const int l = k % 4;
    bank.predict_track(0, T);
    const AlphaBetaGains g = bank.next_update_gains(0);
    bank.update_track(0, zero);
    // Predict (no process noise: the targets fly straight), then the update with K = [α, β/T].
    const double ppp = pp + 2.0 * T * pv + T * T * vv, ppv = pv + T * vv, pvv = vv;
    const double a = g.alpha, b = g.beta / T;
    pp = (1 - a) * (1 - a) * ppp + a * a * var[l];
    pv = (1 - a) * (ppv - b * ppp) + a * b * var[l];
    vv = pvv - 2.0 * b * ppv + b * b * ppp + b * b * var[l];
    sum_p += std::sqrt(2.0 * pp);
    // FTAA: node l's own plot until firm, then the mean of the four nodes' predicted plots.
    double fv = var[l];
    if (k >= firm_step) {
      fv = 0.0;
      for (int age = 0; age < 4; ++age) {
        const double r = age * T / T4;
        fv += var[(l - age + 4) % 4] * ((1 + r) * (1 + r) + r * r) / 16.0;
      }
    }
    sum_f += std::sqrt(2.0 * fv);
  }
  const int n = steps - first + 1;
  m.proposed_rmse = sum_p / n;
  m.ftaa_rmse = sum_f / n;
  return m;
}

void Seed001Options::validate() const {
  require(runs >= 1, "runs", "expected >= 1");
  require(std::isfinite(smoother_process_noise) && smoother_process_noise > 0, "smoother_process_noise",
          "expected > 0 [m/s²]");
  require(std::isfinite(design_range) && design_range > 0, "design_range", "expected > 0 [m]");
  require(std::isfinite(duration) && duration > 0, "duration", "expected > 0 [s]");
  require(std::isfinite(scan_period) && scan_period > 0, "scan_period", "expected > 0 [s]");
  require(std::isfinite(packet_period) && packet_period >= scan_period, "packet_period",
          "expected >= scan_period [s]");
  fuzzy.validate();
  ftaa.validate();
}

Scenario seed001_scenario(const Seed001Options& o) {
  Scenario s;
  s.name = "seed001";
  s.layout = StateLayout::kXY_VXVY;
  s.duration = o.duration;
  s.truth_step = o.scan_period;
  s.seed = o.seed;
  // Paper order [x, vx, y, vy] → (x, y, z, vx, vy, vz).
  const std::array<std::array<double, 6>, 2> x0{
      {{-29500.0, 34500.0, 0.0, 290.0, -400.0, 0.0}, {-12250.0, 32500.0, 0.0, 125.0, -400.0, 0.0}}};
  for (int k = 0; k < 2; ++k) {
    TargetSpec t;
    t.id = k;
    t.initial_state = x0[k];
    MotionSegment seg;
    seg.model = MotionModel::kConstantVelocity;
    seg.duration = o.duration;
    t.segments.push_back(seg);
    s.targets.push_back(t);
  }
  const std::array<double, 4> sb = seed001_sigma_bearing(o.bearing_reading);
  const std::array<std::array<double, 3>, 4> pos{
      {{-40000.0, 0.0, 0.0}, {40000.0, 0.0, 0.0}, {0.0, -60000.0, 0.0}, {0.0, 60000.0, 0.0}}};
  for (int l = 0; l < 4; ++l) {
    Sensor sensor;
    sensor.id = l + 1;  // N1..N4
    sensor.position = pos[l];
    sensor.sigma_range = kSigmaRange[l];
    sensor.sigma_bearing = sb[l];
    sensor.period = o.scan_period;
    sensor.offset = l * o.packet_period / 4.0;  // staggered start: 0, 1, 2, 3 s
    sensor.p_detect = 1.0;
    sensor.clutter_rate = 0.0;
    sensor.reliability = kReliability[l];
    s.sensors.push_back(sensor);
  }
  s.tracker.filter = "cv";
  s.tracker.process_noise = 1.0;
  return s;
}

namespace {

// Truth position of `target` at time t, linear between truth samples (exact for CV motion).
bool truth_at(const TruthTable& truth, int32_t target, double t, double& x, double& y) {
  std::size_t best_lo = truth.size(), best_hi = truth.size();
  for (std::size_t r = 0; r < truth.size(); ++r) {
    if (truth.target[r] != target) continue;
    if (truth.t[r] <= t && (best_lo == truth.size() || truth.t[r] > truth.t[best_lo])) best_lo = r;
    if (truth.t[r] >= t && (best_hi == truth.size() || truth.t[r] < truth.t[best_hi])) best_hi = r;
  }
  if (best_lo == truth.size() || best_hi == truth.size()) return false;
  const double t0 = truth.t[best_lo], t1 = truth.t[best_hi];
  const double w = t1 > t0 ? (t - t0) / (t1 - t0) : 0.0;
  x = (1 - w) * truth.state[0][best_lo] + w * truth.state[0][best_hi];
  y = (1 - w) * truth.state[1][best_lo] + w * truth.state[1][best_hi];
  return true;
}

struct RunOutcome {
  // [method][target][time index]: squared error and count.
  std::array<std::array<std::vector<double>, 2>, 2> se, n;
  std::array<double, 2> time_per_decision{}, decisions{}, system_tracks{};
  std::array<AssociationMetrics, 2> metrics;
};

// What every run of one reading shares: the scenario, the RMSE grid and the two methods.
struct Seed001Setup {
  Scenario scenario;
  std::size_t steps = 0;
  std::array<FuzzyPipelineOptions, 2> method;
};

Seed001Setup seed001_setup(const Seed001Options& o) {
  o.validate();
  Seed001Setup s;
  s.scenario = seed001_scenario(o);
  s.steps = static_cast<std::size_t>(std::floor(o.duration / o.scan_period + 1e-9)) + 1;
  s.method[0].method = FusionMethod::kFuzzy;
  s.method[0].fuzzy = o.fuzzy;
  if (o.design_smoother) s.method[0].fuzzy.smoother = seed001_smoother(o);
  s.method[1].method = FusionMethod::kFtaa;
  s.method[1].ftaa = o.ftaa;
  for (auto& m : s.method) {
    m.packet_period = o.packet_period;
    m.packet_source = o.packet_source;
  }
  return s;
}

// One Monte Carlo run: both methods on one simulation, drawn from (seed, run) alone. `example`
// (run 0 of the reading that is written) receives the scenario, truth, tracks and both associations.
RunOutcome seed001_run(const Seed001Options& o, const Seed001Setup& s, int run, TrackFile* example) {
  const SimulationResult sim = simulate(s.scenario, o.seed, run);
  RunOutcome out;
  for (int m = 0; m < 2; ++m) {
    for (int k = 0; k < 2; ++k) {
      out.se[m][k].assign(s.steps, 0.0);
      out.n[m][k].assign(s.steps, 0.0);
    }
    const std::string name = enum_name(s.method[m].method);
    const FuzzyPipelineResult res =
        run_fuzzy_pipeline(sim.tracks, s.scenario.sensors, s.method[m], name, &sim.measurements);
    const PacketTable& p = res.packets;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const int32_t target = p.truth[i];
      if (res.fusion.system_track[i] < 0 || target < 0 || target > 1) continue;
      double tx, ty;
      if (!truth_at(sim.truth, target, p.t[i], tx, ty)) continue;
      const std::size_t k = static_cast<std::size_t>(std::llround(p.t[i] / o.scan_period));
      if (k >= s.steps) continue;
      const double dx = res.fusion.x[i] - tx, dy = res.fusion.y[i] - ty;
      out.se[m][target][k] += dx * dx + dy * dy;
      out.n[m][target][k] += 1.0;
    }
    const double d = static_cast<double>(res.fusion.summary.iterations);
    out.decisions[m] = d;
    out.time_per_decision[m] = d > 0 ? res.fusion.summary.wall_time_s / d : 0.0;
    out.system_tracks[m] = res.fusion.num_system_tracks;
    out.metrics[m] = evaluate_association(sim.tracks, s.scenario.sensors, res.association);
    if (example) {
      if (m == 0) *example = simulation_to_track_file(s.scenario, sim);
      associate_fuzzy(*example, s.method[m], name);
    }
  }
  return out;
}

// A run's outcome as it travels between ranks (engine/distributed/codec.hpp).
constexpr auto wire_codec(std::type_identity<RunOutcome>) {
  return distributed::codec<RunOutcome>("seed001 run outcome", &RunOutcome::se, &RunOutcome::n,
                                        &RunOutcome::time_per_decision, &RunOutcome::decisions,
                                        &RunOutcome::system_tracks, &RunOutcome::metrics);
}

// The result of one reading from its runs' outcomes, in run order (a deterministic reduction).
Seed001Result seed001_reduce(const Seed001Options& o, const Seed001Setup& s,
                             const std::vector<RunOutcome>& outcomes, TrackFile example) {
  const std::size_t steps = s.steps;
  Seed001Result result;
  result.smoother = s.method[0].fuzzy.smoother;
  result.model = seed001_model(o);
  result.example = std::move(example);
  for (int m = 0; m < 2; ++m) {
    Seed001MethodResult& r = m == 0 ? result.fuzzy : result.ftaa;
    r.method = m == 0 ? "proposed (fuzzy)" : "FTAA";
    r.time.resize(steps);
    for (std::size_t k = 0; k < steps; ++k) r.time[k] = k * o.scan_period;
    for (int target = 0; target < 2; ++target) {
      r.rmse[target].assign(steps, std::numeric_limits<double>::quiet_NaN());
      double sum = 0.0;
      int count = 0;
      for (std::size_t k = 0; k < steps; ++k) {
        double se = 0.0, n = 0.0;
        for (const auto& out : outcomes) {
          se += out.se[m][target][k];
          n += out.n[m][target][k];
        }
        if (n > 0) {
          r.rmse[target][k] = std::sqrt(se / n);
          sum += r.rmse[target][k];
          ++count;
        }
      }
      r.mean_rmse[target] = count ? sum / count : std::numeric_limits<double>::quiet_NaN();
    }
    // Median over runs: one run is ~100 µs, so a single preemption would dominate a mean.
    std::vector<double> times;
    for (const auto& out : outcomes) times.push_back(out.time_per_decision[m]);
    std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
    r.time_per_association_s = times[times.size() / 2];
    for (const auto& out : outcomes) {
      r.decisions_per_run += out.decisions[m] / o.runs;
      r.system_tracks_per_run += out.system_tracks[m] / o.runs;
      r.correct_rate += out.metrics[m].correct_rate / o.runs;
      r.false_rate += out.metrics[m].false_rate / o.runs;
      r.missed_rate += out.metrics[m].missed_rate / o.runs;
    }
    MetricsRecord rec;
    rec.name = std::string("seed001_") + (m == 0 ? "fuzzy" : "ftaa");
    rec.correct_rate = r.correct_rate;
    rec.false_rate = r.false_rate;
    rec.missed_rate = r.missed_rate;
    rec.tables["time"] = r.time;
    rec.tables["rmse_target0"] = r.rmse[0];
    rec.tables["rmse_target1"] = r.rmse[1];
    rec.tables["mean_rmse"] = {r.mean_rmse[0], r.mean_rmse[1]};
    rec.tables["time_per_association_s"] = {r.time_per_association_s};
    result.example.metrics.push_back(rec);
  }
  return result;
}

}  // namespace

Seed001Result run_seed001(const Seed001Options& o) {
  distributed::SingleProcessCommunicator one;
  return run_seed001_readings({o}, one).front();
}

// The runs of every reading, flattened in the order one process visits them (reading, then run),
// dealt to the ranks round robin and run in parallel within a rank (docs/design.md §8); rank 0 reduces
// them in run order. Item 0, the example's run, is always rank 0's (owner_of_item).
std::vector<Seed001Result> run_seed001_readings(const std::vector<Seed001Options>& readings,
                                                distributed::Communicator& comm) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<Seed001Setup> setups;
  for (const auto& o : readings) setups.push_back(seed001_setup(o));  // all errors before any run
  std::vector<int64_t> first{0};                                      // item of each reading's run 0
  for (const auto& o : readings) first.push_back(first.back() + o.runs);
  auto reading_of = [&](int64_t i) {
    return static_cast<std::size_t>(std::upper_bound(first.begin(), first.end(), i) - first.begin() - 1);
  };
  TrackFile example;
  const std::vector<RunOutcome> outcomes = distributed::sharded_items<RunOutcome>(
      comm, first.back(),
      [&](int64_t i) {
        const std::size_t k = reading_of(i);
        const int run = static_cast<int>(i - first[k]);
        return std::vector<RunOutcome>{seed001_run(readings[k], setups[k], run, i == 0 ? &example : nullptr)};
      },
      [&](int64_t i) {
        const std::size_t k = reading_of(i);
        return "seed001 run " + std::to_string(i - first[k]) + " of reading " +
               std::string(enum_name(readings[k].bearing_reading));
      },
      /*parallel=*/true);
  if (!comm.root()) return {};
  std::vector<Seed001Result> results;
  for (std::size_t k = 0; k < readings.size(); ++k) {
    const std::vector<RunOutcome> mine(outcomes.begin() + first[k], outcomes.begin() + first[k + 1]);
    results.push_back(
        seed001_reduce(readings[k], setups[k], mine, k == 0 ? std::move(example) : TrackFile()));
  }
  const double wall = seconds_since(start);
  for (auto& r : results) r.wall_time_s = wall;
  return results;
}

namespace {

// One line per table row: why ours differs from the paper, with the numbers the code computes.
std::string reason(const Seed001Options& o, const Seed001Result& r, bool ftaa) {
  const Seed001MethodResult& m = ftaa ? r.ftaa : r.fuzzy;
  const double* paper = ftaa ? Seed001Paper::ftaa_rmse : Seed001Paper::proposed_rmse;
  const double ratio = 0.5 * (m.mean_rmse[0] / paper[0] + m.mean_rmse[1] / paper[1]);
  std::string s = std::string(enum_name(o.bearing_reading)) + ", " + (ftaa ? "FTAA" : "proposed") +
                  ": ours/paper " + report::fmt(ratio, "%.2f") + "; ";
  if (o.bearing_reading == BearingReading::kLiteral) {
    const double cross = o.design_range * std::numbers::pi / 180.0;  // node 1's cross-range σ
    const std::string plots = "node 1's 1° plots (" + report::fmt(cross, "%.0f") + " m cross-range σ at " +
                              report::fmt(o.design_range / 1000.0, "%.0f") + " km, often beyond the " +
                              report::fmt(o.fuzzy.gate, "%.0f") + " m gate; " +
                              report::fmt(std::sqrt(2.0) * cross / o.packet_period, "%.0f") +
                              " m/s σ on the two-plot velocity)";
    if (ftaa)
      return s + plots + " never make firm pairs: no tuple holds all 4 nodes (correct " +
             report::percent(m.correct_rate) + ", " + report::fmt(m.system_tracks_per_run, "%.1f") +
             " system tracks/run) and node 1's packets output its own plot";
    return s + plots + " miss the gate and start new system tracks (" +
           report::fmt(m.system_tracks_per_run, "%.1f") +
           "/run), output at node 1's plot; the model (every plot in its target's one system track) gives " +
           report::fmt(r.model.proposed_rmse, "%.0f") + " m";
  }
  if (ftaa)
    return s + "plot-noise model " + report::fmt(r.model.ftaa_rmse, "%.0f") +
           " m: FTAA outputs the unweighted mean of the 4 nodes' plots predicted up to 3 s with velocities "
           "differenced over 4 s; the rest is the sensor geometry (not given in the paper)";
  return s + "plot-noise model " + report::fmt(r.model.proposed_rmse, "%.0f") +
         " m: α-β with Kalata gains (σ_w " + report::fmt(r.smoother.process_noise, "%.2g") + " m/s², σ_v " +
         report::fmt(r.smoother.measurement_noise, "%.0f") + " m, steady α " +
         report::fmt(r.model.steady_gains.alpha, "%.3f") + ", β " +
         report::fmt(r.model.steady_gains.beta, "%.4f") +
         ") after its least-squares start; the paper gives neither its gains (σ_w is ours: the RMSE grows "
         "with it, --smoother-process-noise) nor the sensor geometry";
}

}  // namespace

void run_seed001_study(const Seed001Options& o, const std::string& output, std::ostream& out) {
  Seed001Options other = o;
  other.bearing_reading =
      o.bearing_reading == BearingReading::kErratum ? BearingReading::kLiteral : BearingReading::kErratum;
  auto& comm = distributed::world();
  const std::vector<Seed001Result> both = run_seed001_readings({o, other}, comm);
  if (!comm.root()) return;  // rank 0 has the results, and alone prints and writes
  const Seed001Result &r = both[0], &q = both[1];
  write_track_file(output, r.example);
  // Erratum first.
  const bool erratum_first = o.bearing_reading == BearingReading::kErratum;
  const Seed001Options& o1 = erratum_first ? o : other;
  const Seed001Options& o2 = erratum_first ? other : o;
  const Seed001Result& r1 = erratum_first ? r : q;
  const Seed001Result& r2 = erratum_first ? q : r;

  out << "seed 001: " << o.runs << " runs, seed " << o.seed << ", " << o.duration
      << " s; sensors scan every 1 s from 0/1/2/3 s, report every " << o.packet_period << " s ("
      << (o.packet_source == PacketSource::kPlot ? "plot" : "track")
      << " packets); sensors at (-40,0), (40,0), (0,-60), (0,60) km; gate " << o.fuzzy.gate
      << " m; FTAA m >= " << o.ftaa.association_quality << ", D >= " << o.ftaa.separation_quality << "\n"
      << "sigma_theta1: erratum 0.1 deg (default; the reliabilities 1.0/0.8/1.0/0.6 follow sigma_r, so "
         "node 1 = node 3 needs 0.1 deg), literal 1 deg as printed\n\n";
  report::TextTable t({"reading", "method", "RMSE S1 [m]", "paper", "RMSE S2 [m]", "paper", "model [m]",
                       "time/assoc [us]", "paper [us]", "correct", "sys tracks/run"});
  auto row = [&](const Seed001Options& oo, const Seed001Result& rr, bool ftaa) {
    const Seed001MethodResult& m = ftaa ? rr.ftaa : rr.fuzzy;
    const double* paper_rmse = ftaa ? Seed001Paper::ftaa_rmse : Seed001Paper::proposed_rmse;
    const double paper_time = ftaa ? Seed001Paper::ftaa_time_s : Seed001Paper::proposed_time_s;
    t.add({enum_name(oo.bearing_reading), ftaa ? "FTAA" : "proposed", report::fmt(m.mean_rmse[0], "%.1f"),
           report::fmt(paper_rmse[0], "%.1f"), report::fmt(m.mean_rmse[1], "%.1f"),
           report::fmt(paper_rmse[1], "%.1f"),
           report::fmt(ftaa ? rr.model.ftaa_rmse : rr.model.proposed_rmse, "%.0f"),
           report::fmt(1e6 * m.time_per_association_s, "%.2f"), report::fmt(1e6 * paper_time, "%.0f"),
           report::percent(m.correct_rate), report::fmt(m.system_tracks_per_run, "%.2f")});
  };
  row(o1, r1, true);
  row(o1, r1, false);
  row(o2, r2, true);
  row(o2, r2, false);
  t.print(out);
  out << "\nWhy ours differs from the paper (model = the plot-noise model of "
         "engine/studies/seed001/experiment_seed001.hpp, nominal range "
      << report::fmt(o.design_range / 1000.0, "%.0f") << " km):\n";
  for (const auto* p : {&o1, &o2})
    for (bool ftaa : {true, false}) out << "  " << reason(*p, p == &o1 ? r1 : r2, ftaa) << "\n";
  out << "  times: the paper's are MATLAB 2009 wall times per association (its Table 2 has the proposed\n"
         "  method slower, contradicting its text); ours are C++ per decision.\n"
      << "proposed / FTAA RMSE (" << enum_name(o1.bearing_reading)
      << "): " << report::fmt(r1.fuzzy.mean_rmse[0] / r1.ftaa.mean_rmse[0], "%.2f") << " (S1), "
      << report::fmt(r1.fuzzy.mean_rmse[1] / r1.ftaa.mean_rmse[1], "%.2f") << " (S2); paper: 0.34, 0.36.\n"
      << "wall time " << report::fmt(r.wall_time_s, "%.2f") << " s; " << enum_name(o.bearing_reading)
      << " reading -> " << output << "\n";
}

}  // namespace trackassoc
