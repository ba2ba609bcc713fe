// `associate` on recordings as they come (issue 30, README Reliability), as a user's files and
// commands: a sensor that tracked nothing is associated around; any number of sensors (20 here);
// a giant connected component stays within an explicit --memory-budget, peak RSS measured.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "io/track_file.hpp"
#include "tests/support/cli_runner.hpp"
#include "tests/support/sanitizer.hpp"

namespace trackassoc {
namespace {

namespace fs = std::filesystem;
using testing_support::CliResult;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

const std::string kColumns =
    " -c time=t -c sensor=sensor -c track=track -c x=x -c y=y -c truth=truth --sigma-pos 30 --sigma-vel 3";

// One CSV report line "t,sensor,track,x,y,truth".
std::string report(double t, int sensor, int track, double x, double y, int truth) {
  std::ostringstream s;
  s.precision(12);
  s << t << "," << sensor << "," << track << "," << x << "," << y << "," << truth << "\n";
  return s.str();
}

// The tuples of `rec` as sets of (sensor column, track) with >= 2 members, and their truth ids.
std::vector<std::set<int32_t>> linked_truths(const TrackFile& f, const AssociationRecord& rec) {
  std::map<std::pair<int32_t, int32_t>, int32_t> truth;  // (sensor id, track) -> truth
  for (std::size_t r = 0; r < f.tracks.size(); ++r)
    truth[{f.tracks.sensor[r], f.tracks.track[r]}] = f.tracks.truth[r];
  std::vector<std::set<int32_t>> out;
  const std::size_t S = f.sensors.size();
  for (std::size_t k = 0; k < rec.num_tuples(); ++k) {
    std::set<int32_t> ids;
    int members = 0;
    for (std::size_t s = 0; s < S; ++s)
      if (const int32_t t = rec.tuples[k * S + s]; t >= 0)
        ++members, ids.insert(truth.at({f.sensors[s].id, t}));
    if (members >= 2) out.push_back(ids);
  }
  return out;
}

class AssociateRecordings : public testing_support::CliFixture {};

TEST_F(AssociateRecordings, ASensorWithNoLocalTracksIsAssociatedAround) {
  // Three sensors tracking four targets 5 km apart; sensor 9 is in the recording but saw nothing.
  std::string csv = "t,sensor,track,x,y,truth\n";
  for (int t = 0; t <= 20; ++t)
    for (int sensor : {1, 2, 3})
      for (int target = 0; target < 4; ++target)
        csv += report(t, sensor, 10 * sensor + target, 5000.0 * target + 100.0 * t + 3.0 * sensor, -50.0 * t,
                      target);
  write("t.csv", csv);
  ASSERT_EQ(run("import csv -i " + path("t.csv") + kColumns + " --sensors 1 2 9 3 --period 9:1 -o " +
                path("with.h5"))
                .status,
            0);
  ASSERT_EQ(
      run("import csv -i " + path("t.csv") + kColumns + " --sensors 1 2 3 -o " + path("without.h5")).status,
      0);
  const CliResult r = run("associate --input " + path("with.h5") + " --output " + path("a.h5"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(
      has(r.out, "sensors with no local tracks: 9 (associated around; their column of the tuples is -1)"))
      << r.out;
  EXPECT_TRUE(has(r.out, "sensor 9 0")) << r.out;  // among the unassociated tracks per sensor: none
  ASSERT_EQ(run("associate --input " + path("without.h5") + " --output " + path("b.h5")).status, 0);
  const TrackFile a = read_track_file(path("a.h5")), b = read_track_file(path("b.h5"));
  ASSERT_EQ(a.sensors.size(), 4u);
  ASSERT_EQ(a.sensors[2].id, 9);
  const AssociationRecord &ra = a.associations.at(0), &rb = b.associations.at(0);
  ASSERT_EQ(ra.num_tuples(), rb.num_tuples());
  for (std::size_t k = 0; k < ra.num_tuples(); ++k) {
    EXPECT_EQ(ra.tuples[k * 4 + 2], -1) << "tuple " << k;  // the empty sensor's column
    // The other columns: the association of the same tracks without the empty sensor.
    EXPECT_EQ(ra.tuples[k * 4 + 0], rb.tuples[k * 3 + 0]);
    EXPECT_EQ(ra.tuples[k * 4 + 1], rb.tuples[k * 3 + 1]);
    EXPECT_EQ(ra.tuples[k * 4 + 3], rb.tuples[k * 3 + 2]);
  }
  // The targets, one tuple of three tracks each (an invariant of this geometry: 5 km apart, σ 30 m).
  const auto truths = linked_truths(a, ra);
  EXPECT_EQ(truths.size(), 4u);
  for (const auto& ids : truths) EXPECT_EQ(ids.size(), 1u);
  // Only one sensor with tracks: nothing to associate, said so.
  write("one.csv", "t,sensor,track,x,y,truth\n" + report(0, 1, 0, 0, 0, 0) + report(1, 1, 0, 100, 0, 0));
  ASSERT_EQ(
      run("import csv -i " + path("one.csv") + kColumns + " --sensors 1 2 --period 2:1 -o " + path("one.h5"))
          .status,
      0);
  const CliResult one = run("associate --input " + path("one.h5") + " --output " + path("c.h5"));
  EXPECT_EQ(one.status, 2);
  EXPECT_TRUE(
      has(one.err, "association needs the local tracks of at least 2 sensors; sensor 2 of 2 has none"))
      << one.err;
}

TEST_F(AssociateRecordings, TwentySensorsAreAssociated) {
  // A wide-area network: 20 sensors, 20 targets 100 km apart, target j seen by sensors j, j+1 and
  // j+2 (mod 20), so each sensor has 3 tracks and no two targets share a component. Every target
  // is one tuple of its three tracks (the truth column says which).
  std::string csv = "t,sensor,track,x,y,truth\n";
  for (int t = 0; t <= 30; ++t)
    for (int sensor = 0; sensor < 20; ++sensor)
      for (int k = 0; k < 3; ++k) {
        const int target = (sensor - k + 20) % 20;
        csv +=
            report(t, sensor, k, 1e5 * target + 200.0 * t + 7.0 * (sensor % 3), 20.0 * t - 5.0 * k, target);
      }
  write("t.csv", csv);
  ASSERT_EQ(run("import csv -i " + path("t.csv") + kColumns + " -o " + path("t.h5")).status, 0);
  const CliResult r = run("associate --input " + path("t.h5") + " --output " + path("a.h5"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(has(r.out, "the tracks of 20 sensors")) << r.out;
  const TrackFile f = read_track_file(path("a.h5"));
  const auto truths = linked_truths(f, f.associations.at(0));
  ASSERT_EQ(truths.size(), 20u);
  std::set<int32_t> targets;
  for (const auto& ids : truths) {
    ASSERT_EQ(ids.size(), 1u);
    targets.insert(*ids.begin());
  }
  EXPECT_EQ(targets.size(), 20u);
  for (std::size_t k = 0; k < f.associations[0].num_tuples(); ++k) {
    int members = 0;
    for (std::size_t s = 0; s < 20; ++s) members += f.associations[0].tuples[k * 20 + s] >= 0;
    EXPECT_EQ(members, 3) << "tuple " << k;
  }
}

// Peak RSS [KiB] of `trackassoc ARGS` and its children (the forked reader), measured in a child
// of this test (getrusage RUSAGE_CHILDREN there counts that command alone).
long peak_rss_kib(const std::string& args, const fs::path& dir, int& status) {
  int fd[2];
  if (::pipe(fd) != 0) return -1;
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(fd[0]);
    const CliResult r = testing_support::run_cli(args, dir);
    rusage u{};
    ::getrusage(RUSAGE_CHILDREN, &u);
    const long out[2] = {u.ru_maxrss, r.status};
    (void)!::write(fd[1], out, sizeof out);
    ::_exit(0);
  }
  ::close(fd[1]);
  long in[2] = {-1, -1};
  (void)!::read(fd[0], in, sizeof in);
  ::close(fd[0]);
  ::waitpid(child, nullptr, 0);
  status = static_cast<int>(in[1]);
  return in[0];
}

using testing_support::kAddressSanitizer;

TEST_F(AssociateRecordings, AGiantComponentStaysWithinTheMemoryBudget) {
  // 3 sensors × 2500 targets 40 m apart on a line (σ 30 m): every track is gated with its
  // neighbours', so the gated graph is one component of 7500 tracks, solved over its listed
  // tuples (engine/pipeline/sparse_sd_tuples.hpp; by the merging fallback before issue 31). Before issue 30
  // its link matrices were dense (2500² doubles per sensor pair, 150 MB) and so was each merging LAP (2500 ×
  // 2500 and 5000 × 2500 doubles): far over a 96 MiB budget.
  const int n = 2500;
  std::string csv = "t,sensor,track,x,y,truth\n";
  csv.reserve(std::size_t{3} * n * 11 * 40);
  for (int t = 0; t <= 10; ++t)
    for (int sensor = 0; sensor < 3; ++sensor)
      for (int target = 0; target < n; ++target)
        csv += report(t, sensor, target, 40.0 * target + 100.0 * t + 5.0 * sensor, 10.0 * sensor, target);
  write("t.csv", csv);
  ASSERT_EQ(run("import csv -i " + path("t.csv") + kColumns + " -o " + path("t.h5")).status, 0);
  int status = -1;
  const int budget_mib = 96;
  // The baseline: the program and its libraries (HDF5, TBB, the C++ runtime), thread stacks and
  // the forked reader: 64 MiB (`associate` on a file of a few tracks peaks at 21 MiB).
  const long baseline_mib = 64;
  const long rss_kib = peak_rss_kib("--memory-budget " + std::to_string(budget_mib) + " associate --input " +
                                        path("t.h5") + " --output " + path("a.h5") + " --threads 2",
                                    dir_, status);
  const std::string out = slurp(path("stdout.txt")), err = slurp(path("stderr.txt"));
  // A finished association or a clean refusal naming the budget, never a crash.
  ASSERT_TRUE(status == 0 || status == 2) << status << ": " << err;
  if (status == 2) {
    EXPECT_TRUE(has(err, "more than the memory budget of 96 MiB")) << err;
  } else {
    // One giant component, over its listed tuples, with its bound.
    EXPECT_TRUE(has(out, "fallback components 0, components over listed tuples 1")) << out;
    const TrackFile f = read_track_file(path("a.h5"));
    const auto truths = linked_truths(f, f.associations.at(0));
    EXPECT_GT(truths.size(), std::size_t(n) / 2);  // most targets found (40 m apart at σ 30 m)
    // The tuples partition the tracks: each sensor's column holds each of its n tracks once.
    const AssociationRecord& rec = f.associations[0];
    for (std::size_t s = 0; s < 3; ++s) {
      std::multiset<int32_t> tracks;
      for (std::size_t k = 0; k < rec.num_tuples(); ++k)
        if (rec.tuples[k * 3 + s] >= 0) tracks.insert(rec.tuples[k * 3 + s]);
      EXPECT_EQ(tracks.size(), std::size_t(n)) << "sensor " << s;
      EXPECT_EQ(std::set<int32_t>(tracks.begin(), tracks.end()).size(), std::size_t(n)) << "sensor " << s;
    }
  }
  std::cout << "peak RSS " << rss_kib / 1024 << " MiB (budget " << budget_mib << " MiB + baseline "
            << baseline_mib << " MiB); exit " << status << "\n";
  if (!kAddressSanitizer) {  // ASan's shadow memory and quarantine are not the program's
    EXPECT_LT(rss_kib / 1024, budget_mib + baseline_mib);
  }
}

}  // namespace
}  // namespace trackassoc
