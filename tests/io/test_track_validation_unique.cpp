// The repeated-report check of /tracks (io/track_validation.cpp, check_unique_reports through
// check_tracks) against the naive peer it replaced: every row index sorted by (sensor, track, t, row),
// the first two neighbours with the same (sensor, track, t) named. On random tables with few
// sensors, tracks and times (so repeats are common), in shuffled, time-ordered and reversed row
// orders, the check must throw exactly when the peer finds a repeat, with the same message.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "io/track_validation.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

// The naive peer: {} when no (sensor, track, t) repeats, else what the message must contain.
std::vector<std::string> naive_repeat(const TrackTable& t) {
  std::vector<std::size_t> rows(t.size());
  std::iota(rows.begin(), rows.end(), std::size_t{0});
  auto key = [&](std::size_t r) { return std::make_tuple(t.sensor[r], t.track[r], t.t[r], r); };
  std::sort(rows.begin(), rows.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  for (std::size_t k = 1; k < rows.size(); ++k) {
    const std::size_t a = rows[k - 1], b = rows[k];
    if (t.sensor[a] != t.sensor[b] || t.track[a] != t.track[b] || t.t[a] != t.t[b]) continue;
    bool same = true;
    for (const auto& c : t.state) same = same && c[a] == c[b];
    return {"f.h5: /tracks: row " + std::to_string(b) + ": sensor " + std::to_string(t.sensor[b]) +
                ", track " + std::to_string(t.track[b]) + ", t = ",
            " is also row " + std::to_string(a) +
                (same ? " (the same state repeated)" : " with a different state") +
                "; a local track reports at most once per time"};
  }
  return {};
}

TrackTable random_table(std::mt19937_64& rng, int rows, int order) {
  std::uniform_int_distribution<int> sensor(0, 2), track(0, 4), time(0, 30), state(0, 1);
  TrackTable t;
  for (int r = 0; r < rows; ++r) {
    t.sensor.push_back(sensor(rng) * 10);
    t.track.push_back(track(rng));
    t.t.push_back(0.5 * time(rng));
    t.truth.push_back(-1);
    for (auto& c : t.state) c.push_back(state(rng));
    const double packed[10] = {1, 0, 0, 0, 1, 0, 0, 1, 0, 1};  // identity, packed upper triangle
    for (int k = 0; k < 10; ++k) t.cov[k].push_back(packed[k]);
  }
  if (order > 0) {  // rows in time order (order 1) or reversed (order 2), as recordings may be
    std::vector<std::size_t> p(t.size());
    std::iota(p.begin(), p.end(), std::size_t{0});
    std::stable_sort(p.begin(), p.end(), [&](std::size_t a, std::size_t b) { return t.t[a] < t.t[b]; });
    if (order == 2) std::reverse(p.begin(), p.end());
    TrackTable u;
    for (std::size_t r : p) {
      u.sensor.push_back(t.sensor[r]), u.track.push_back(t.track[r]), u.t.push_back(t.t[r]);
      u.truth.push_back(-1);
      for (std::size_t c = 0; c < t.state.size(); ++c) u.state[c].push_back(t.state[c][r]);
      for (std::size_t c = 0; c < t.cov.size(); ++c) u.cov[c].push_back(t.cov[c][r]);
    }
    return u;
  }
  return t;
}

TEST(TrackValidationUnique, FindsTheSameRepeatAsTheSortOfAllRows) {
  const std::vector<Sensor> sensors = [] {
    std::vector<Sensor> s(3);
    for (int i = 0; i < 3; ++i) s[i].id = 10 * i;
    return s;
  }();
  std::mt19937_64 rng(29);
  int repeats = 0, clean = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const int rows = 1 + trial % 60;
    const TrackTable t = random_table(rng, rows, trial % 3);
    const std::vector<std::string> want = naive_repeat(t);
    std::string got;
    try {
      track_validation::check_tracks("f.h5", t, sensors);
    } catch (const InputError& e) {
      got = e.what();
    }
    if (want.empty()) {
      EXPECT_EQ(got, "") << "trial " << trial;
      ++clean;
    } else {
      EXPECT_EQ(got.rfind(want[0], 0), 0u) << "trial " << trial << ": " << got << "\nwanted: " << want[0];
      EXPECT_NE(got.find(want[1]), std::string::npos)
          << "trial " << trial << ": " << got << "\nwanted: " << want[1];
      ++repeats;
    }
  }
  EXPECT_GT(repeats, 500);  // both outcomes are exercised
  EXPECT_GT(clean, 200);
}

}  // namespace
}  // namespace trackassoc
