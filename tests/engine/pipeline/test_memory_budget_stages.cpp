// --memory-budget bounds the default (sparse S-D) pipeline's stages before they allocate (issues 30
// and 31; io/memory_budget.hpp, docs/design.md §7): the candidate search, whose size is known only
// as it finds pairs, counts its buffers as they grow (kernels/core/allocation_gauge.hpp) and is
// refused before the buffer that would cross the budget, measured as the process's peak resident
// set; a budget it fits lets it finish. --sparse shares the front half, so its search is refused too.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <algorithm>
#include <string>

#include "engine/pipeline/registration_stage.hpp"
#include "engine/pipeline/sparse_pipeline.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/pipeline/track_segments.hpp"
#include "engine/pipeline/track_stitching.hpp"
#include "io/memory_budget.hpp"
#include "io/track_file.hpp"
#include "kernels/core/error.hpp"
#include "tests/support/sanitizer.hpp"
#include "tests/support/two_sensor_file.hpp"

namespace trackassoc {
namespace {

using testing_support::kAddressSanitizer;

constexpr std::size_t kMiB = std::size_t{1} << 20;

// `sensors` sensors (period 1 s; two or three) with n tracks each over [0, K − 1] s, all at the
// same place (x = t, σ 5 m): every pair of two sensors is a candidate at every scan.
TrackFile crowd(int32_t n, int32_t K, int32_t sensors = 2) {
  TrackFile f = testing_support::two_sensor_file();
  if (sensors == 3) f.sensors.push_back(Sensor{f.sensors[1]}), f.sensors.back().id = 2;
  const Eigen::MatrixXd P = Eigen::Vector4d(25, 25, 1, 1).asDiagonal();
  for (int32_t s = 0; s < sensors; ++s)
    for (int32_t i = 0; i < n; ++i)
      for (int32_t k = 0; k < K; ++k) f.tracks.push_back(s, i, k, Eigen::Vector4d(k, 0, 1, 0), P, i);
  return f;
}

double peak_resident_bytes() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) * 1024.0;  // Linux: KiB
}

// By hand: 1000 tracks a sensor over 16 common times, every one of the 10⁶ pairs within its bound
// at each scan. Each of the search's two blocks of 8 scans holds at least its 10⁶ distinct hits of
// 12 bytes until the merge, which reserves the 2·10⁶ of both beside them: at least 48 MB at once
// (more with their growth and duplicates), and 16 MB of output: a search counted only once done
// would be past a 32 MiB budget by then. The input (32 000 reports) and the aligned tracks (32 000
// cells of 113 bytes) are ~8 MB.
TEST(MemoryBudgetStages, TheCandidateSearchIsRefusedBeforeItsHitsAreAllocated) {
  const TrackFile f = crowd(1000, 16);
  const double hits_by_hand = 4.0 * 1e6 * 12.0;
  const std::size_t budget = 32 * kMiB;
  ASSERT_GT(hits_by_hand, static_cast<double>(budget));
  const double peak_before = peak_resident_bytes();
  set_memory_budget_bytes(budget);  // the baseline: what the process holds now (the file too)
  const double start = std::max(peak_before, static_cast<double>(resident_bytes()));
  std::string message;
  try {
    build_sparse_sd_problem(f, SparseSDOptions{});
  } catch (const InputError& e) {
    message = e.what();
  }
  const double grew = peak_resident_bytes() - start;
  set_memory_budget_bytes(default_memory_budget_bytes());
  EXPECT_NE(message.find("the candidate search of 2 sensors (2000 local tracks"), std::string::npos)
      << message;
  EXPECT_NE(message.find("more than the memory budget of 32 MiB"), std::string::npos) << message;
  // Refused before: the peak grew by at most the budget, not by the 48 MB of hits (not checked under
  // ASan, whose shadow memory and quarantine of freed blocks are resident but not the program's).
  std::cout << "peak resident grew by " << grew / kMiB
            << " MiB (budget 32 MiB, hits at least 48 MB by hand)\n";
  if (!kAddressSanitizer) {
    EXPECT_LE(grew, static_cast<double>(budget));
  }
}

// --sparse (the three-sensor path) shares the default path's front half, budget included: three
// sensors of 1000 tracks, 3·10⁶ pairs at every scan, 144 MB of hits by the count above, refused
// at 32 MiB (before the front half was shared, --sparse ran its own search unchecked and finished).
TEST(MemoryBudgetStages, TheSparseThreeSensorPathIsRefusedToo) {
  const TrackFile f = crowd(1000, 16, 3);
  set_memory_budget_bytes(32 * kMiB);
  std::string message;
  try {
    build_sparse_association_problem(f, SparsePipelineOptions{});
  } catch (const InputError& e) {
    message = e.what();
  }
  set_memory_budget_bytes(default_memory_budget_bytes());
  EXPECT_NE(message.find("the candidate search of 3 sensors (3000 local tracks"), std::string::npos)
      << message;
  EXPECT_NE(message.find("more than the memory budget of 32 MiB"), std::string::npos) << message;
}

// The same stage within a budget it fits: 100 tracks a sensor, 10 000 pairs (by hand: all of them),
// a few MB at most, finish under 32 MiB.
TEST(MemoryBudgetStages, ABudgetTheStagesFitLetsThemFinish) {
  const TrackFile f = crowd(100, 16);
  set_memory_budget_bytes(32 * kMiB);
  const SparseSDProblem p = build_sparse_sd_problem(f, SparseSDOptions{});
  set_memory_budget_bytes(default_memory_budget_bytes());
  ASSERT_EQ(p.S(), 2);
  EXPECT_EQ(p.candidate_pairs[1], 10000u);
  // The kept candidates' bytes (8 a pair) are what the candidates stage reports it holds.
  const auto it =
      std::find_if(p.stages.begin(), p.stages.end(), [](const auto& s) { return s.name == "candidates"; });
  ASSERT_NE(it, p.stages.end());
  EXPECT_NEAR(it->data_mib * static_cast<double>(kMiB), 8.0 * 10000.0, 1.0);
}

