#include "engine/studies/scale/experiment_scale.hpp"

#include <oneapi/tbb/global_control.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>
#include <numeric>
#include <set>
#include <sstream>

#include "engine/pipeline/associator.hpp"
#include "engine/pipeline/metrics.hpp"
#include "engine/pipeline/pipeline.hpp"
#include "engine/pipeline/sparse_pipeline.hpp"
#include "engine/studies/experiments.hpp"
#include "io/atomic_file.hpp"
#include "io/hdf5_wrapper.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

void SyntheticTrackSpec::validate() const {
  require(targets >= 0, "SyntheticTrackSpec.targets", "must be >= 0");
  require(sensors >= 1, "SyntheticTrackSpec.sensors", "must be >= 1");
  require(box > 0 && std::isfinite(box) && box_z >= 0 && std::isfinite(box_z), "SyntheticTrackSpec.box",
          "must be finite and positive");
  require(speed_min >= 0 && speed_max >= speed_min, "SyntheticTrackSpec.speed_min",
          "need 0 <= speed_min <= speed_max");
  require(duration > 0 && std::isfinite(duration), "SyntheticTrackSpec.duration", "must be positive");
  require(sigma_pos > 0 && sigma_vel > 0, "SyntheticTrackSpec.sigma_pos", "error sigmas must be positive");
  require(p_seen >= 0 && p_seen <= 1, "SyntheticTrackSpec.p_seen", "must be in [0, 1]");
  require(min_lifetime_fraction > 0 && min_lifetime_fraction <= 1, "SyntheticTrackSpec.min_lifetime_fraction",
          "must be in (0, 1]");
  require(!periods.empty() && !offsets.empty(), "SyntheticTrackSpec.periods",
          "need at least one period and offset");
  for (double p : periods)
    require(p > 0 && std::isfinite(p), "SyntheticTrackSpec.periods", "must be positive");
}

TrackFile synthetic_recorded_tracks(const SyntheticTrackSpec& spec) {
  spec.validate();
  const StateLayout layout = spec.three_d ? StateLayout::kXYZ_VXVYVZ : StateLayout::kXY_VXVY;
  const int D = state_dim(layout), m = D / 2;
  TrackFile file;
  file.created_by = "trackassoc synthetic_recorded_tracks";
  file.tracks.reset(layout);
  std::vector<Eigen::VectorXd> x0(spec.targets, Eigen::VectorXd::Zero(D));
  CounterRng trng(spec.seed, 0, 1000);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(m);
  for (int32_t g = 0; g < spec.targets; ++g) {
    Eigen::VectorXd& x = x0[g];
    x[0] = trng.uniform(0.0, spec.box);
    x[1] = trng.uniform(0.0, spec.box);
    if (m == 3) x[2] = trng.uniform(0.0, spec.box_z);
    if (!spec.formation || g == 0) {
      const double heading = trng.uniform(0.0, 6.283185307179586);
      const double speed = trng.uniform(spec.speed_min, spec.speed_max);
      v[0] = speed * std::cos(heading);
      v[1] = speed * std::sin(heading);
      if (m == 3) v[2] = spec.vertical_speed * trng.normal();
    }
    x.tail(m) = v;
  }
  std::size_t rows = 0;
  for (int32_t s = 0; s < spec.sensors; ++s)
    rows += static_cast<std::size_t>(spec.targets) *
            (1 + static_cast<std::size_t>(spec.duration / spec.periods[s % spec.periods.size()]));
  file.tracks.reserve(static_cast<std::size_t>(rows * spec.p_seen) + 16);
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(D, D);
  Eigen::VectorXd x(D), z(D);
  for (int32_t s = 0; s < spec.sensors; ++s) {
    Sensor sensor;
    sensor.id = s + 1;
    sensor.period = spec.periods[s % spec.periods.size()];
    sensor.offset = spec.offsets[s % spec.offsets.size()];
    sensor.p_detect = spec.p_seen;
    file.sensors.push_back(sensor);
    CounterRng rng(spec.seed, 1, static_cast<uint64_t>(s));
    std::vector<int32_t> seen, number;
    for (int32_t g = 0; g < spec.targets; ++g)
      if (rng.uniform() < spec.p_seen) seen.push_back(g);
    number.resize(seen.size());
    std::iota(number.begin(), number.end(), 0);
    rng.shuffle(std::span<int32_t>(number));  // local track numbers carry no information
    for (std::size_t q = 0; q < seen.size(); ++q) {
      const int32_t g = seen[q];
      CounterRng e(spec.seed, 2 + static_cast<uint64_t>(s), static_cast<uint64_t>(g));
      const double scale = e.uniform(0.5, 2.0);
      P.setZero();
      for (int c = 0; c < m; ++c) {
        P(c, c) = scale * spec.sigma_pos * spec.sigma_pos;
        P(m + c, m + c) = scale * spec.sigma_vel * spec.sigma_vel;
      }
      const Eigen::VectorXd sd = P.diagonal().cwiseSqrt();  // diagonal: L = diag(σ)
      double t_begin = 0.0, t_end = spec.duration;
      if (spec.min_lifetime_fraction < 1.0) {
        const double life = spec.duration * e.uniform(spec.min_lifetime_fraction, 1.0);
        t_begin = e.uniform(0.0, spec.duration - life);
        t_end = t_begin + life;
      }
      const int64_t scans =
          static_cast<int64_t>(std::floor((spec.duration - sensor.offset) / sensor.period + 1e-9));
      for (int64_t k = 0; k <= scans; ++k) {
        const double t = sensor.offset + static_cast<double>(k) * sensor.period;
        if (t < t_begin || t > t_end) continue;
        x = x0[g];
        x.head(m) += t * x0[g].tail(m);
        for (int c = 0; c < D; ++c) z[c] = e.normal();
        file.tracks.push_back(sensor.id, number[q], t, x + sd.cwiseProduct(z), P, g);
      }
    }
  }
  return file;
}

