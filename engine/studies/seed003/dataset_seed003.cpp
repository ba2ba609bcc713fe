// Seed 003 simulation and pair data set (see dataset_seed003.hpp).
#include "engine/studies/seed003/dataset_seed003.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <numeric>
#include <unordered_map>

#include "engine/simulation/simulation_truth.hpp"
#include "io/json_input.hpp"
#include "io/memory_budget.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/random.hpp"

namespace trackassoc {
namespace {

// Random streams (the third key of CounterRng).
constexpr uint64_t kStreamMotion = 1, kStreamRadar1 = 2, kStreamRadar2 = 3, kStreamPairs = 4;

// Truth of one target: the simulator's closed-form trajectory (engine/simulation/simulation_truth.hpp), and
// its positions at the whole seconds n = 0..N for the close-negative distance.
struct Trajectory {
  TargetTrajectory path;
  std::vector<double> x, y;  // at whole seconds
  void position(double t, double& px, double& py) const {
    const Kinematics k = path.at(t);
    px = k.p[0];
    py = k.p[1];
  }
};

// seed 003 §3.1: random initial position, speed and heading, then a random heading and speed change
// every second, flown by the simulator's MotionModel::kRandomManoeuvre (one constant-acceleration
// piece per second taking the old velocity to the new one, so position and velocity are continuous).
Trajectory fly(const Seed003Options& o, uint64_t run, int target) {
  CounterRng rng(o.seed, run, static_cast<uint64_t>(target), kStreamMotion);
  TargetSpec spec;
  spec.id = target;
  const double x = rng.uniform(0, o.area), y = rng.uniform(0, o.area);
  const double speed = rng.uniform(o.speed_min, o.speed_max);
  const double heading = rng.uniform(0, 2 * std::numbers::pi);
  spec.initial_state = {x, y, 0.0, speed * std::cos(heading), speed * std::sin(heading), 0.0};
  MotionSegment seg;
  seg.model = MotionModel::kRandomManoeuvre;
  seg.duration = o.duration;
  seg.manoeuvre_period = 1.0;
  seg.max_turn_rate = o.max_heading_change;  // [rad/s] × 1 s period = Δψ per manoeuvre
  seg.max_speed_change = o.max_speed_change;
  seg.speed_min = o.speed_min;
  seg.speed_max = o.speed_max;
  spec.segments.push_back(seg);
  Trajectory tr;
  tr.path = scripted_trajectory(spec, o.duration, 2, rng);
  const int seconds = static_cast<int>(std::ceil(o.duration));
  for (int n = 0; n <= seconds; ++n) {
    const Kinematics k = tr.path.at(n);
    tr.x.push_back(k.p[0]);
    tr.y.push_back(k.p[1]);
  }
  return tr;
}

// Converted plots of one target by one radar: range/bearing with Gaussian errors, back to (x, y).
void observe(const Seed003Options& o, uint64_t run, int target, int radar, const Trajectory& tr,
             std::vector<double>& x, std::vector<double>& y, std::vector<double>& t) {
  CounterRng rng(o.seed, run, static_cast<uint64_t>(target), radar == 1 ? kStreamRadar1 : kStreamRadar2);
  const double period = radar == 1 ? o.period1 : o.period2;
  const double rx = radar == 1 ? o.radar1_x : o.radar2_x, ry = radar == 1 ? o.radar1_y : o.radar2_y;
  const double sb = o.sigma_bearing_deg * std::numbers::pi / 180.0;
  const double phase = rng.uniform(0, period);
  for (double time = phase; time <= o.duration; time += period) {
    double px, py;
    tr.position(time, px, py);
    const double range = std::hypot(px - rx, py - ry) + rng.normal(0, o.sigma_range);
    const double bearing = std::atan2(py - ry, px - rx) + rng.normal(0, sb);
    x.push_back(rx + range * std::cos(bearing));
    y.push_back(ry + range * std::sin(bearing));
    t.push_back(time);
  }
}

double mean_distance(const Trajectory& a, const Trajectory& b) {
  double s = 0;
  for (std::size_t n = 0; n < a.x.size(); ++n) s += std::hypot(a.x[n] - b.x[n], a.y[n] - b.y[n]);
  return s / double(a.x.size());
}

struct SceneWithTruth {
  Seed003Scene scene;
  std::vector<Trajectory> truth;
};

SceneWithTruth simulate(const Seed003Options& o, int count, uint64_t run) {
  // Per target and second: a trajectory piece and a truth sample; per plot (x, y, t) twice (the
  // per-target vectors, then the scene's columns).
  const double seconds = std::ceil(o.duration) + 1.0;
  const double plots = o.duration / o.period1 + o.duration / o.period2 + 2.0;
  const double per_target = seconds * (sizeof(Kinematics) + 16.0) + plots * 48.0 + 8 * 24.0;
  char what[160];
  std::snprintf(what, sizeof what, "the seed 003 scene (%d targets × %g s; see --targets)", count,
                o.duration);
  require_memory(bytes_of(per_target * count, 1), what);
  SceneWithTruth out;
  out.truth.resize(count);
  std::vector<std::vector<double>> px1(count), py1(count), pt1(count), px2(count), py2(count), pt2(count);
  parallel_for_range(static_cast<std::size_t>(count), 256, [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) {
      const int i = static_cast<int>(k);
      out.truth[k] = fly(o, run, i);
      observe(o, run, i, 1, out.truth[k], px1[k], py1[k], pt1[k]);
      observe(o, run, i, 2, out.truth[k], px2[k], py2[k], pt2[k]);
    }
  });
  auto append = [](TrackSequences& tr, const std::vector<double>& x, const std::vector<double>& y,
                   const std::vector<double>& t) {
    tr.x.insert(tr.x.end(), x.begin(), x.end());
    tr.y.insert(tr.y.end(), y.begin(), y.end());
    tr.t.insert(tr.t.end(), t.begin(), t.end());
    tr.offset.push_back(static_cast<int64_t>(tr.x.size()));
  };
  for (int k = 0; k < count; ++k) {
    append(out.scene.radar1, px1[k], py1[k], pt1[k]);
    append(out.scene.radar2, px2[k], py2[k], pt2[k]);
    out.scene.target1.push_back(k);
    out.scene.target2.push_back(k);
  }
  return out;
}

}  // namespace

