// Filter-bank throughput (docs/design.md §6: CV Kalman bank, 2-D, 10^6 tracks: ≥ 40 M updates/s on 2
// threads and ≥ 2× a per-track Eigen loop in the same run).
//
//   BM_CvBank/N/threads          batched CV bank (kernels/filters/kalman_bank.hpp), one scan per iteration
//   BM_EigenPerTrack/N/threads   naive baseline: one object per track with fixed-size Eigen
//                                matrices (Matrix4d/Matrix2d, no heap), textbook formulas, the
//                                same scan, looped (and split over TBB for 2 threads)
//   BM_ImmBank/N/threads         seed 002 IMM {CS-parallel + network, CA} bank
//   BM_CsParallelBank/N/threads  the two parallel CS filters alone
// Counter "updates/s" = tracks advanced (predict + update, 90 % detected) per second.
#include <benchmark/benchmark.h>
#include <oneapi/tbb/global_control.h>

#include <Eigen/Dense>
#include <vector>

#include "kernels/core/parallel.hpp"
#include "kernels/core/random.hpp"
#include "kernels/filters/cs_parallel.hpp"
#include "kernels/filters/imm.hpp"
#include "kernels/filters/kalman_bank.hpp"
#include "kernels/learning/bp_network.hpp"

namespace {

using namespace trackassoc;

struct ScanColumns {
  std::vector<double> z0, z1, r0, r1, r2;
  std::vector<uint8_t> det;
  explicit ScanColumns(std::size_t n) {
    CounterRng rng(11);
    for (std::size_t i = 0; i < n; ++i) {
      z0.push_back(rng.normal(0, 100));
      z1.push_back(rng.normal(0, 100));
      r0.push_back(2500.0), r1.push_back(300.0), r2.push_back(1600.0);
      det.push_back(rng.uniform() < 0.9);
    }
  }
  PositionScan view() const {
    PositionScan s;
    s.z[0] = z0, s.z[1] = z1, s.R[0] = r0, s.R[1] = r1, s.R[2] = r2;
    s.detected = det;
    return s;
  }
};

void set_rate(benchmark::State& state, std::size_t n) {
  state.counters["updates/s"] = benchmark::Counter(
      static_cast<double>(n) * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["tracks"] = static_cast<double>(n);
}

void BM_CvBank(benchmark::State& state) {
  const std::size_t n = state.range(0);
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, state.range(1));
  KinematicBank bank(2, 2, n);
  const ScanColumns scan(n);
  KalmanOptions o;
  for (auto _ : state) {
    kalman_bank_step(bank, 1.0, scan.view(), o);
    benchmark::ClobberMemory();
  }
  set_rate(state, n);
}

// The naive baseline: the obvious per-track object with fixed-size Eigen types.
struct EigenCvTrack {
  Eigen::Vector4d x = Eigen::Vector4d::Zero();
  Eigen::Matrix4d P = Eigen::Matrix4d::Identity();
  void step(const Eigen::Matrix4d& F, const Eigen::Matrix4d& Q, const Eigen::Vector2d& z,
            const Eigen::Matrix2d& R, bool detected) {
    x = F * x;
    P = F * P * F.transpose() + Q;
    if (!detected) return;
    const Eigen::Matrix<double, 2, 4> H =
        (Eigen::Matrix<double, 2, 4>() << 1, 0, 0, 0, 0, 1, 0, 0).finished();
    const Eigen::Matrix2d S = H * P * H.transpose() + R;
    const Eigen::Matrix<double, 4, 2> K = P * H.transpose() * S.inverse();
    x += K * (z - H * x);
    P -= K * S * K.transpose();
  }
};

void BM_EigenPerTrack(benchmark::State& state) {
  const std::size_t n = state.range(0);
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, state.range(1));
  std::vector<EigenCvTrack> tracks(n);
  const ScanColumns scan(n);
  Eigen::Matrix4d F = Eigen::Matrix4d::Identity();
  F(0, 2) = F(1, 3) = 1.0;
  Eigen::Matrix4d Q = Eigen::Matrix4d::Zero();
  Q(0, 0) = Q(1, 1) = 0.25, Q(0, 2) = Q(2, 0) = Q(1, 3) = Q(3, 1) = 0.5, Q(2, 2) = Q(3, 3) = 1.0;
  for (auto _ : state) {
    parallel_for_range(n, 2048, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        Eigen::Matrix2d R;
        R << scan.r0[i], scan.r1[i], scan.r1[i], scan.r2[i];
        tracks[i].step(F, Q, Eigen::Vector2d(scan.z0[i], scan.z1[i]), R, scan.det[i]);
      }
    });
    benchmark::ClobberMemory();
  }
  set_rate(state, n);
}

void init_order3(KinematicBank& b) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.dim());
  const Eigen::MatrixXd P = 100.0 * Eigen::MatrixXd::Identity(b.dim(), b.dim());
  for (std::size_t i = 0; i < b.size(); ++i) b.set(i, x, P);
}

void BM_CsParallelBank(benchmark::State& state) {
  const std::size_t n = state.range(0);
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, state.range(1));
  CsParallelBank bank(2, n, trained_cs_network());
  init_order3(bank.f1);
  init_order3(bank.f2);
  const ScanColumns scan(n);
  CsParallelOptions o;
  for (auto _ : state) {
    cs_parallel_step(bank, 1.0, scan.view(), o);
    benchmark::ClobberMemory();
  }
  set_rate(state, n);
}

void BM_ImmBank(benchmark::State& state) {
  const std::size_t n = state.range(0);
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, state.range(1));
  ImmBank bank(2, n, ImmOptions::seed002(), trained_cs_network());
  for (int j = 0; j < bank.num_models(); ++j) init_order3(bank.model(j).filter());
  init_order3(bank.model(0).parallel->f1);
  const ScanColumns scan(n);
  for (auto _ : state) {
    imm_bank_step(bank, 1.0, scan.view());
    benchmark::ClobberMemory();
  }
  set_rate(state, n);
}

void sizes_and_threads(benchmark::internal::Benchmark* b, std::vector<int64_t> sizes) {
  for (int64_t n : sizes)
    for (int64_t t : {1, 2}) b->Args({n, t});
  b->ArgNames({"tracks", "threads"})->UseRealTime()->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_CvBank)->Apply([](auto* b) { sizes_and_threads(b, {1000, 100000, 1000000}); });
BENCHMARK(BM_EigenPerTrack)->Apply([](auto* b) { sizes_and_threads(b, {1000, 100000, 1000000}); });
BENCHMARK(BM_CsParallelBank)->Apply([](auto* b) { sizes_and_threads(b, {1000, 100000}); });
BENCHMARK(BM_ImmBank)->Apply([](auto* b) { sizes_and_threads(b, {1000, 100000}); });

}  // namespace

BENCHMARK_MAIN();