// n tracks on each of two sensors, 3 reports each at 0-2 s, 100 km apart: sensor s's track i at
// x = 100 km · i when `together` (both sensors' track i one target, truth i), else at 100 km · (2i + s)
// (all apart, false tracks).
TrackFile short_tracks(int32_t n, bool together) {
  TrackFile f = testing_support::two_sensor_file();
  const Eigen::MatrixXd P = Eigen::Vector4d(25, 25, 1, 1).asDiagonal();
  for (int32_t i = 0; i < n; ++i)
    for (int32_t s = 0; s < 2; ++s)
      for (int32_t k = 0; k < 3; ++k)
        f.tracks.push_back(s, i, k, Eigen::Vector4d(1e5 * (together ? i : 2 * i + s), 0, 1, 0), P,
                           together ? i : -1);
  return f;
}

// Runs `stage` under a budget of 1 MiB over what the process holds, then of 64 MiB, and restores the
// default: returns the first run's refusal (empty when it passed) and the second run's result, which
// must pass.
template <class Stage>
auto refused_at_1_mib_then_run_at_64(Stage&& stage) {
  std::string message;
  set_memory_budget_bytes(kMiB);
  try {
    stage();
  } catch (const InputError& e) {
    message = e.what();
  }
  set_memory_budget_bytes(64 * kMiB);
  auto within = stage();
  set_memory_budget_bytes(default_memory_budget_bytes());
  EXPECT_NE(message.find("more than the memory budget of 1 MiB"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  return std::pair{message, within};
}

// Fragment stitching checks its groups before it allocates them. 20 000 one-track groups (10 000
// tracks a sensor, 3 reports each at 0-2 s, far apart: no candidates) need, by hand, at least
// 20 000 × (16 rows of start scratch × 8 bytes + ~100 bytes of index) ≈ 4.6 MB beside the file: a
// budget of 1 MiB over what the process holds refuses it in one line naming the stage; 64 MiB lets it
// finish.
TEST(MemoryBudgetStages, FragmentStitchingIsRefusedBeforeItsGroupsAreAllocated) {
  const TrackFile f = short_tracks(10000, false);
  AssociationRecord rec;
  rec.num_sensors = 2;
  for (int32_t i = 0; i < 10000; ++i) rec.tuples.insert(rec.tuples.end(), {i, -1, -1, i});
  ASSERT_GT(20000.0 * (16 * 8 + 100), 1.0 * kMiB);
  const auto [message, summary] = refused_at_1_mib_then_run_at_64([&] {
    AssociationRecord copy = rec;
    return stitch_fragments(f, copy, TrackStitchOptions{});
  });
  EXPECT_NE(message.find("fragment stitching (20000 tuples)"), std::string::npos) << message;
  EXPECT_EQ(summary.groups, 20000);
  EXPECT_EQ(summary.stitches, 0);
}

// The segment pass checks its graph before it builds it: crowd(100, 16) has 200 local tracks and
// 10 000 gated pairs (by hand, as above), so its graph needs at least 10 000 × (4 adjacency entries of
// 16 bytes + 64 bytes of hash entry) = 1.28 MB: refused in one line at a 1 MiB budget over what the
// process holds, finished at 64 MiB (no tuples: nothing joined).
TEST(MemoryBudgetStages, TheSegmentPassIsRefusedBeforeItsGraphIsBuilt) {
  const TrackFile f = crowd(100, 16);
  const SparseSDProblem p = build_sparse_sd_problem(f, SparseSDOptions{});
  ASSERT_EQ(p.candidate_pairs[1], 10000u);
  AssociationRecord rec;
  rec.num_sensors = 2;
  const auto [message, within] = refused_at_1_mib_then_run_at_64(
      [&] { return join_track_segments(p, f.tracks, rec, SegmentOptions{}); });
  EXPECT_NE(message.find("the track segment pass (200 local tracks, 10000 gated pairs)"), std::string::npos)
      << message;
  EXPECT_EQ(within.num_tuples(), 0u);
}

// The registration stage checks its rows per local track before it builds them: 20 000 tracks of 3
// reports (grouped by track, as files are written) need, by hand, 60 000 × 16 + 20 000 × 80 bytes =
// 2.56 MB: refused in one line at a 1 MiB budget over what the process holds, finished at 64 MiB.
TEST(MemoryBudgetStages, TheRegistrationStageIsRefusedBeforeItsRowsPerTrackAreAllocated) {
  const TrackFile f = short_tracks(10000, true);
  AssociationRecord rec;
  rec.num_sensors = 2;
  for (int32_t i = 0; i < 10000; ++i) rec.tuples.insert(rec.tuples.end(), {i, i});
  ASSERT_GT(60000.0 * 16 + 20000.0 * 80, 1.0 * kMiB);
  const auto [message, within] = refused_at_1_mib_then_run_at_64(
      [&] { return registration_observations(f, rec, RegistrationStageOptions{}); });
  EXPECT_NE(message.find(
                "the registration stage's rows per local track (60000 reports, at most 20000 local tracks)"),
            std::string::npos)
      << message;
  EXPECT_GT(within.size(), 0u);  // every tuple's pair gives observations at its 3 common times
}

}  // namespace
}  // namespace trackassoc