void ScaleExperimentOptions::validate() const {
  require(!sizes.empty(), "ScaleExperimentOptions.sizes", "need at least one size");
  for (int32_t n : sizes)
    require(n >= 1, "ScaleExperimentOptions.sizes", "sizes must be >= 1, got " + std::to_string(n));
  require(dense_max >= 0, "ScaleExperimentOptions.dense_max", "must be >= 0");
  require(density > 0 && std::isfinite(density), "ScaleExperimentOptions.density", "must be positive");
  require(gate_probability > 0 && gate_probability < 1, "ScaleExperimentOptions.gate_probability",
          "must be in (0, 1)");
  require(threads >= 0, "ScaleExperimentOptions.threads", "must be >= 0");
  require(tracks.sensors == 3, "ScaleExperimentOptions.tracks.sensors",
          "the scale experiment uses 3 sensors");
  tracks.validate();
}

nlohmann::json ScaleRow::to_json() const {
  return {{"n", n},
          {"tracks", tracks},
          {"candidate_pairs", candidate_pairs},
          {"gated_pairs", gated_pairs},
          {"components", components},
          {"largest_component", largest_component},
          {"stage", stage},
          {"stage_s", stage_s},
          {"stage_peak_mib", stage_peak_mib},
          {"stage_data_mib", stage_data_mib},
          {"total_s", total_s},
          {"peak_mib", peak_mib},
          {"correct_rate", correct_rate},
          {"false_rate", false_rate},
          {"missed_rate", missed_rate},
          {"dense_run", dense_run},
          {"dense_total_s", dense_total_s},
          {"dense_peak_mib", dense_peak_mib},
          {"dense_correct_rate", dense_correct_rate},
          {"dense_identical", dense_identical},
          {"dense_gated_pairs", dense_gated_pairs},
          {"error", error}};
}

