// Track hygiene (engine/pipeline/track_hygiene.hpp) on hand-made files: a recycled number (a gap,
// then a jump the track's motion cannot explain) is split, a pause its motion explains is not,
// and /tracks/source_track keeps the recorded number through a write and a read.
#include <gtest/gtest.h>

#include <filesystem>

#include "engine/pipeline/track_hygiene.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

// Sensor 0 reports every 2 s. `rows` = (track, truth, t0, t1, x0, y0, vx, vy): a straight segment.
TrackFile hand_made(const std::vector<std::array<double, 8>>& segments) {
  TrackFile f;
  Sensor s;
  s.id = 0;
  f.sensors = {s};
  f.tracks = TrackTable(StateLayout::kXY_VXVY);
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  P.diagonal() << 100.0 * 100.0, 100.0 * 100.0, 10.0 * 10.0, 10.0 * 10.0;
  for (const auto& g : segments)
    for (double t = g[2]; t <= g[3] + 1e-9; t += 2.0) {
      const double dt = t - g[2];
      f.tracks.push_back(0, static_cast<int32_t>(g[0]), t,
                         Eigen::Vector4d(g[4] + g[6] * dt, g[5] + g[7] * dt, g[6], g[7]), P,
                         static_cast<int32_t>(g[1]));
    }
  return f;
}

TEST(TrackHygiene, ARecycledNumberIsSplitAtItsJump) {
  // Track 5 follows target 1 for 0-40 s, pauses 30 s, then reports target 2, 20 km away, heading
  // elsewhere: a CV prediction over 30 s with σ_a = 3 m/s² allows ~1 km. Track 3 is one target.
  TrackFile f = hand_made({{5, 1, 0, 40, 0, 0, 200, 0},
                           {5, 2, 70, 100, 20000, 20000, 0, -150},
                           {3, 4, 0, 100, -5000, 0, 100, 100}});
  const TrackSplitSummary s = split_recycled_tracks(f, TrackSplitOptions{});
  EXPECT_EQ(s.gaps, 1);
  EXPECT_EQ(s.cuts, 1);
  ASSERT_EQ(f.source_track.size(), f.tracks.size());
  for (std::size_t r = 0; r < f.tracks.size(); ++r) {
    const int32_t truth = f.tracks.truth[r];
    // New number one above the sensor's largest (5): 6, for target 2's rows only.
    EXPECT_EQ(f.tracks.track[r], truth == 1 ? 5 : truth == 2 ? 6 : 3) << "row " << r;
    EXPECT_EQ(f.source_track[r], truth == 4 ? 3 : 5);
  }
  // Written and read back.
  const std::string path = (std::filesystem::temp_directory_path() / "trackassoc_hygiene_test.h5").string();
  write_track_file(path, f);
  const TrackFile back = read_track_file_in_process(path);
  EXPECT_EQ(back.source_track, f.source_track);
  EXPECT_EQ(back.tracks.track, f.tracks.track);
  std::filesystem::remove(path);
}

TEST(TrackHygiene, APauseTheTrackOwnMotionExplainsIsKept) {
  // Target 1 at 200 m/s: reports 0-40 s, nothing for 30 s, then exactly where CV puts it.
  TrackFile f = hand_made({{5, 1, 0, 40, 0, 0, 200, 0}, {5, 1, 70, 100, 14000, 0, 200, 0}});
  const std::vector<int32_t> before = f.tracks.track;
  const TrackSplitSummary s = split_recycled_tracks(f, TrackSplitOptions{});
  EXPECT_EQ(s.gaps, 1);
  EXPECT_EQ(s.cuts, 0);
  EXPECT_EQ(f.tracks.track, before);
  EXPECT_TRUE(f.source_track.empty());
  // A shorter pause than min_gap_s is not a gap at all.
  TrackSplitOptions o;
  o.min_gap_s = 60.0;
  TrackFile g = hand_made({{5, 1, 0, 40, 0, 0, 200, 0}, {5, 2, 70, 100, 20000, 20000, 0, -150}});
  EXPECT_EQ(split_recycled_tracks(g, o).gaps, 0);
}

TEST(TrackHygiene, BadOptionsNameTheField) {
  TrackSplitOptions o;
  o.gap_factor = 0.5;
  TrackFile f = hand_made({{5, 1, 0, 40, 0, 0, 200, 0}});
  try {
    split_recycled_tracks(f, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gap_factor"), std::string::npos);
  }
}

}  // namespace
}  // namespace trackassoc