void Seed003Options::validate() const {
  require(targets >= 2 && targets <= 10000000, "Seed003Options.targets",
          "must be in [2, 1e7], got " + std::to_string(targets));
  require(area > 0 && std::isfinite(area), "Seed003Options.area", "must be finite and > 0");
  require(speed_min > 0 && speed_max >= speed_min && std::isfinite(speed_max),
          "Seed003Options.speed_min/speed_max", "need 0 < speed_min <= speed_max");
  require(duration >= 1 && duration <= 3600, "Seed003Options.duration", "must be in [1, 3600] s");
  require(max_heading_change >= 0 && max_heading_change <= std::numbers::pi,
          "Seed003Options.max_heading_change", "must be in [0, π]");
  require(max_speed_change >= 0 && std::isfinite(max_speed_change), "Seed003Options.max_speed_change",
          "must be >= 0");
  require(sigma_range >= 0 && std::isfinite(sigma_range), "Seed003Options.sigma_range", "must be >= 0");
  require(sigma_bearing_deg >= 0 && sigma_bearing_deg < 90, "Seed003Options.sigma_bearing_deg",
          "must be in [0, 90)");
  require(period1 > 0 && period1 <= duration, "Seed003Options.period1", "must be in (0, duration]");
  require(period2 > 0 && period2 <= duration, "Seed003Options.period2", "must be in (0, duration]");
  require(positives >= 0 && positives <= targets, "Seed003Options.positives", "must be in [0, targets]");
  require(random_negatives >= 0, "Seed003Options.random_negatives", "must be >= 0");
  require(close_negatives >= 0 && close_negatives <= targets, "Seed003Options.close_negatives",
          "must be in [0, targets]");
  require(close_distance > 0 && std::isfinite(close_distance), "Seed003Options.close_distance",
          "must be > 0");
  require(train_fraction > 0 && train_fraction < 1, "Seed003Options.train_fraction", "must be in (0, 1)");
}

std::string Seed003Options::to_json() const {
  nlohmann::json j = {{"targets", targets},
                      {"area_m", area},
                      {"speed_min", speed_min},
                      {"speed_max", speed_max},
                      {"duration_s", duration},
                      {"max_heading_change_rad", max_heading_change},
                      {"max_speed_change_mps", max_speed_change},
                      {"radar1", {radar1_x, radar1_y}},
                      {"radar2", {radar2_x, radar2_y}},
                      {"sigma_range_m", sigma_range},
                      {"sigma_bearing_deg", sigma_bearing_deg},
                      {"period1_s", period1},
                      {"period2_s", period2},
                      {"positives", positives},
                      {"random_negatives", random_negatives},
                      {"close_negatives", close_negatives},
                      {"close_distance_m", close_distance},
                      {"close_measure", close_measure == CloseMeasure::kMeanDistance ? "mean" : "start"},
                      {"train_fraction", train_fraction},
                      {"seed", seed}};
  return j.dump();
}

Seed003Options seed003_scene_of(const std::string& generator_json, Seed003Options o,
                                const std::string& source) {
  const auto j = parse_json_input(generator_json, source + ": seed 003 generator options");
  require(j.is_object(), source, "the seed 003 generator options are not a JSON object");
  try {
    auto number = [&](const char* key, double& v) {
      if (j.contains(key)) v = j.at(key).get<double>();
    };
    auto point = [&](const char* key, double& x, double& y) {
      if (j.contains(key)) x = j.at(key).at(0).get<double>(), y = j.at(key).at(1).get<double>();
    };
    point("radar1", o.radar1_x, o.radar1_y);
    point("radar2", o.radar2_x, o.radar2_y);
    number("sigma_range_m", o.sigma_range);
    number("sigma_bearing_deg", o.sigma_bearing_deg);
    number("period1_s", o.period1);
    number("period2_s", o.period2);
    number("area_m", o.area);
    number("speed_min", o.speed_min);
    number("speed_max", o.speed_max);
    number("duration_s", o.duration);
    number("max_heading_change_rad", o.max_heading_change);
    number("max_speed_change_mps", o.max_speed_change);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(source + ": malformed seed 003 generator options: " + e.what());
  }
  o.validate();
  return o;
}