ScaleRow ScaleRow::from_json(const nlohmann::json& j) {
  ScaleRow r;
  j.at("n").get_to(r.n);
  j.at("tracks").get_to(r.tracks);
  j.at("candidate_pairs").get_to(r.candidate_pairs);
  j.at("gated_pairs").get_to(r.gated_pairs);
  j.at("components").get_to(r.components);
  j.at("largest_component").get_to(r.largest_component);
  j.at("stage").get_to(r.stage);
  j.at("stage_s").get_to(r.stage_s);
  j.at("stage_peak_mib").get_to(r.stage_peak_mib);
  j.at("stage_data_mib").get_to(r.stage_data_mib);
  j.at("total_s").get_to(r.total_s);
  j.at("peak_mib").get_to(r.peak_mib);
  j.at("correct_rate").get_to(r.correct_rate);
  j.at("false_rate").get_to(r.false_rate);
  j.at("missed_rate").get_to(r.missed_rate);
  j.at("dense_run").get_to(r.dense_run);
  j.at("dense_total_s").get_to(r.dense_total_s);
  j.at("dense_peak_mib").get_to(r.dense_peak_mib);
  j.at("dense_correct_rate").get_to(r.dense_correct_rate);
  j.at("dense_identical").get_to(r.dense_identical);
  j.at("dense_gated_pairs").get_to(r.dense_gated_pairs);
  j.at("error").get_to(r.error);
  return r;
}

namespace {

// One size, in the current process.
ScaleRow run_one_size(const ScaleExperimentOptions& o, int32_t n) {
  std::unique_ptr<tbb::global_control> gc;
  if (o.threads > 0)
    gc = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               static_cast<std::size_t>(o.threads));
  ScaleRow row;
  row.n = n;
  SyntheticTrackSpec spec = o.tracks;
  spec.targets = n;
  spec.box = std::sqrt(n / o.density) * 10000.0;  // density per 100 km² = (10 km)²
  spec.seed = stream_key(o.seed, static_cast<uint64_t>(n));
  const TrackFile file = synthetic_recorded_tracks(spec);

  SparsePipelineOptions so;
  so.pipeline = PipelineOptions::paper();  // the scale study of the χ²(n·D) index (sparse_candidates.hpp)
  so.pipeline.statistic.gate_probability = o.gate_probability;
  // The problem built here (its candidate and component counts are columns of the row), solved
  // through the association interface as `run`'s sparse rows are.
  AssociatorOptions request;
  request.sparse = true;
  request.solver = o.solver;
  request.solver_options = o.solver_options;
  request.seed = o.seed;
  request.pipeline = so.pipeline;
  const auto t0 = std::chrono::steady_clock::now();
  const auto sp =
      std::make_shared<const SparseAssociationProblem>(build_sparse_association_problem(file, so));
  const SparseAssociationProblem& p = *sp;
  const AssociationOutcome out = make_three_sensor_associator(request, {nullptr, sp})->associate(file);
  const AssociationRecord& rec = out.record;
  row.total_s = seconds_since(t0);
  for (const auto& s : out.summary.stages) {
    row.stage.push_back(s.name);
    row.stage_s.push_back(s.seconds);
    row.stage_peak_mib.push_back(s.peak_rss_mib);
    row.stage_data_mib.push_back(s.data_mib);
    row.peak_mib = std::max(row.peak_mib, s.peak_rss_mib);
  }
  for (int d = 0; d < 3; ++d) row.tracks.push_back(p.aligned[d].n_tracks());
  for (std::size_t c : p.candidate_pairs) row.candidate_pairs += static_cast<int64_t>(c);
  row.gated_pairs = static_cast<int64_t>(p.s12.size() + p.s23.size() + p.s13.size());
  row.components = p.components.count;
  for (int32_t c = 0; c < p.components.count; ++c)
    row.largest_component = std::max(row.largest_component, p.components.size(c));
  const AssociationMetrics m = evaluate_association(file.tracks, file.sensors, rec);
  row.correct_rate = m.correct_rate;
  row.false_rate = m.false_rate;
  row.missed_rate = m.missed_rate;

  if (n <= o.dense_max) {
    row.dense_run = true;
    const auto t1 = std::chrono::steady_clock::now();
    const auto dense =
        std::make_shared<const AssociationProblem>(build_association_problem(file, so.pipeline));
    const AssociationProblem& dp = *dense;
    request.sparse = false;
    request.three_d = true;
    const AssociationRecord drec =
        make_three_sensor_associator(request, {dense, nullptr})->associate(file).record;
    row.dense_total_s = seconds_since(t1);
    row.dense_peak_mib = peak_rss_mib();
    row.dense_correct_rate = evaluate_association(file.tracks, file.sensors, drec).correct_rate;
    row.dense_identical = tuple_set(rec) == tuple_set(drec);
    for (const PairStatistic* s : {&dp.s12, &dp.s23, &dp.s13})
      for (uint8_t g : s->in_gate) row.dense_gated_pairs += g;
  }
  return row;
}

