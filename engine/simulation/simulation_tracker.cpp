#include "engine/simulation/simulation_tracker.hpp"

#include <algorithm>
#include <map>
#include <numeric>

#include "engine/simulation/simulation_truth.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/random.hpp"
#include "kernels/filters/alpha_beta.hpp"
#include "kernels/filters/cs_filter.hpp"
#include "kernels/filters/cs_parallel.hpp"
#include "kernels/filters/imm.hpp"
#include "kernels/filters/kalman_converted.hpp"
#include "kernels/learning/bp_network.hpp"

namespace trackassoc {

namespace {

// The acceleration of an order-3 model is unknown at initiation: prior σ = 20 m/s² (2 g), no
// correlation with the two-point position and velocity.
constexpr double kAccelPriorVariance = 20.0 * 20.0;

void position_velocity_of(const KinematicBank& bank, std::size_t i, Eigen::VectorXd& x, Eigen::MatrixXd& P) {
  const int m = 2 * bank.spatial_dim();
  x = bank.state_vector(i).head(m);
  P = bank.covariance(i).topLeftCorner(m, m);
}

// CV / CA Kalman bank (kernels/filters/kalman_bank.hpp).
class KalmanLocalBank final : public LocalFilterBank {
 public:
  KalmanLocalBank(KalmanModel model, double sigma, int d, std::size_t n)
      : bank_(d, static_cast<int>(model), n) {
    options_.model = model;
    options_.process_noise = sigma;
    options_.validate();
  }
  void step(double dt, const PositionScan& scan) override { kalman_bank_step(bank_, dt, scan, options_); }
  void initialise(std::size_t i, const Eigen::VectorXd& z1, const Eigen::MatrixXd& R1,
                  const Eigen::VectorXd& z2, const Eigen::MatrixXd& R2, double dt) override {
    two_point_initialise(bank_, i, z1, R1, z2, R2, dt, kAccelPriorVariance);
  }
  void position_velocity(std::size_t i, Eigen::VectorXd& x, Eigen::MatrixXd& P) const override {
    position_velocity_of(bank_, i, x, P);
  }

 private:
  KinematicBank bank_;
  KalmanOptions options_;
};

// "Current" statistical model (kernels/filters/cs_filter.hpp), CsOptions defaults.
class CsLocalBank final : public LocalFilterBank {
 public:
  CsLocalBank(int d, std::size_t n) : bank_(d, 3, n) {}
  void step(double dt, const PositionScan& scan) override { cs_bank_step(bank_, dt, scan, options_); }
  void initialise(std::size_t i, const Eigen::VectorXd& z1, const Eigen::MatrixXd& R1,
                  const Eigen::VectorXd& z2, const Eigen::MatrixXd& R2, double dt) override {
    two_point_initialise(bank_, i, z1, R1, z2, R2, dt, kAccelPriorVariance);
  }
  void position_velocity(std::size_t i, Eigen::VectorXd& x, Eigen::MatrixXd& P) const override {
    position_velocity_of(bank_, i, x, P);
  }

 private:
  KinematicBank bank_;
  CsOptions options_;
};

// Two parallel CS filters tuned by the trained network (kernels/filters/cs_parallel.hpp).
class CsParallelLocalBank final : public LocalFilterBank {
 public:
  CsParallelLocalBank(int d, std::size_t n) : bank_(d, n, trained_cs_network()) {}
  void step(double dt, const PositionScan& scan) override { cs_parallel_step(bank_, dt, scan, options_); }
  void initialise(std::size_t i, const Eigen::VectorXd& z1, const Eigen::MatrixXd& R1,
                  const Eigen::VectorXd& z2, const Eigen::MatrixXd& R2, double dt) override {
    two_point_initialise(bank_.f1, i, z1, R1, z2, R2, dt, kAccelPriorVariance);
    two_point_initialise(bank_.f2, i, z1, R1, z2, R2, dt, kAccelPriorVariance);
    bank_.scale[i] = 1.0;
  }
  void position_velocity(std::size_t i, Eigen::VectorXd& x, Eigen::MatrixXd& P) const override {
    position_velocity_of(bank_.f2, i, x, P);
  }