Seed003Scene simulate_seed003_scene(const Seed003Options& options, int count, uint64_t run) {
  options.validate();
  require(count >= 1, "count", "must be >= 1");
  // Run 0 is the training data set; scenes use run + 1 so they never repeat its targets.
  return simulate(options, count, run + 1).scene;
}

Seed003Dataset generate_seed003_dataset(const Seed003Options& o) {
  o.validate();
  SceneWithTruth sim = simulate(o, o.targets, 0);
  Seed003Dataset d;
  d.radar1 = std::move(sim.scene.radar1);
  d.radar2 = std::move(sim.scene.radar2);
  d.target1 = std::move(sim.scene.target1);
  d.target2 = std::move(sim.scene.target2);

  struct Pair {
    int32_t left, right;
    uint8_t label, kind;
  };
  std::vector<Pair> pairs;
  CounterRng rng(o.seed, 0, 0, kStreamPairs);
  // Positives: the first `positives` targets of a random order.
  std::vector<int32_t> order(o.targets);
  std::iota(order.begin(), order.end(), 0);
  rng.shuffle(std::span<int32_t>(order));
  for (int k = 0; k < o.positives; ++k) pairs.push_back({order[k], order[k], 1, 0});
  for (int k = 0; k < o.random_negatives; ++k) {
    const auto i = static_cast<int32_t>(rng.uniform_int(o.targets));
    auto j = static_cast<int32_t>(rng.uniform_int(o.targets - 1));
    if (j >= i) ++j;
    pairs.push_back({i, j, 0, 1});
  }
  // Close negatives: candidates from a grid of cell close_distance on the positions at the grid time
  // (mid-flight for the mean distance, the start for the start distance). Every target is checked,
  // so close_candidates is the number of targets that have a close partner at all.
  const bool by_mean = o.close_measure == CloseMeasure::kMeanDistance;
  const int at = by_mean ? static_cast<int>(sim.truth[0].x.size()) / 2 : 0;
  const double cell = o.close_distance;
  auto key = [](int64_t cx, int64_t cy) { return (cx << 32) ^ (cy & 0xffffffff); };
  auto cell_of = [&](int32_t i) {
    return std::pair{static_cast<int64_t>(std::floor(sim.truth[i].x[at] / cell)),
                     static_cast<int64_t>(std::floor(sim.truth[i].y[at] / cell))};
  };
  std::unordered_map<int64_t, std::vector<int32_t>> grid;
  for (int32_t i = 0; i < o.targets; ++i) {
    const auto [cx, cy] = cell_of(i);
    grid[key(cx, cy)].push_back(i);
  }
  rng.shuffle(std::span<int32_t>(order));
  int found = 0, candidates = 0;
  for (int32_t i : order) {
    const auto [cx, cy] = cell_of(i);
    double best = o.close_distance;
    int32_t best_j = -1;
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy) {
        const auto it = grid.find(key(cx + dx, cy + dy));
        if (it == grid.end()) continue;
        for (int32_t j : it->second) {
          if (j == i) continue;
          const double dist = by_mean ? mean_distance(sim.truth[i], sim.truth[j])
                                      : std::hypot(sim.truth[i].x[0] - sim.truth[j].x[0],
                                                   sim.truth[i].y[0] - sim.truth[j].y[0]);
          if (dist < best) best = dist, best_j = j;
        }
      }
    if (best_j < 0) continue;
    ++candidates;
    if (found < o.close_negatives) {
      pairs.push_back({i, best_j, 0, 2});
      ++found;
    }
  }
  // Shuffle and split.
  rng.shuffle(std::span<Pair>(pairs));
  const std::size_t n_train = static_cast<std::size_t>(std::llround(o.train_fraction * double(pairs.size())));
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    PairSet& set = k < n_train ? d.train : d.test;
    auto& kind = k < n_train ? d.train_kind : d.test_kind;
    set.left.push_back(pairs[k].left);
    set.right.push_back(pairs[k].right);
    set.label.push_back(pairs[k].label);
    kind.push_back(pairs[k].kind);
  }
  nlohmann::json j = nlohmann::json::parse(o.to_json());
  j["close_negatives_found"] = found;
  j["close_candidates"] = candidates;
  j["pairs_total"] = pairs.size();
  j["note"] =
      "tracks are sequences of converted plots (x, y, t) per radar per target; see "
      "engine/studies/seed003/dataset_seed003.hpp";
  d.generator_json = j.dump();
  return d;
}

}  // namespace trackassoc
