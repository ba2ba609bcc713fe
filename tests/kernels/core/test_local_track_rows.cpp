// The rows of each local track (kernels/core/local_track_rows.hpp) against the form every stage used
// to write for itself: a std::map from (sensor, track) to its rows in row order, each then
// stable-sorted by time. Random tables with few keys and times (so ties are common), in shuffled,
// time-ordered and reversed row orders, negative ids included.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <random>
#include <vector>

#include "kernels/core/local_track_rows.hpp"

namespace trackassoc {
namespace {

std::map<LocalTrackRows::Key, std::vector<std::size_t>> by_map(const TrackTable& t) {
  std::map<LocalTrackRows::Key, std::vector<std::size_t>> rows;
  for (std::size_t r = 0; r < t.size(); ++r) rows[{t.sensor[r], t.track[r]}].push_back(r);
  for (auto& [key, v] : rows)
    std::stable_sort(v.begin(), v.end(), [&](std::size_t a, std::size_t b) { return t.t[a] < t.t[b]; });
  return rows;
}

TEST(LocalTrackRows, EqualsTheMapOfStableSortedRows) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> sensor(-2, 3), track(0, 6), time(0, 12);
  for (int trial = 0; trial < 500; ++trial) {
    TrackTable t;
    const int n = trial % 80;
    for (int r = 0; r < n; ++r) {
      t.sensor.push_back(sensor(rng));
      t.track.push_back(trial % 7 == 0 ? 1 << 30 : track(rng));
      t.t.push_back(0.25 * time(rng));
      t.truth.push_back(-1);
    }
    if (trial % 3 == 1 || trial % 3 == 2) {  // rows in time order, or reversed
      std::vector<std::size_t> p(t.size());
      std::iota(p.begin(), p.end(), std::size_t{0});
      std::stable_sort(p.begin(), p.end(), [&](std::size_t a, std::size_t b) { return t.t[a] < t.t[b]; });
      if (trial % 3 == 2) std::reverse(p.begin(), p.end());
      TrackTable u;
      for (std::size_t r : p)
        u.sensor.push_back(t.sensor[r]), u.track.push_back(t.track[r]), u.t.push_back(t.t[r]),
            u.truth.push_back(-1);
      t = u;
    }
    const auto want = by_map(t);
    const LocalTrackRows got = local_track_rows(t);
    ASSERT_EQ(got.size(), want.size()) << "trial " << trial;
    ASSERT_EQ(got.row.size(), t.size());
    std::size_t k = 0;
    for (const auto& [key, rows] : want) {
      EXPECT_EQ(got.key[k], key) << "trial " << trial;
      const auto span = got.rows(k);
      EXPECT_EQ(std::vector<std::size_t>(span.begin(), span.end()), rows) << "trial " << trial;
      EXPECT_EQ(got.find(key), k);
      ++k;
    }
    EXPECT_EQ(got.find({99, 99}), got.size());
  }
}

}  // namespace
}  // namespace trackassoc
