// Benchmarks of the CSV track import (io/csv_tracks.hpp) on a 10^6-row file the benchmark writes
// once into the temporary folder: 3 sensors × 1000 tracks × 333⅓ reports (periods 3, 4, 5 s).
//  - BM_ImportCsv/0: t, sensor, track, x, y, vx, vy (σ from --sigma-pos/--sigma-vel), 52 MB;
//  - BM_ImportCsv/1: the same with the 10 packed covariance columns (as `export csv` writes), 83 MB;
//  - BM_ImportCsv/2: variant 0 without velocity columns (estimated per track), 34 MB;
//  - BM_ImportCsvToHdf5/0: variant 0 and write_track_file (its validation and the HDF5 write):
//    what `trackassoc import csv` does.
// Counters: rows per second, bytes per second.
#include <benchmark/benchmark.h>

#include <charconv>
#include <filesystem>
#include <fstream>

#include "io/csv_tracks.hpp"

namespace trackassoc::bench {
namespace {

constexpr int kSensors = 3, kTracksPerSensor = 1000;
constexpr std::size_t kRows = 1000000;

std::string bench_file(int variant) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("trackassoc_bench_csv_" + std::to_string(variant) + ".csv"))
          .string();
  if (std::filesystem::exists(path)) return path;
  std::ofstream out(path + ".tmp", std::ios::binary);
  out << "t,sensor,track,x,y" << (variant == 2 ? "" : ",vx,vy");
  if (variant == 1) out << ",c00,c01,c02,c03,c11,c12,c13,c22,c23,c33";
  out << "\n";
  std::string chunk;
  char buf[64];
  auto put = [&](double v) {
    chunk.append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
    chunk += ',';
  };
  const double periods[kSensors] = {3, 4, 5};
  // Reports in time order over all tracks of a sensor, scans interleaved, as a recorder writes.
  for (std::size_t row = 0; row < kRows;) {
    const std::size_t scan = row / (kSensors * kTracksPerSensor);
    for (int s = 0; s < kSensors && row < kRows; ++s)
      for (int k = 0; k < kTracksPerSensor && row < kRows; ++k, ++row) {
        const double t = 0.5 + s + static_cast<double>(scan) * periods[s];
        const double vx = 100.0 + k, vy = -50.0 + 0.1 * k;
        put(t);
        chunk += std::to_string(s) + "," + std::to_string(k) + ",";
        put(1000.0 * k + vx * t + 0.37 * s);
        put(-5000.0 * k + vy * t - 0.21 * s);
        if (variant != 2) {
          put(vx);
          put(vy);
        }
        if (variant == 1)
          for (double c : {2500.0, 10.0, 5.0, 0.0, 2500.0, 0.0, 5.0, 100.0, 1.0, 100.0}) put(c);
        chunk.back() = '\n';
        if (chunk.size() > (1 << 20)) {
          out << chunk;
          chunk.clear();
        }
      }
  }
  out << chunk;
  out.close();
  std::filesystem::rename(path + ".tmp", path);
  return path;
}

CsvImportOptions options(int variant) {
  CsvImportOptions o;
  o.columns = parse_csv_mapping(
      variant == 2 ? R"({"time": "t", "sensor": "sensor", "track": "track", "x": "x", "y": "y"})"
                   : R"({"time": "t", "sensor": "sensor", "track": "track", "x": "x", "y": "y",
                                                  "vx": "vx", "vy": "vy"})",
      "bench");
  if (variant == 1)
    o.columns.cov = {"c00", "c01", "c02", "c03", "c11", "c12", "c13", "c22", "c23", "c33"};
  else {
    o.sigma_position = parse_per_sensor_value("50", "--sigma-pos");
    o.sigma_velocity = parse_per_sensor_value("10", "--sigma-vel");
  }
  return o;
}

void BM_ImportCsv(benchmark::State& state) {
  const int variant = static_cast<int>(state.range(0));
  const std::string path = bench_file(variant);
  const CsvImportOptions o = options(variant);
  std::size_t rows = 0;
  for (auto _ : state) {
    const TrackFile f = import_csv_tracks_file(path, o);
    rows = f.tracks.size();
    benchmark::DoNotOptimize(f.tracks.t.data());
  }
  state.counters["rows"] = static_cast<double>(rows);
  state.counters["rows_per_s"] =
      benchmark::Counter(static_cast<double>(rows), benchmark::Counter::kIsIterationInvariantRate);
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(std::filesystem::file_size(path)));
}

void BM_ImportCsvToHdf5(benchmark::State& state) {
  const int variant = static_cast<int>(state.range(0));
  const std::string path = bench_file(variant);
  const std::string out = (std::filesystem::temp_directory_path() / "trackassoc_bench_csv_out.h5").string();
  const CsvImportOptions o = options(variant);
  for (auto _ : state) write_track_file(out, import_csv_tracks_file(path, o));
  std::filesystem::remove(out);
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(std::filesystem::file_size(path)));
}

BENCHMARK(BM_ImportCsv)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_ImportCsvToHdf5)->Arg(0)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace trackassoc::bench

BENCHMARK_MAIN();