 private:
  CsParallelBank bank_;
  CsParallelOptions options_;
};

// Alpha-beta bank (kernels/filters/alpha_beta.hpp) with Kalata steady-state gains for the DWNA model of
// σ_w = spec.process_noise and, per track, σ_v² = tr(R)/d of its latest converted plot (the mean
// per-axis variance: the α-β filter has one scalar gain pair for all axes), after an expanding-
// memory (least-squares) start from the two-point initialisation.
// Covariance. An α-β filter carries none; we propagate the true error covariance of its estimate
// under the tracking model for the gains actually applied: predict P ← F P Fᵀ + Q (DWNA, as the
// CV Kalman bank), and at an update with gain K = [α, β/T]ᵀ ⊗ I_d the Joseph form
// P ← (I − K H) P (I − K H)ᵀ + K R Kᵀ, valid for any gain (Bar-Shalom et al. 2001, Eq. 5.2.3-18),
// with the plot's full converted-measurement R. It starts from the two-point covariance. So:
//   - during the expanding-memory start (least-squares gains) it is the least-squares line fit's
//     covariance (plus the process noise); for n plots of variance σ² at step T and σ_w = 0,
//     P_pp = 2(2n−1)/(n(n+1))·σ², P_pv = 6/(n(n+1)T)·σ², P_vv = 12/(n(n²−1)T²)·σ² (Brookner §1.2.6);
//   - in steady state with isotropic R = σ_v² I it converges to the Kalata relation
//     P_pp = α σ_v², P_pv = β σ_v²/T, P_vv = β(α − β/2)/(1 − α)·σ_v²/T² (Kalata 1984; Bar-Shalom
//     et al. 2001 §6.5.3), i.e. the steady-state Kalman covariance, as the gains are Kalman's;
//   - with anisotropic R (range vs cross-range) the gains are not Kalman's, and P is still the
//     error covariance of the estimate actually produced, not the (smaller) Kalman one.
// The covariance update is per track and scalar (Eigen on 4×4 / 6×6); the bank itself is SoA.
class AlphaBetaLocalBank final : public LocalFilterBank {
 public:
  AlphaBetaLocalBank(double sigma, int d, std::size_t n)
      : d_(d), sigma_(sigma), bank_(d, n, options(sigma)), P_(n), initialised_(n, 0) {}
  static AlphaBetaOptions options(double sigma) {
    AlphaBetaOptions o;  // Kalata gains, expanding-memory start
    require(sigma > 0.0, "tracker.process_noise",
            "the alpha-beta filter (Kalata gains) needs a white-noise acceleration σ > 0 [m/s²], got " +
                std::to_string(sigma));
    o.process_noise = sigma;
    return o;
  }
  void step(double dt, const PositionScan& scan) override {
    const std::size_t n = bank_.size();
    for (std::size_t i = 0; i < n; ++i)
      if (scan.detected[i]) {
        double trace = 0.0;
        for (int a = 0, k = 0; a < d_; k += d_ - a, ++a) trace += scan.R[k][i];
        bank_.measurement_noise[i] = std::sqrt(trace / d_);
      }
    if (dt > 0.0) bank_.predict(dt);
    std::vector<AlphaBetaGains> gains(n);
    for (std::size_t i = 0; i < n; ++i)
      if (scan.detected[i] && initialised_[i]) gains[i] = bank_.next_update_gains(i);
    std::span<const double> z[3] = {scan.z[0], scan.z[1], scan.z[2]};
    bank_.update(std::span<const std::span<const double>>(z, d_), scan.detected);
    for (std::size_t i = 0; i < n; ++i) {
      if (!initialised_[i]) continue;
      if (dt > 0.0) predict_covariance(P_[i], dt);
      if (gains[i].alpha > 0.0) update_covariance(P_[i], gains[i], bank_.step[i], scan, i);
    }
  }
  void initialise(std::size_t i, const Eigen::VectorXd& z1, const Eigen::MatrixXd& R1,
                  const Eigen::VectorXd& z2, const Eigen::MatrixXd& R2, double dt) override {
    Eigen::VectorXd v = (z2 - z1) / dt;
    bank_.initialise(i, std::span<const double>(z2.data(), d_), std::span<const double>(v.data(), d_), 2);
    bank_.measurement_noise[i] = std::sqrt(R2.trace() / d_);
    // Two-point initialisation (Bar-Shalom et al. 2001 §5.5.3): p = z2, v = (z2 − z1)/dt.
    Eigen::MatrixXd& P = P_[i];
    P.resize(2 * d_, 2 * d_);
    P.topLeftCorner(d_, d_) = R2;
    P.topRightCorner(d_, d_) = R2 / dt;
    P.bottomLeftCorner(d_, d_) = R2 / dt;
    P.bottomRightCorner(d_, d_) = (R1 + R2) / (dt * dt);
    initialised_[i] = 1;
  }
  void position_velocity(std::size_t i, Eigen::VectorXd& x, Eigen::MatrixXd& P) const override {
    x.resize(2 * d_);
    for (int a = 0; a < d_; ++a) x(a) = bank_.position[a][i], x(d_ + a) = bank_.velocity[a][i];
    P = P_[i];
  }