ScaleRow run_isolated(const ScaleExperimentOptions& o, int32_t n) {
  int fd[2];
  if (pipe(fd) != 0) return run_one_size(o, n);
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) {
    close(fd[0]);
    close(fd[1]);
    return run_one_size(o, n);
  }
  if (pid == 0) {  // child: run, write one JSON document, exit without unwinding the parent's state
    close(fd[0]);
    std::string out;
    try {
      out = run_one_size(o, n).to_json().dump();
    } catch (const std::exception& e) {
      ScaleRow r;
      r.n = n;
      r.error = e.what();
      out = r.to_json().dump();
    }
    std::size_t off = 0;
    while (off < out.size()) {
      const ssize_t w = write(fd[1], out.data() + off, out.size() - off);
      if (w <= 0) break;
      off += static_cast<std::size_t>(w);
    }
    close(fd[1]);
    _exit(0);
  }
  close(fd[1]);
  std::string in;
  char buf[65536];
  for (ssize_t r; (r = read(fd[0], buf, sizeof buf)) > 0;) in.append(buf, static_cast<std::size_t>(r));
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (in.empty()) {
    ScaleRow r;
    r.n = n;
    r.error = WIFSIGNALED(status)
                  ? "child killed by signal " + std::to_string(WTERMSIG(status)) + " (out of memory?)"
                  : "child produced no result";
    return r;
  }
  return ScaleRow::from_json(nlohmann::json::parse(in));
}

}  // namespace

std::vector<ScaleRow> run_scale_experiment(const ScaleExperimentOptions& options,
                                           const std::function<void(const ScaleRow&)>& progress) {
  options.validate();
  std::vector<int32_t> sizes = options.sizes;
  std::sort(sizes.begin(), sizes.end());
  std::vector<ScaleRow> rows;
  for (int32_t n : sizes) {
    ScaleRow r;
    if (options.isolate) {
      r = run_isolated(options, n);
    } else {
      try {
        r = run_one_size(options, n);
      } catch (const InputError& e) {
        r.n = n;
        r.error = e.what();
      }
    }
    rows.push_back(r);
    if (progress) progress(rows.back());
  }
  return rows;
}

double scaling_exponent(const std::vector<ScaleRow>& rows, int32_t n_min) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int c = 0;
  for (const auto& r : rows)
    if (r.error.empty() && r.n >= n_min && r.total_s > 0) {
      const double x = std::log(r.n), y = std::log(r.total_s);
      sx += x, sy += y, sxx += x * x, sxy += x * y, ++c;
    }
  if (c < 2) return std::numeric_limits<double>::quiet_NaN();
  return (c * sxy - sx * sy) / (c * sxx - sx * sx);
}

std::string scale_table(const std::vector<ScaleRow>& rows) {
  std::ostringstream os;
  char line[512];
  std::snprintf(line, sizeof line, "%7s %9s %9s %8s %8s %8s %8s %8s %8s %8s %9s %8s %8s %8s %5s\n", "n",
                "cand", "gated", "comps", "align_s", "cand_s", "stat_s", "clust_s", "solve_s", "total_s",
                "peak_MiB", "correct", "dense_s", "dense_ok", "same");
  os << line;
  for (const auto& r : rows) {
    if (!r.error.empty()) {
      os << std::string(7 - std::min<std::size_t>(7, std::to_string(r.n).size()), ' ') << r.n
         << "  error: " << r.error << "\n";
      continue;
    }
    auto st = [&](const char* name) {
      for (std::size_t q = 0; q < r.stage.size(); ++q)
        if (r.stage[q] == name) return r.stage_s[q];
      return 0.0;
    };
    std::snprintf(line, sizeof line, "%7d %9lld %9lld %8d %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f %9.0f %7.1f%% ",
                  r.n, static_cast<long long>(r.candidate_pairs), static_cast<long long>(r.gated_pairs),
                  r.components, st("alignment"), st("candidates"), st("statistics"), st("components"),
                  st("solve"), r.total_s, r.peak_mib, 100.0 * r.correct_rate);
    os << line;
    if (r.dense_run) {
      std::snprintf(line, sizeof line, "%8.3f %7.1f%% %5s\n", r.dense_total_s, 100.0 * r.dense_correct_rate,
                    r.dense_identical ? "yes" : "NO");
    } else {
      std::snprintf(line, sizeof line, "%8s %8s %5s\n", "-", "-", "-");
    }
    os << line;
  }
  return os.str();
}

