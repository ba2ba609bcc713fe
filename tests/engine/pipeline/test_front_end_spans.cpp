// The front end's memory check counts the aligned tracks over their spans (engine/pipeline/front_end.cpp,
// kernels/statistics/association_statistic.hpp), so a long recording of short tracks fits a budget
// that the whole grid times the tracks would not, and a budget below the spans is refused in one line.
#include <gtest/gtest.h>

#include <string>

#include "engine/pipeline/front_end.hpp"
#include "engine/pipeline/pipeline.hpp"
#include "io/memory_budget.hpp"
#include "io/track_file.hpp"
#include "kernels/core/error.hpp"
#include "tests/support/two_sensor_file.hpp"

namespace trackassoc {
namespace {

// Two sensors (period 1 s), each with a track over [0, 9] s and one over [late, late + 9] s.
TrackFile long_recording_of_short_tracks(double late = 990.0) {
  TrackFile f = testing_support::two_sensor_file();
  const Eigen::MatrixXd P = Eigen::Vector4d(25, 25, 1, 1).asDiagonal();
  for (int32_t s = 0; s < 2; ++s)
    for (const double t0 : {0.0, late})
      for (double t = t0; t <= t0 + 9.0; t += 1.0)
        f.tracks.push_back(s, static_cast<int32_t>(t0) + s, t, Eigen::Vector4d(t, 0, 1, 0), P, 0);
  return f;
}

// By hand: the grid runs over the union of the reports (PipelineOptions::span_union), 0..999 s,
// 1000 times (8 000 bytes). With max_extrapolation 10 s a track over [0, 9] s spans the grid times
// 0..19 (20 cells), one over [990, 999] s the times 980..999 (20): 80 cells of 8·(4 + 10) + 1 = 113
// bytes, 9 040 bytes, plus 4 tracks × 28 bytes = 9 152 bytes. The dense layout held 4 × 1000 cells,
// 452 000 bytes.
TEST(FrontEndSpans, TheMemoryCheckCountsSpans) {
  const TrackFile f = long_recording_of_short_tracks();
  PipelineOptions po;
  ASSERT_EQ(po.alignment.max_extrapolation, 10.0);
  // The check is of the spans beside what the process holds above what it held when the budget was
  // set (engine/pipeline/front_end.cpp; a few hundred KiB move with the pages the test touches
  // meanwhile), so the budget that separates the layouts is set on a recording 100 times longer:
  // 4 MiB fits its grid (100 000 times, 800 000 bytes) and its spans (the same 9 152 bytes), not its
  // dense layout (4 tracks × 100 000 times × 113 bytes = 45.2 MB).
  set_memory_budget_bytes(4 * 1024 * 1024);
  const AlignedSensors longer =
      align_sensors(long_recording_of_short_tracks(99990.0), po, SensorRule::kTwoOrMore);
  ASSERT_EQ(longer.common_times.size(), 100000u);
  int64_t longer_cells = 0;
  for (const AlignedTracks& x : longer.aligned) longer_cells += x.cells();
  EXPECT_EQ(longer_cells, 80);
  set_memory_budget_bytes(default_memory_budget_bytes());
  const AlignedSensors p = align_sensors(f, po, SensorRule::kTwoOrMore);
  ASSERT_TRUE(po.span_union);
  ASSERT_EQ(p.common_times.size(), 1000u);
  int64_t cells = 0;
  for (const AlignedTracks& x : p.aligned) cells += x.cells();
  EXPECT_EQ(cells, 80);
  EXPECT_EQ(p.first_valid[0], 0);  // track 0 of sensor 0: grid times 0..19
  EXPECT_EQ(p.last_valid[0], 19);
  EXPECT_EQ(p.first_valid[1], 980);  // track 990: grid times 980..999
  EXPECT_EQ(p.last_valid[1], 999);
  EXPECT_FALSE(p.coexist(0, 3));  // sensor 0's early track and sensor 1's late one
  EXPECT_TRUE(p.coexist(0, 2));

  set_memory_budget_bytes(9000);  // the grid (8 000 bytes) fits, the spans (9 152) do not
  try {
    align_sensors(f, po, SensorRule::kTwoOrMore);
    FAIL() << "expected a refusal";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("the aligned tracks (4 local tracks over their spans: 80 cells of 113 bytes"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("memory budget"), std::string::npos) << m;
  }
  set_memory_budget_bytes(default_memory_budget_bytes());
}

}  // namespace
}  // namespace trackassoc