 private:
  // P ← F P Fᵀ + Q, F = [[1, T], [0, 1]] ⊗ I_d, Q = σ_w²[[T⁴/4, T³/2], [T³/2, T²]] ⊗ I_d (DWNA).
  void predict_covariance(Eigen::MatrixXd& P, double T) const {
    Eigen::MatrixXd F = Eigen::MatrixXd::Identity(2 * d_, 2 * d_);
    F.topRightCorner(d_, d_).diagonal().setConstant(T);
    const double q = sigma_ * sigma_;
    P = F * P * F.transpose();
    for (int a = 0; a < d_; ++a) {
      P(a, a) += q * T * T * T * T / 4.0;
      P(a, d_ + a) += q * T * T * T / 2.0;
      P(d_ + a, a) += q * T * T * T / 2.0;
      P(d_ + a, d_ + a) += q * T * T;
    }
  }
  // Joseph form for the applied gain K = [α, β/T]ᵀ ⊗ I_d and the plot's R.
  void update_covariance(Eigen::MatrixXd& P, AlphaBetaGains g, double T, const PositionScan& scan,
                         std::size_t i) const {
    Eigen::MatrixXd R(d_, d_);
    for (int a = 0, k = 0; a < d_; ++a)
      for (int b = a; b < d_; ++b, ++k) R(a, b) = R(b, a) = scan.R[k][i];
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(2 * d_, d_);
    K.topRows(d_).diagonal().setConstant(g.alpha);
    K.bottomRows(d_).diagonal().setConstant(g.beta / T);
    Eigen::MatrixXd A = Eigen::MatrixXd::Identity(2 * d_, 2 * d_);
    A.leftCols(d_) -= K;  // I − K H with H = [I_d 0]
    P = A * P * A.transpose() + K * R * K.transpose();
    P = 0.5 * (P + P.transpose());
  }

  int d_;
  double sigma_;
  AlphaBetaBank bank_;
  std::vector<Eigen::MatrixXd> P_;
  std::vector<uint8_t> initialised_;
};

// The seed 002 IMM {CS-parallel with network, CA σ = 5 m/s²} (kernels/filters/imm.hpp).
class ImmLocalBank final : public LocalFilterBank {
 public:
  ImmLocalBank(int d, std::size_t n) : bank_(d, n, ImmOptions::seed002(), trained_cs_network()) {}
  void step(double dt, const PositionScan& scan) override { imm_bank_step(bank_, dt, scan); }
  void initialise(std::size_t i, const Eigen::VectorXd& z1, const Eigen::MatrixXd& R1,
                  const Eigen::VectorXd& z2, const Eigen::MatrixXd& R2, double dt) override {
    bank_.initialise(i, z1, R1, z2, R2, dt, kAccelPriorVariance);
  }
  void position_velocity(std::size_t i, Eigen::VectorXd& x, Eigen::MatrixXd& P) const override {
    position_velocity_of(bank_.combined(), i, x, P);
  }
  std::vector<double> model_probabilities(std::size_t i) const override {
    std::vector<double> mu(bank_.num_models());
    for (int j = 0; j < bank_.num_models(); ++j) mu[j] = bank_.probability(i, j);
    return mu;
  }
  int num_models() const override { return bank_.num_models(); }