nlohmann::json ScaleExperimentOptions::to_json() const {
  return {{"sizes", sizes},
          {"dense_max", dense_max},
          {"solver", solver},
          {"solver_options", solver_options},
          {"density_per_100km2", density},
          {"gate_probability", gate_probability},
          {"duration", tracks.duration},
          {"sigma_pos", tracks.sigma_pos},
          {"p_seen", tracks.p_seen},
          {"min_lifetime_fraction", tracks.min_lifetime_fraction},
          {"three_d", tracks.three_d},
          {"seed", seed},
          {"threads", threads}};
}

void write_scale_outputs(const std::string& dir, const std::vector<ScaleRow>& rows,
                         const ScaleExperimentOptions& options, double slope) {
  write_atomically(dir + "/scale.csv",
                   [&](const std::string& tmp) { std::ofstream(tmp) << scale_csv(rows); });
  nlohmann::json j = {
      {"options", options.to_json()}, {"loglog_slope_n_ge_1000", slope}, {"rows", nlohmann::json::array()}};
  for (const auto& r : rows) j["rows"].push_back(r.to_json());
  write_atomically(dir + "/scale.json",
                   [&](const std::string& tmp) { std::ofstream(tmp) << j.dump(1) << "\n"; });
  write_scale_h5(dir + "/scale.h5", rows, j["options"], slope);
}

std::string scale_csv(const std::vector<ScaleRow>& rows) {
  std::ostringstream os;
  os << "n,tracks1,tracks2,tracks3,candidate_pairs,gated_pairs,components,largest_component";
  const std::vector<std::string> stages{"alignment", "candidates", "statistics", "components", "solve"};
  for (const auto& s : stages) os << "," << s << "_s," << s << "_peak_mib," << s << "_data_mib";
  os << ",total_s,peak_mib,correct_rate,false_rate,missed_rate,dense_total_s,dense_peak_mib,dense_correct_"
        "rate,"
        "dense_identical,dense_gated_pairs,error\n";
  for (const auto& r : rows) {
    os << r.n;
    for (int d = 0; d < 3; ++d) os << "," << (d < static_cast<int>(r.tracks.size()) ? r.tracks[d] : 0);
    os << "," << r.candidate_pairs << "," << r.gated_pairs << "," << r.components << ","
       << r.largest_component;
    for (const auto& s : stages) {
      double t = NAN, pk = NAN, dm = NAN;
      for (std::size_t q = 0; q < r.stage.size(); ++q)
        if (r.stage[q] == s) t = r.stage_s[q], pk = r.stage_peak_mib[q], dm = r.stage_data_mib[q];
      os << "," << t << "," << pk << "," << dm;
    }
    os << "," << r.total_s << "," << r.peak_mib << "," << r.correct_rate << "," << r.false_rate << ","
       << r.missed_rate;
    if (r.dense_run)
      os << "," << r.dense_total_s << "," << r.dense_peak_mib << "," << r.dense_correct_rate << ","
         << (r.dense_identical ? 1 : 0) << "," << r.dense_gated_pairs;
    else
      os << ",,,,,";
    std::string err = r.error;
    std::replace(err.begin(), err.end(), ',', ';');
    std::replace(err.begin(), err.end(), '\n', ' ');
    os << "," << err << "\n";
  }
  return os.str();
}

