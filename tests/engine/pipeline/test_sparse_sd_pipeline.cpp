// The default pipeline for recorded track sets (engine/pipeline/sparse_sd_pipeline.hpp) and its candidate
// index (kernels/statistics/scan_candidates.hpp), against independent computations:
//  * the per-scan index and the position-bound pruning are lossless: they return every pair the
//    dense statistic gates in, and the index equals its O(n²) scan;
//  * the association equals a brute-force optimum over all groupings of the tracks, with the
//    tuple cost written from the dense statistic of every pair;
//  * on the realistic-recording family the default reaches the targets, the CLI uses every
//    sensor, and bad input is exit 2 with one line and no output.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>

#include "engine/pipeline/associator.hpp"
#include "engine/pipeline/associator_fields.hpp"
#include "engine/pipeline/metrics.hpp"
#include "engine/pipeline/pipeline_sd.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "io/track_file.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/statistics/gate_candidates.hpp"
#include "tests/support/cli_runner.hpp"

namespace trackassoc {
namespace {

using testing_support::CliFixture;
using testing_support::CliResult;

TrackFile simulate_file(const std::string& scenario, int run = 0, int targets = -1) {
  Scenario sc = load_scenario(scenario);
  if (targets >= 0) sc.random_targets.count = targets;
  return simulation_to_track_file(sc, simulate(sc, 1, run));
}

std::set<std::pair<int32_t, int32_t>> as_set(const CandidatePairs& c) {
  std::set<std::pair<int32_t, int32_t>> s;
  for (std::size_t q = 0; q < c.size(); ++q) s.insert({c.a[q], c.b[q]});
  return s;
}

// The rows of `t` for which keep(row) holds.
TrackTable keep_rows(const TrackTable& t, const std::function<bool(std::size_t)>& keep) {
  TrackTable out(t.layout);
  for (std::size_t r = 0; r < t.size(); ++r)
    if (keep(r)) out.push_back(t.sensor[r], t.track[r], t.t[r], t.state_at(r), t.cov_at(r), t.truth[r]);
  return out;
}

// A recorded_sync file cut so that sensor 0 reports only before t = 20 s and sensor 1 only after
// t = 40 s (sensor 2 removed): no two tracks of different sensors ever coexist.
TrackFile tracks_never_together() {
  TrackFile f = simulate_file("recorded_sync");
  f.tracks = keep_rows(f.tracks, [&](std::size_t r) {
    return (f.tracks.sensor[r] == 0 && f.tracks.t[r] < 20.0) ||
           (f.tracks.sensor[r] == 1 && f.tracks.t[r] > 40.0);
  });
  f.sensors.pop_back();
  f.measurements.reset();
  f.truth.reset();
  return f;
}

TEST(ScanCandidates, LosslessAgainstTheDenseGateAndEqualToTheNaiveScan) {
  for (const char* name : {"recorded_3s", "recorded_dense", "recorded_formation"}) {
    const TrackFile file = simulate_file(name);
    const PipelineOptions po;
    const std::vector<int32_t> ids{file.sensors[0].id, file.sensors[1].id, file.sensors[2].id};
    const std::vector<double> grid = common_time_grid(file.tracks, ids, file.sensors[2].period, true);
    const AlignedTracks a = align_tracks(file.tracks, ids[0], grid, po.alignment);
    const AlignedTracks b = align_tracks(file.tracks, ids[2], grid, po.alignment);
    const double cap = SequentialGate(a.dim, po.statistic).cap();
    const CandidatePairs fast = scan_candidate_pairs(a, b, cap);
    EXPECT_EQ(as_set(fast), as_set(scan_candidate_pairs_all_pairs(a, b, cap))) << name;
    const auto pruned = as_set(prune_by_position_bound(a, b, fast, po.statistic));
    const PairStatistic dense = independent_sequential_statistic(a, b, po.statistic);
    int gated = 0;
    for (int32_t i = 0; i < a.n_tracks(); ++i)
      for (int32_t j = 0; j < b.n_tracks(); ++j)
        if (dense.in_gate[static_cast<std::size_t>(i) * b.n_tracks() + j]) {
          ++gated;
          EXPECT_TRUE(pruned.count({i, j})) << name << ": gated pair " << i << "," << j << " lost";
        }
    EXPECT_GT(gated, 5) << name;
    EXPECT_LT(pruned.size(), static_cast<std::size_t>(a.n_tracks()) * b.n_tracks() / 2) << name;
  }
}

// One track with a covariance 10^8 times the others' (a just-initialised or far track): the grid
// is sized by the median radius, the wide query reads every point, and the result is still the
// naive scan's.
TEST(ScanCandidates, AWideCovarianceAmongSmallOnesGivesTheNaiveResult) {
  auto make = [](int32_t sensor, uint64_t seed) {
    AlignedTracks x;
    x.sensor = sensor;
    x.dim = 4;
    x.n_times = 3;
    CounterRng rng(seed, 0, 0);
    for (int32_t i = 0; i < 300; ++i) {
      x.track.push_back(i);
      x.truth.push_back(i);
      for (int k = 0; k < 3; ++k) {
        x.valid.push_back(k != 1 || i % 3 != 0);
        const double px = rng.uniform(0.0, 1e5), py = rng.uniform(0.0, 1e5);
        for (double v : {px, py, 100.0, 0.0}) x.state.push_back(v);
        const double var = i == 7 ? 1e12 : 1e4 * (1.0 + (i % 5));
        for (double v : {var, 0.0, 0.0, 0.0, var, 0.0, 0.0, 1.0, 0.0, 1.0}) x.cov.push_back(v);
      }
    }
    x.span_begin.assign(x.track.size(), 0);  // every track over the 3 common times
    for (std::size_t i = 0; i <= x.track.size(); ++i) x.span_offset.push_back(3 * static_cast<int64_t>(i));
    return x;
  };
  const AlignedTracks a = make(0, 1), b = make(1, 2);
  for (double cap : {1.0, 18.47}) {
    const CandidatePairs fast = scan_candidate_pairs(a, b, cap);
    EXPECT_EQ(as_set(fast), as_set(scan_candidate_pairs_all_pairs(a, b, cap))) << cap;
    int wide = 0;
    for (std::size_t q = 0; q < fast.size(); ++q) wide += fast.a[q] == 7 || fast.b[q] == 7;
    EXPECT_GT(wide, 250) << cap;  // the wide track is near everything
  }
}

// Brute force: every grouping of the tracks into tuples with at most one track per sensor, cost
// from the dense statistic (link (λ − G(n))/f when gated in; a tested pair outside the gate
// forbids the tuple; pairs never together are neutral; members connected through gated pairs).
// The link is rival-weighted as the pipeline's (rival_link_costs, κ = rival_exponent): G at
// probability max(1/2, 1 − (1 − p)·m^κ), m counted here from the dense gate and the tracks' valid
// common times.
double brute_force_optimum(const TrackFile& file, const PipelineOptions& po,
                           const std::vector<int32_t>& keep_tracks, double rival_exponent = 2.0) {
  std::vector<int32_t> ids;
  for (const auto& s : file.sensors) ids.push_back(s.id);
  double period = 0.0;
  for (const auto& s : file.sensors) period = std::max(period, s.period);
  const std::vector<double> grid = common_time_grid(file.tracks, ids, period, true);
  std::vector<AlignedTracks> al;
  for (int32_t id : ids) al.push_back(align_tracks(file.tracks, id, grid, po.alignment));
  struct Node {
    int32_t s, i;
  };
  std::vector<Node> nodes;
  for (int32_t s = 0; s < static_cast<int32_t>(al.size()); ++s)
    for (int32_t i = 0; i < al[s].n_tracks(); ++i)
      if (std::find(keep_tracks.begin(), keep_tracks.end(), al[s].truth[i]) != keep_tracks.end())
        nodes.push_back({s, i});
  const std::size_t N = nodes.size();
  std::vector<std::vector<double>> link(N, std::vector<double>(N, 0.0));
  std::vector<std::vector<int>> kind(N, std::vector<int>(N, 0));  // 1 gated, -1 forbidden, 0 neutral
  std::vector<std::vector<double>> lambda(N, std::vector<double>(N, 0.0));
  std::vector<std::vector<int32_t>> scans(N, std::vector<int32_t>(N, 0));
  for (std::size_t x = 0; x < N; ++x)
    for (std::size_t y = x + 1; y < N; ++y) {
      if (nodes[x].s == nodes[y].s) continue;
      const auto& A = al[nodes[x].s];
      const auto& B = al[nodes[y].s];
      AlignedTracks one = A, two = B;  // the pair alone, through the dense kernel
      auto keep_one = [](AlignedTracks& t, int32_t i) {
        const int D = t.dim, P = packed_size(D);
        const int64_t o = t.span_offset[i], n = t.span(i).size();
        std::vector<double> st(t.state.begin() + o * D, t.state.begin() + (o + n) * D);
        std::vector<double> cv(t.cov.begin() + o * P, t.cov.begin() + (o + n) * P);
        std::vector<uint8_t> va(t.valid.begin() + o, t.valid.begin() + o + n);
        t.state = st, t.cov = cv, t.valid = va, t.track = {t.track[i]}, t.truth = {t.truth[i]};
        t.span_begin = {t.span_begin[i]}, t.span_offset = {0, n};
      };
      keep_one(one, nodes[x].i);
      keep_one(two, nodes[y].i);
      const PairStatistic ps = independent_sequential_statistic(one, two, po.statistic);
      if (ps.in_gate[0]) {
        kind[x][y] = kind[y][x] = 1;
        lambda[x][y] = lambda[y][x] = ps.lambda[0];
        scans[x][y] = scans[y][x] = ps.dof[0] / one.dim;
      } else if (ps.dof[0] > 0) {
        kind[x][y] = kind[y][x] = -1;
      }
    }
  // Each track's first and last valid common time; rivals of (x, y): y's sensor's tracks gated
  // with x whose valid times meet y's, and the same from y's side.
  std::vector<std::pair<int64_t, int64_t>> valid(N, {-1, -1});
  for (std::size_t x = 0; x < N; ++x) {
    const auto& t = al[nodes[x].s];
    const int64_t o = t.span_offset[nodes[x].i], n = t.span_offset[nodes[x].i + 1] - o;
    for (int64_t c = 0; c < n; ++c)
      if (t.valid[o + c]) {
        const int64_t k = t.span_begin[nodes[x].i] + c;
        if (valid[x].first < 0) valid[x].first = k;
        valid[x].second = k;
      }
  }
  auto meet = [&](std::size_t u, std::size_t v) {
    return valid[u].first >= 0 && valid[v].first >= 0 &&
           std::max(valid[u].first, valid[v].first) <= std::min(valid[u].second, valid[v].second);
  };
  auto rivals = [&](std::size_t x, std::size_t y) {  // x's partners on y's sensor that meet y
    int m = 0;
    for (std::size_t z = 0; z < N; ++z)
      m += nodes[z].s == nodes[y].s && kind[x][z] == 1 && (z == y || meet(z, y));
    return m;
  };
  for (std::size_t x = 0; x < N; ++x)
    for (std::size_t y = 0; y < N; ++y) {
      if (kind[x][y] != 1) continue;
      const int m = std::max(rivals(x, y), rivals(y, x));
      StatisticOptions so = po.statistic;
      so.gate_probability =
          std::max(0.5, 1.0 - (1.0 - so.gate_probability) * std::pow(static_cast<double>(m), rival_exponent));
      link[x][y] = SequentialGate(al[0].dim, so).link_cost(lambda[x][y], scans[x][y]);
    }
  auto tuple_cost = [&](const std::vector<std::size_t>& m) {
    if (m.size() <= 1) return 0.0;
    double c = 0.0;
    std::vector<int> comp(m.size());
    for (std::size_t x = 0; x < m.size(); ++x) comp[x] = static_cast<int>(x);
    for (std::size_t x = 0; x < m.size(); ++x)
      for (std::size_t y = x + 1; y < m.size(); ++y) {
        if (kind[m[x]][m[y]] < 0) return std::numeric_limits<double>::infinity();
        if (kind[m[x]][m[y]] == 1) {
          c += link[m[x]][m[y]];
          const int from = comp[y], to = comp[x];
          for (auto& v : comp)
            if (v == from) v = to;
        }
      }
    for (int v : comp)
      if (v != comp[0]) return std::numeric_limits<double>::infinity();
    return c;
  };
  double best = std::numeric_limits<double>::infinity();
  std::vector<std::vector<std::size_t>> groups;
  std::function<void(std::size_t, double)> rec = [&](std::size_t k, double acc) {
    if (k == N) {
      double total = 0.0;
      for (const auto& g : groups) total += tuple_cost(g);
      best = std::min(best, total);
      return;
    }
    for (std::size_t gi = 0; gi < groups.size(); ++gi) {  // by index: rec() grows `groups`
      bool clash = false;
      for (std::size_t u : groups[gi]) clash |= nodes[u].s == nodes[k].s;
      if (clash) continue;
      groups[gi].push_back(k);
      rec(k + 1, acc);
      groups[gi].pop_back();
    }
    groups.push_back({k});
    rec(k + 1, acc);
    groups.pop_back();
  };
  rec(0, 0.0);
  return best;
}

// recorded_formation's run with the tracks of targets 0..3 only (no false tracks).
TrackFile formation_of_four(int run) {
  TrackFile file = simulate_file("recorded_formation", run);
  const std::vector<int32_t> keep{0, 1, 2, 3};
  file.tracks = keep_rows(file.tracks, [&](std::size_t r) {
    return std::find(keep.begin(), keep.end(), file.tracks.truth[r]) != keep.end();
  });
  return file;
}

TEST(SparseSDPipeline, EqualsTheBruteForceOptimumOverAllGroupings) {
  // A formation (3 members 400 m apart) and a fourth target: one component of ~12 tracks, with
  // partial lifetimes and unequal counts.
  for (int run = 0; run < 3; ++run) {
    const TrackFile file = formation_of_four(run);
    const double brute = brute_force_optimum(file, PipelineOptions{}, {0, 1, 2, 3});
    EXPECT_LT(brute, -10.0) << "run " << run << ": the instance links nothing";
    SparseSDOptions so;
    for (const char* solver : {"exact", "lr+ls"}) {
      const AssociationRecord rec = associate_sparse_sd(file, solver, nlohmann::json::object(), 1, so);
      double total = 0.0;
      for (double c : rec.cost) total += c;
      if (std::string(solver) == "exact") {
        EXPECT_NEAR(rec.objective, brute, 1e-3 * std::max(1.0, std::fabs(brute))) << "run " << run;
        EXPECT_NEAR(total, brute, 1e-3 * std::max(1.0, std::fabs(brute))) << "run " << run;
      } else {
        EXPECT_GE(rec.objective, brute - 1e-3 * std::max(1.0, std::fabs(brute)));
      }
    }
  }
}

// The rival exponent κ is a field of the association request (AssociatorOptions, and the Python
// module's keyword): on the default path it reaches the link costs, whose optimum is the brute
// force's at that κ; the instance has rivals, so κ = 0 and κ = 2 give different optima.
TEST(SparseSDPipeline, TheRivalExponentOfTheRequestIsTheLinkCostsExponent) {
  const TrackFile file = formation_of_four(0);
  AssociatorOptions o;
  o.solver = "exact";
  o.registration.enabled = false;  // the brute force is on the reports as recorded
  o.stitching.enabled = false;
  std::vector<double> optimum;
  for (double kappa : {0.0, 2.0}) {
    const double brute = brute_force_optimum(file, PipelineOptions{}, {0, 1, 2, 3}, kappa);
    o.rival_exponent = kappa;
    const AssociationOutcome out = make_associator(o)->associate(file);
    EXPECT_NEAR(out.record.objective, brute, 1e-3 * std::max(1.0, std::fabs(brute))) << "kappa " << kappa;
    optimum.push_back(brute);
  }
  EXPECT_GT(std::fabs(optimum[1] - optimum[0]), 1.0);
  EXPECT_EQ(read_associator_options({{"rival_exponent", 0.5}}, "associate").rival_exponent, 0.5);
  for (double bad :
       {-1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    o.rival_exponent = bad;
    EXPECT_THROW(make_associator(o), InputError) << bad;
  }
  EXPECT_THROW(read_associator_options({{"rival_exponent", -0.5}}, "associate"), InputError);
}

// A component over max_component_entries is solved over its listed allowed tuples
// (engine/pipeline/sparse_sd_tuples.hpp), not by LAP merging: its bound is valid against the brute
// force, its objective within the reported gap, and the list holds every allowed tuple (the dense
// path's optimum, solved by "exact" on the same instance, is reached or bounded).
TEST(SparseSDPipeline, AComponentTooLargeForItsTensorIsSolvedOverItsListedTuplesWithABound) {
  for (int run = 0; run < 3; ++run) {
    const TrackFile file = formation_of_four(run);
    const double brute = brute_force_optimum(file, PipelineOptions{}, {0, 1, 2, 3});
    const double tol = 1e-3 * std::max(1.0, std::fabs(brute));
    SparseSDOptions so;
    so.max_component_entries = 1;  // every component of two or more tracks is "too large"
    SparseSDReport rep;
    const AssociationRecord rec = associate_sparse_sd(file, "lr+ls", nlohmann::json::object(), 1, so, &rep);
    EXPECT_GE(rep.solve.listed_components, 1) << "run " << run;
    EXPECT_EQ(rep.solve.fallback_components, 0) << "run " << run;
    EXPECT_GT(rep.solve.largest_listed_tuples, 0u);
    EXPECT_LE(rec.lower_bound, brute + tol) << "run " << run << ": invalid bound";
    EXPECT_GE(rec.objective, brute - tol) << "run " << run;
    EXPECT_LE(rec.objective - brute, rec.objective - rec.lower_bound + tol) << "run " << run;
    EXPECT_LE(rep.solve.largest_component_gap, 0.01) << "run " << run;
  }
}

TEST(SparseSDPipeline, EveryTrackInExactlyOneTupleAndBitIdenticalForOneAndTwoThreads) {
  const TrackFile file = simulate_file("recorded_5s");
  std::vector<AssociationRecord> recs;
  for (int threads : {1, 2}) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    recs.push_back(associate_sparse_sd(file, "lr+ls", nlohmann::json::object(), 1, SparseSDOptions{}));
  }
  EXPECT_EQ(recs[0].tuples, recs[1].tuples);
  EXPECT_EQ(recs[0].num_sensors, 5);
  std::set<std::pair<int32_t, int32_t>> seen, all;
  for (std::size_t r = 0; r < file.tracks.size(); ++r)
    all.insert({file.tracks.sensor[r], file.tracks.track[r]});
  for (std::size_t q = 0; q < recs[0].num_tuples(); ++q)
    for (int32_t s = 0; s < 5; ++s) {
      const int32_t trk = recs[0].tuples[q * 5 + s];
      if (trk >= 0) {
        EXPECT_TRUE(seen.insert({file.sensors[s].id, trk}).second);
      }
    }
  EXPECT_EQ(seen, all);
}

// The family at the targets (one run each; experiment recorded measures more).
TEST(SparseSDPipeline, DefaultOnTheRecordedFamilyIsCorrectWithFewFalseTuples) {
  for (const char* name : {"recorded_sync", "recorded_3s", "recorded_4s", "recorded_5s", "recorded_dense"}) {
    const TrackFile file = simulate_file(name);
    const AssociationRecord rec =
        associate_sparse_sd(file, "lr+ls", nlohmann::json::object(), 1, SparseSDOptions{});
    const AssociationMetrics m = evaluate_association(file.tracks, file.sensors, rec);
    EXPECT_GE(m.correct_rate, 0.95) << name;
    EXPECT_LE(m.false_tuples, std::max(1, m.linked_tuples / 50)) << name;
  }
}

TEST(SparseSDPipeline, RefusesBadOptionsAndTracksThatNeverCoexist) {
  TrackFile file = simulate_file("recorded_sync");
  SparseSDOptions so;
  so.pipeline.statistic.gate_probability = 1.0;
  EXPECT_THROW(build_sparse_sd_problem(file, so), InputError);
  so = {};
  so.pipeline.sensors = {0, 7};
  EXPECT_THROW(build_sparse_sd_problem(file, so), InputError);
  EXPECT_THROW(require_sparse_sd_solver("hopfield"), InputError);
  file = tracks_never_together();
  try {
    build_sparse_sd_problem(file, SparseSDOptions{});
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nothing to associate"), std::string::npos) << e.what();
  }
}

// A sensor with a single report is data, not an error: its track is associated or left alone.
TEST(SparseSDPipeline, ASensorWithOneReportIsAssociatedOrLeftAlone) {
  TrackFile file = simulate_file("recorded_sync");
  bool kept = false;  // sensor 2 keeps one report: its first after t = 20 s
  file.tracks = keep_rows(file.tracks, [&](std::size_t r) {
    if (file.tracks.sensor[r] != 2) return true;
    if (kept || file.tracks.t[r] < 20.0) return false;
    return kept = true;
  });
  const AssociationRecord rec =
      associate_sparse_sd(file, "lr+ls", nlohmann::json::object(), 1, SparseSDOptions{});
  const AssociationMetrics m = evaluate_association(file.tracks, file.sensors, rec);
  EXPECT_GE(m.correct_rate, 0.95);
  EXPECT_EQ(m.false_tuples, 0);
}

// The dense S-D tensor takes the default path's rule (engine/pipeline/tuple_cost.hpp): sensor 0
// reports only before t = 20 s and sensor 2 only after t = 40 s (more than the 10 s alignment
// reaches past a report), so their tracks never coexist;
// the tuple of a target's three tracks costs link(0,1) + link(1,2), joined through sensor 1,
// where the dense S-D path used to forbid it.
TEST(SparseSD, DenseSDJoinsTracksThatNeverCoexistThroughASensorThatSawBoth) {
  TrackFile file = simulate_file("recorded_sync");
  file.tracks = keep_rows(file.tracks, [&](std::size_t r) {
    const int32_t s = file.tracks.sensor[r];
    return s == 1 || (s == 0 && file.tracks.t[r] < 20.0) || (s == 2 && file.tracks.t[r] > 40.0);
  });
  const SDProblem p = build_sd_problem(file, PipelineOptions{});
  ASSERT_EQ(p.S(), 3);
  int joined = 0;
  for (int32_t i = 0; i < p.aligned[0].n_tracks(); ++i)
    for (int32_t j = 0; j < p.aligned[1].n_tracks(); ++j)
      for (int32_t k = 0; k < p.aligned[2].n_tracks(); ++k) {
        const int32_t target = p.aligned[0].truth[i];
        if (target < 0 || p.aligned[1].truth[j] != target || p.aligned[2].truth[k] != target) continue;
        ASSERT_FALSE(p.coexist(p.offset[0] + i, p.offset[2] + k));
        const float l01 = p.link[1][static_cast<std::size_t>(i) * p.aligned[1].n_tracks() + j];
        const float l12 = p.link[5][static_cast<std::size_t>(j) * p.aligned[2].n_tracks() + k];
        if (std::isinf(l01) || std::isinf(l12)) continue;  // a true pair outside the gate
        const int32_t t[3] = {i, j, k};
        EXPECT_EQ(p.tensor.at(t), static_cast<float>(static_cast<double>(l01) + static_cast<double>(l12)));
        ++joined;
      }
  EXPECT_GE(joined, 10);  // recorded_sync: 25 targets, almost all gated in on both pairs
}

class SparseSDCli : public CliFixture {};

TEST_F(SparseSDCli, AssociateUsesEverySensorByDefaultAndBadInputIsExitTwo) {
  const std::string sim = path("sim.h5"), out = path("out.h5");
  ASSERT_EQ(run("simulate --scenario recorded_5s --output " + sim).status, 0);
  CliResult r = run("associate --input " + sim + " --output " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("5 sensors (sparse S-D"), std::string::npos) << r.out;
  const TrackFile f = read_track_file(out);
  ASSERT_EQ(f.associations.size(), 1u);
  EXPECT_EQ(f.associations[0].num_sensors, 5);
  r = run("evaluate --input " + out);
  EXPECT_EQ(r.status, 0) << r.err;
  // A 3-D solver on five sensors is refused, never run on three of them silently.
  r = run("associate --input " + sim + " --output " + path("o2.h5") + " --solver pairwise");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("5 sensors"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(path("o2.h5")));
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  // With --sensors it runs on the three named.
  r = run("associate --input " + sim + " --output " + path("o3.h5") + " --solver pairwise --sensors 0 1 2");
  EXPECT_EQ(r.status, 0) << r.err;
  // Tracks that never coexist: exit 2, one line, nothing written.
  {
    const TrackFile bad = tracks_never_together();
    write_track_file(path("apart.h5"), bad);
    r = run("associate --input " + path("apart.h5") + " --output " + path("o5.h5"));
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.err.find("nothing to associate"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(std::filesystem::exists(path("o5.h5")));
  }
  // A gate of 1 is no miss cost: exit 2, nothing written.
  r = run("associate --input " + sim + " --output " + path("o4.h5") + " --gate 1");
  EXPECT_EQ(r.status, 2);
  EXPECT_FALSE(std::filesystem::exists(path("o4.h5")));
}

}  // namespace
}  // namespace trackassoc
