// The traditional fuzzy track association baseline (kernels/fuzzy/ftaa.hpp): association only after M
// consecutive decisions (counted by hand on a noise-free stream), separation after D failures,
// one target grouped across 4 sensors, separated targets never merged.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <vector>

#include "kernels/core/error.hpp"
#include "kernels/fuzzy/ftaa.hpp"
#include "tests/support/fuzzy_test_scenes.hpp"

using namespace trackassoc;

namespace {
// Two sensors, one target at (0, 0) moving (100, 0) m/s; sensor 0 reports at t = 0, 4, 8, ...,
// sensor 1 at 2, 6, 10, ... . Sensor 1's plots are shifted by `jump` from t ≥ jump_time.
struct Stream {
  std::vector<int32_t> sensor, local;
  std::vector<double> t, x, y;
  PacketSpans spans() const { return {sensor, local, t, x, y}; }
};
Stream two_sensor_stream(double jump = 0.0, double jump_time = 1e9) {
  Stream s;
  for (double t = 0; t <= 80; t += 2) {
    const int32_t k = static_cast<int32_t>(t / 2) % 2;
    s.sensor.push_back(k);
    s.local.push_back(k);
    s.t.push_back(t);
    s.x.push_back(100 * t);
    s.y.push_back(k == 1 && t >= jump_time ? jump : 0.0);
  }
  return s;
}
}  // namespace

TEST(Ftaa, AssociatesAfterMConsecutiveDecisions) {
  // Decisions: t=6 (b vs a) m=1, 8: 2, 10: 3, 12: 4, 14: 5, 16: 6 → firm at the packet of t = 16.
  const Stream s = two_sensor_stream();
  const FtaaOptions o;  // M = 6
  const FtaaResult r = run_ftaa(s.spans(), 2, 2, o);
  for (std::size_t i = 0; i < s.t.size(); ++i) {
    if (s.t[i] < 4) {
      EXPECT_EQ(r.fusion.system_track[i], -1) << "t=" << s.t[i];  // first plots: no state yet
    } else if (s.t[i] < 16) {
      EXPECT_EQ(r.fusion.system_track[i], s.local[i]) << "t=" << s.t[i];  // still separate
    } else {
      EXPECT_EQ(r.fusion.system_track[i], 0) << "t=" << s.t[i];  // one system track
    }
  }
  EXPECT_EQ(r.firm_pairs, 1);
  EXPECT_EQ(r.fusion.num_system_tracks, 1);
  EXPECT_EQ(r.final_system_track, (std::vector<int32_t>{0, 0}));
  // Fused state is the mean of both members predicted to the packet time: exact on this stream.
  for (std::size_t i = 0; i < s.t.size(); ++i)
    if (s.t[i] >= 16) {
      EXPECT_NEAR(r.fusion.x[i], 100 * s.t[i], 1e-9);
      EXPECT_NEAR(r.fusion.vx[i], 100.0, 1e-9);
    }
  FtaaOptions three = o;
  three.association_quality = 3;  // firm at t = 10
  const FtaaResult r3 = run_ftaa(s.spans(), 2, 2, three);
  for (std::size_t i = 0; i < s.t.size(); ++i)
    if (s.t[i] >= 10) {
      EXPECT_EQ(r3.fusion.system_track[i], 0) << "t=" << s.t[i];
    }
}

TEST(Ftaa, SeparatesAfterDFailures) {
  // Sensor 1's plots jump 5 km from t = 40 (first at 42): its temporary velocity is wild once, then
  // it is outside the gate: every decision fails; D = 6 failures separate the pair.
  const Stream s = two_sensor_stream(5000.0, 41.0);
  const FtaaResult r = run_ftaa(s.spans(), 2, 2, FtaaOptions{});
  EXPECT_EQ(r.firm_pairs, 0);
  EXPECT_EQ(r.fusion.num_system_tracks, 2);
  // Still together right after the jump, separate at the end.
  for (std::size_t i = 0; i < s.t.size(); ++i) {
    if (s.t[i] >= 42 && s.t[i] < 46) {
      EXPECT_EQ(r.fusion.system_track[i], 0) << "t=" << s.t[i];
    }
    if (s.t[i] >= 70) {
      EXPECT_EQ(r.fusion.system_track[i], s.local[i]) << "t=" << s.t[i];
    }
  }
}

TEST(Ftaa, OneTargetGroupedSeparatedTargetsNeverMerged) {
  for (int run = 0; run < 10; ++run) {
    const auto one = test_scenes::make_scene(3, run, {{-29500, 34500, 290, -400}}, 200.0);
    const FtaaOptions o;
    const FtaaResult r1 = run_ftaa(one.spans(), 4, one.num_local, o);
    EXPECT_EQ(r1.fusion.num_system_tracks, 1) << "run " << run;
    const auto two = test_scenes::make_scene(4, run, {{0, 0, 250, 0}, {0, 5000, 250, 0}}, 150.0);
    const FtaaResult r2 = run_ftaa(two.spans(), 4, two.num_local, o);
    std::map<int32_t, std::set<int32_t>> targets_of;
    for (std::size_t i = 0; i < two.size(); ++i)
      if (r2.fusion.system_track[i] >= 0) targets_of[r2.fusion.system_track[i]].insert(two.target[i]);
    for (const auto& [trk, tgts] : targets_of) EXPECT_EQ(tgts.size(), 1u) << "run " << run;
    EXPECT_EQ(r2.fusion.num_system_tracks, 2) << "run " << run;
  }
}

TEST(Ftaa, ValidateNamesTheField) {
  FtaaOptions o;
  o.association_quality = 0;
  try {
    o.validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("association_quality"), std::string::npos);
  }
}