void write_scale_h5(const std::string& path, const std::vector<ScaleRow>& rows, const nlohmann::json& options,
                    double loglog_slope) {
  static const char* const kStages[5] = {"alignment", "candidates", "statistics", "components", "solve"};
  const hsize_t K = rows.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<int32_t> n, tracks, components, largest, dense_run, dense_identical, ok;
  std::vector<double> candidates, gated, stage_s, stage_peak, stage_data, total, peak, correct, false_rate,
      missed, dense_total, dense_peak, dense_correct, dense_gated;
  nlohmann::json errors = nlohmann::json::array();
  for (const ScaleRow& r : rows) {
    const bool good = r.error.empty();
    n.push_back(r.n);
    for (int d = 0; d < 3; ++d) tracks.push_back(d < static_cast<int>(r.tracks.size()) ? r.tracks[d] : 0);
    components.push_back(r.components);
    largest.push_back(r.largest_component);
    candidates.push_back(good ? static_cast<double>(r.candidate_pairs) : nan);
    gated.push_back(good ? static_cast<double>(r.gated_pairs) : nan);
    for (const char* name : kStages) {
      double t = nan, pk = nan, dm = nan;
      for (std::size_t q = 0; q < r.stage.size(); ++q)
        if (r.stage[q] == name) t = r.stage_s[q], pk = r.stage_peak_mib[q], dm = r.stage_data_mib[q];
      stage_s.push_back(t);
      stage_peak.push_back(pk);
      stage_data.push_back(dm);
    }
    total.push_back(good ? r.total_s : nan);
    peak.push_back(good ? r.peak_mib : nan);
    correct.push_back(good ? r.correct_rate : nan);
    false_rate.push_back(good ? r.false_rate : nan);
    missed.push_back(good ? r.missed_rate : nan);
    dense_run.push_back(r.dense_run ? 1 : 0);
    dense_total.push_back(r.dense_run ? r.dense_total_s : nan);
    dense_peak.push_back(r.dense_run ? r.dense_peak_mib : nan);
    dense_correct.push_back(r.dense_run ? r.dense_correct_rate : nan);
    dense_gated.push_back(r.dense_run ? static_cast<double>(r.dense_gated_pairs) : nan);
    dense_identical.push_back(r.dense_run ? (r.dense_identical ? 1 : 0) : -1);
    ok.push_back(good ? 1 : 0);
    errors.push_back(r.error);
  }
  write_atomically(path, [&](const std::string& tmp) {
    h5::File f = h5::File::create(tmp);
    {
      const h5::Group root = f.root();
      write_experiment_header(root, "scale");
      root.write_attribute("options", options.dump());
      root.write_attribute("loglog_slope_n_ge_1000", loglog_slope);
      const h5::Group g = root.create_group("scale");
      auto ints = [&](const char* name, const std::vector<int32_t>& v, hsize_t cols = 1) {
        g.write_dataset(name, std::span<const int32_t>(v),
                        cols == 1 ? std::vector<hsize_t>{K} : std::vector<hsize_t>{K, cols});
      };
      auto doubles = [&](const char* name, const std::vector<double>& v, hsize_t cols = 1) {
        g.write_dataset(name, std::span<const double>(v),
                        cols == 1 ? std::vector<hsize_t>{K} : std::vector<hsize_t>{K, cols});
      };
      ints("n", n);
      ints("tracks", tracks, 3);
      ints("components", components);
      ints("largest_component", largest);
      doubles("candidate_pairs", candidates);
      doubles("gated_pairs", gated);
      doubles("stage_s", stage_s, 5);
      doubles("stage_peak_mib", stage_peak, 5);
      doubles("stage_data_mib", stage_data, 5);
      doubles("total_s", total);
      doubles("peak_mib", peak);
      doubles("correct_rate", correct);
      doubles("false_rate", false_rate);
      doubles("missed_rate", missed);
      ints("dense_run", dense_run);
      doubles("dense_total_s", dense_total);
      doubles("dense_peak_mib", dense_peak);
      doubles("dense_correct_rate", dense_correct);
      doubles("dense_gated_pairs", dense_gated);
      ints("dense_identical", dense_identical);
      ints("ok", ok);
      g.write_attribute("stages", std::string("alignment,candidates,statistics,components,solve"));
      g.write_attribute("errors", errors.dump());
    }
    f.close();
  });
}

}  // namespace trackassoc