 private:
  ImmBank bank_;
};

struct SensorTracks {
  TrackTable table;
  std::vector<double> model_prob;
  int num_models = 0;
};

Eigen::MatrixXd unpack(int d, const std::array<double, 6>& R) {
  Eigen::MatrixXd M(d, d);
  for (int a = 0, k = 0; a < d; ++a)
    for (int b = a; b < d; ++b, ++k) M(a, b) = M(b, a) = R[k];
  return M;
}

// The lifecycle's deletions after a scan's update: M missed scans in a row. A deleted track waits
// for two new plots (have_first cleared).
void end_missed_tracks(const TrackLifecycle& life, const std::vector<uint8_t>& detected,
                       std::vector<uint8_t>& active, std::vector<uint8_t>& have_first,
                       std::vector<int32_t>& misses) {
  for (std::size_t i = 0; i < active.size(); ++i) {
    if (!active[i]) continue;
    misses[i] = detected[i] ? 0 : misses[i] + 1;
    if (misses[i] >= life.coast_scans) active[i] = have_first[i] = 0;
  }
}

// Whether an estimate lies beyond the sensor's coverage radius (0 = unlimited).
bool beyond_coverage(const Eigen::VectorXd& x, const Sensor& sensor, double radius) {
  if (radius <= 0.0) return false;
  const int d = static_cast<int>(x.size()) / 2;
  double r2 = 0.0;
  for (int a = 0; a < d; ++a) r2 += (x[a] - sensor.position[a]) * (x[a] - sensor.position[a]);
  return r2 > radius * radius;
}

SensorTracks track_one_sensor(const Measurements& meas, const std::vector<std::size_t>& rows,
                              const Sensor& sensor, std::size_t sensor_index, StateLayout layout,
                              const LocalTrackerSpec& spec, uint64_t seed, int run, std::vector<double> scans,
                              const TrackLifecycle& life) {
  const int d = spatial_dim(layout);
  SensorTracks out;
  out.table.reset(layout);
  // Targets seen by this sensor, in ascending id order = bank order.
  std::vector<int32_t> targets;
  for (std::size_t r : rows)
    if (meas.target[r] >= 0) targets.push_back(meas.target[r]);
  std::sort(targets.begin(), targets.end());
  targets.erase(std::unique(targets.begin(), targets.end()), targets.end());
  const std::size_t n = targets.size();
  if (scans.empty())
    for (std::size_t r : rows) scans.push_back(meas.t[r]);
  std::sort(scans.begin(), scans.end());
  scans.erase(std::unique(scans.begin(), scans.end()), scans.end());
  if (n == 0) return out;

  // Shuffled local track numbers: track_number[bank index].
  std::vector<int32_t> track_number(n);
  std::iota(track_number.begin(), track_number.end(), 0);
  CounterRng shuffle_rng(seed, static_cast<uint64_t>(run),
                         stream_id(SimulationStream::kShuffle, sensor_index));
  shuffle_rng.shuffle(std::span<int32_t>(track_number));
  std::vector<std::size_t> by_number(n);
  for (std::size_t i = 0; i < n; ++i) by_number[track_number[i]] = i;

  // Detections grouped by scan time (first detection of a target per scan wins).
  std::map<double, std::vector<std::size_t>> at_time;
  for (std::size_t r : rows)
    if (meas.target[r] >= 0) at_time[meas.t[r]].push_back(r);

  auto bank = make_local_filter_bank(spec, d, n);
  out.num_models = bank->num_models();
  std::vector<double> z[3], R[6];
  for (auto& c : z) c.assign(n, 0.0);
  for (auto& c : R) c.assign(n, 0.0);
  std::vector<uint8_t> detected(n, 0), active(n, 0), have_first(n, 0);
  std::vector<ConvertedMeasurement> first_plot(n);
  std::vector<double> first_time(n, 0.0);
  // Track lifecycle (TrackLifecycle): misses in a row, scan of the first plot, current number.
  const bool lifecycle = life.coast_scans > 0;
  std::vector<int32_t> misses(n, 0), number_of(n, -1);
  std::vector<long> first_scan(n, 0);
  int32_t next_number = 0;
  long scan_index = -1;
  std::vector<ConvertedMeasurement> plot(n);
  PositionScan scan;
  for (int a = 0; a < 3; ++a) scan.z[a] = z[a];
  for (int k = 0; k < 6; ++k) scan.R[k] = R[k];
  scan.detected = detected;

  double previous = scans.front();
  Eigen::VectorXd x;
  Eigen::MatrixXd P;
  for (double t : scans) {
    ++scan_index;
    std::fill(detected.begin(), detected.end(), 0);
    std::vector<uint8_t> seen(n, 0);
    if (auto it = at_time.find(t); it != at_time.end()) {
      for (std::size_t r : it->second) {
        const std::size_t i =
            std::lower_bound(targets.begin(), targets.end(), meas.target[r]) - targets.begin();
        if (seen[i]) continue;
        seen[i] = 1;
        const double el = meas.elevation.empty() ? 0.0 : meas.elevation[r];
        plot[i] = convert_polar(d, sensor, meas.range[r], meas.bearing[r], el);
        if (active[i]) {
          for (int a = 0; a < d; ++a) z[a][i] = plot[i].z[a];
          for (int k = 0; k < packed_size(d); ++k) R[k][i] = plot[i].R[k];
          detected[i] = 1;
        }
      }
    }
    bank->step(t - previous, scan);
    previous = t;
    if (lifecycle) end_missed_tracks(life, detected, active, have_first, misses);
    for (std::size_t i = 0; i < n; ++i) {
      if (!seen[i] || active[i]) continue;
      const bool close = !lifecycle || scan_index - first_scan[i] <= life.coast_scans;
      if (have_first[i] && t > first_time[i] && close) {
        bank->initialise(i, Eigen::Map<Eigen::VectorXd>(first_plot[i].z.data(), d),
                         unpack(d, first_plot[i].R), Eigen::Map<Eigen::VectorXd>(plot[i].z.data(), d),
                         unpack(d, plot[i].R), t - first_time[i]);
        active[i] = 1;
        misses[i] = 0;
        number_of[i] = next_number++;
      } else {
        first_plot[i] = plot[i];
        first_time[i] = t;
        first_scan[i] = scan_index;
        have_first[i] = 1;
      }
    }
    if (lifecycle) {  // bank order; a track's number is its own; an estimate beyond coverage ends it
      for (std::size_t i = 0; i < n; ++i) {
        if (!active[i]) continue;
        bank->position_velocity(i, x, P);
        if (beyond_coverage(x, sensor, life.coverage_radius)) {
          active[i] = have_first[i] = 0;
          continue;
        }
        out.table.push_back(sensor.id, number_of[i], t, x, P, targets[i]);
        if (out.num_models > 0) {
          const auto mu = bank->model_probabilities(i);
          out.model_prob.insert(out.model_prob.end(), mu.begin(), mu.end());
        }
      }
      continue;
    }
    for (int32_t number = 0; number < static_cast<int32_t>(n); ++number) {
      const std::size_t i = by_number[number];
      if (!active[i]) continue;
      bank->position_velocity(i, x, P);
      out.table.push_back(sensor.id, number, t, x, P, targets[i]);
      if (out.num_models > 0) {
        const auto mu = bank->model_probabilities(i);
        out.model_prob.insert(out.model_prob.end(), mu.begin(), mu.end());
      }
    }
  }
  return out;
}

void append(TrackTable& dst, const TrackTable& src) {
  dst.sensor.insert(dst.sensor.end(), src.sensor.begin(), src.sensor.end());
  dst.track.insert(dst.track.end(), src.track.begin(), src.track.end());
  dst.t.insert(dst.t.end(), src.t.begin(), src.t.end());
  dst.truth.insert(dst.truth.end(), src.truth.begin(), src.truth.end());
  for (std::size_t c = 0; c < dst.state.size(); ++c)
    dst.state[c].insert(dst.state[c].end(), src.state[c].begin(), src.state[c].end());
  for (std::size_t c = 0; c < dst.cov.size(); ++c)
    dst.cov[c].insert(dst.cov[c].end(), src.cov[c].begin(), src.cov[c].end());
}

}  // namespace

std::unique_ptr<LocalFilterBank> make_local_filter_bank(const LocalTrackerSpec& spec, int d, std::size_t n) {
  require(std::isfinite(spec.process_noise) && spec.process_noise >= 0.0, "tracker.process_noise",
          "expected a finite σ ≥ 0 [m/s²]");
  if (spec.filter == "cv")
    return std::make_unique<KalmanLocalBank>(KalmanModel::kConstantVelocity, spec.process_noise, d, n);
  if (spec.filter == "ca")
    return std::make_unique<KalmanLocalBank>(KalmanModel::kConstantAcceleration, spec.process_noise, d, n);
  if (spec.filter == "cs") return std::make_unique<CsLocalBank>(d, n);
  if (spec.filter == "cs-nn") return std::make_unique<CsParallelLocalBank>(d, n);
  if (spec.filter == "imm") return std::make_unique<ImmLocalBank>(d, n);
  if (spec.filter == "ab") return std::make_unique<AlphaBetaLocalBank>(spec.process_noise, d, n);
  throw InputError("tracker.filter: expected cv, ca, ab, cs, cs-nn or imm, got '" + spec.filter + "'");
}

LocalTrackingResult track_measurements(const Measurements& meas, const std::vector<Sensor>& sensors,
                                       StateLayout layout, const LocalTrackerSpec& spec, uint64_t seed,
                                       int run, const std::vector<std::vector<double>>& scan_times) {
  return track_measurements(meas, sensors, layout, std::vector<LocalTrackerSpec>(sensors.size(), spec), seed,
                            run, scan_times);
}

LocalTrackingResult track_measurements(const Measurements& meas, const std::vector<Sensor>& sensors,
                                       StateLayout layout, std::span<const LocalTrackerSpec> specs,
                                       uint64_t seed, int run,
                                       const std::vector<std::vector<double>>& scan_times,
                                       std::span<const TrackLifecycle> lifecycle) {
  require(lifecycle.empty() || lifecycle.size() == sensors.size(), "track_measurements.lifecycle",
          "expected none or one per sensor");
  require(specs.size() == sensors.size(), "track_measurements.specs",
          "expected one tracker per sensor (" + std::to_string(sensors.size()) + "), found " +
              std::to_string(specs.size()));
  for (const LocalTrackerSpec& spec : specs)
    make_local_filter_bank(spec, spatial_dim(layout), 0);  // validates the specs before any work
  require(scan_times.empty() || scan_times.size() == sensors.size(), "track_measurements.scan_times",
          "expected one list per sensor");
  if (spatial_dim(layout) == 3)
    require(meas.elevation.size() == meas.size(), "measurements.elevation",
            "a 3-D layout needs one elevation per measurement");
  std::map<int32_t, std::size_t> index_of;
  for (std::size_t s = 0; s < sensors.size(); ++s) index_of[sensors[s].id] = s;
  std::vector<std::vector<std::size_t>> rows(sensors.size());
  for (std::size_t r = 0; r < meas.size(); ++r) {
    auto it = index_of.find(meas.sensor[r]);
    require(it != index_of.end(), "measurements.sensor",
            "row " + std::to_string(r) + " names sensor " + std::to_string(meas.sensor[r]) +
                ", which is not in /sensors");
    rows[it->second].push_back(r);
  }
  std::vector<SensorTracks> parts(sensors.size());
  parallel_for_range(sensors.size(), 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t s = b; s < e; ++s)
      parts[s] = track_one_sensor(meas, rows[s], sensors[s], s, layout, specs[s], seed, run,
                                  scan_times.empty() ? std::vector<double>{} : scan_times[s],
                                  lifecycle.empty() ? TrackLifecycle{} : lifecycle[s]);
  });
  LocalTrackingResult result;
  result.tracks.reset(layout);
  bool one_model_set = true, first = true;  // every sensor with tracks has the same number of models
  std::size_t rows_total = 0;
  for (const auto& p : parts) rows_total += p.table.size();
  result.tracks.reserve(rows_total);
  for (auto& p : parts) {
    append(result.tracks, p.table);
    const bool has_rows = p.table.size() > 0;
    p.table = TrackTable{};  // freed at once: the result and one sensor's part at most, not two copies
    if (!has_rows) continue;
    if (first) result.num_models = p.num_models;
    first = false;
    one_model_set = one_model_set && p.num_models == result.num_models;
    result.model_prob.insert(result.model_prob.end(), p.model_prob.begin(), p.model_prob.end());
  }
  if (!one_model_set || result.num_models == 0) {
    result.num_models = 0;
    result.model_prob.clear();
  }
  return result;
}

}  // namespace trackassoc
