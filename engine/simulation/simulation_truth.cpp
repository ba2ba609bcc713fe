#include "engine/simulation/simulation_truth.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/core/error.hpp"

namespace trackassoc {

namespace {

Kinematics evaluate(const TrajectoryPiece& q, double t) {
  const double tau = t - q.t0;
  Kinematics k;
  const auto& s = q.start;
  if (q.turn_rate == 0.0) {
    for (int i = 0; i < 3; ++i) {
      k.p[i] = s.p[i] + s.v[i] * tau + 0.5 * s.a[i] * tau * tau;
      k.v[i] = s.v[i] + s.a[i] * tau;
      k.a[i] = s.a[i];
    }
    return k;
  }
  // Coordinated turn: v(τ) = Rot(ωτ) v0, p(τ) = p0 + ∫ v.
  const double w = q.turn_rate, c = std::cos(w * tau), sn = std::sin(w * tau);
  k.v = {s.v[0] * c - s.v[1] * sn, s.v[0] * sn + s.v[1] * c, s.v[2]};
  k.p = {s.p[0] + (s.v[0] * sn - s.v[1] * (1.0 - c)) / w, s.p[1] + (s.v[1] * sn + s.v[0] * (1.0 - c)) / w,
         s.p[2] + s.v[2] * tau};
  k.a = {-w * k.v[1], w * k.v[0], 0.0};
  return k;
}

}  // namespace

Kinematics TargetTrajectory::at(double t) const {
  if (pieces.empty()) return {};
  // Pieces are sorted; the last piece with t0 ≤ t holds t.
  auto it = std::upper_bound(pieces.begin(), pieces.end(), t,
                             [](double v, const TrajectoryPiece& q) { return v < q.t0; });
  const TrajectoryPiece& q = it == pieces.begin() ? pieces.front() : *std::prev(it);
  return evaluate(q, t);
}

std::array<double, 3> TargetTrajectory::position_at(double t, std::size_t& piece) const {
  if (pieces.empty()) return {0, 0, 0};
  while (piece + 1 < pieces.size() && pieces[piece + 1].t0 <= t) ++piece;
  return evaluate(pieces[piece], t).p;
}

void TargetTrajectory::append(double duration, const std::array<double, 3>& accel, double turn_rate) {
  TrajectoryPiece q;
  if (!pieces.empty()) {
    const TrajectoryPiece& last = pieces.back();
    q.t0 = last.t1;
    q.start = evaluate(last, last.t1);
  }
  q.t1 = q.t0 + duration;
  q.turn_rate = turn_rate;
  q.start.a = turn_rate == 0.0 ? accel : std::array<double, 3>{0, 0, 0};
  pieces.push_back(q);
}

TargetTrajectory scripted_trajectory(const TargetSpec& spec, double duration, int spatial_dim,
                                     CounterRng& rng) {
  TargetTrajectory tr;
  tr.id = spec.id;
  const auto& s0 = spec.initial_state;
  TrajectoryPiece first;
  first.start.p = {s0[0], s0[1], spatial_dim == 3 ? s0[2] : 0.0};
  first.start.v = {s0[3], s0[4], spatial_dim == 3 ? s0[5] : 0.0};
  auto axes = [&](std::array<double, 3> a) {
    if (spatial_dim == 2) a[2] = 0.0;
    return a;
  };
  double t = 0.0;
  bool started = false;
  auto push = [&](double len, const std::array<double, 3>& a, double w) {
    if (!started) {
      first.t0 = 0.0;
      first.t1 = len;
      first.turn_rate = w;
      first.start.a = w == 0.0 ? a : std::array<double, 3>{0, 0, 0};
      tr.pieces.push_back(first);
      started = true;
    } else {
      tr.append(len, a, w);
    }
    t += len;
  };
  for (std::size_t i = 0; i < spec.segments.size(); ++i) {
    const MotionSegment& seg = spec.segments[i];
    const bool last = i + 1 == spec.segments.size();
    const double len = last ? std::max(duration - t, seg.duration) : seg.duration;
    require(std::isfinite(len) && len >= 0.0,
            "targets[" + std::to_string(spec.id) + "].segments[" + std::to_string(i) + "].duration",
            "expected a finite duration ≥ 0");
    if (len == 0.0 && !last) continue;
    switch (seg.model) {
      case MotionModel::kConstantVelocity:
        push(len, {0, 0, 0}, 0.0);
        break;
      case MotionModel::kConstantAcceleration:
      case MotionModel::kAccelerationStep:
        push(len, axes(seg.acceleration), 0.0);
        break;
      case MotionModel::kCoordinatedTurn:
        push(len, {0, 0, 0}, seg.turn_rate);
        break;
      case MotionModel::kRandomManoeuvre: {
        require(
            seg.manoeuvre_period > 0.0,
            "targets[" + std::to_string(spec.id) + "].segments[" + std::to_string(i) + "].manoeuvre_period",
            "expected > 0");
        double done = 0.0;
        while (done < len - 1e-12) {
          const double piece = std::min(seg.manoeuvre_period, len - done);
          Kinematics k;
          if (started) {
            const auto& q = tr.pieces.back();
            k = evaluate(q, q.t1);
          } else {
            k = first.start;
          }
          const double speed = std::hypot(k.v[0], k.v[1]);
          const double heading = std::atan2(k.v[1], k.v[0]);
          const double dh = rng.uniform(-seg.max_turn_rate, seg.max_turn_rate) * seg.manoeuvre_period;
          const double ns = std::clamp(speed + rng.uniform(-seg.max_speed_change, seg.max_speed_change),
                                       seg.speed_min, seg.speed_max);
          const std::array<double, 3> nv{ns * std::cos(heading + dh), ns * std::sin(heading + dh), k.v[2]};
          push(piece, {(nv[0] - k.v[0]) / seg.manoeuvre_period, (nv[1] - k.v[1]) / seg.manoeuvre_period, 0.0},
               0.0);
          done += piece;
        }
        break;
      }
    }
  }
  if (!started) push(duration, {0, 0, 0}, 0.0);  // no segments: constant velocity
  return tr;
}

TargetTrajectory random_trajectory(const RandomTargetSpec& spec, int32_t id, double duration, double step,
                                   int spatial_dim, CounterRng& rng) {
  TargetTrajectory tr;
  tr.id = id;
  TrajectoryPiece first;
  for (int i = 0; i < spatial_dim; ++i) first.start.p[i] = rng.uniform(spec.area_min[i], spec.area_max[i]);
  const double speed = rng.uniform(spec.speed_min, spec.speed_max);
  const double heading = rng.uniform(spec.heading_min, spec.heading_max);
  first.start.v = {speed * std::cos(heading), speed * std::sin(heading), 0.0};
  const int steps = std::max(1, static_cast<int>(std::ceil(duration / step - 1e-9)));
  for (int k = 0; k < steps; ++k) {
    std::array<double, 3> a{0, 0, 0};
    for (int i = 0; i < spatial_dim; ++i) a[i] = spec.process_noise * rng.normal();
    if (k == 0) {
      first.t0 = 0.0;
      first.t1 = step;
      first.start.a = a;
      tr.pieces.push_back(first);
    } else {
      tr.append(step, a, 0.0);
    }
  }
  return tr;
}

std::vector<TargetTrajectory> random_group_trajectories(const RandomTargetSpec& spec, int32_t first_id,
                                                        int members, double duration, double step,
                                                        int spatial_dim, CounterRng& rng,
                                                        CounterRng& manoeuvre_rng) {
  const ManoeuvreSpec& man = spec.manoeuvres;
  if (members == 1 && !man.enabled)
    return {random_trajectory(spec, first_id, duration, step, spatial_dim, rng)};
  // The reference trajectory: the same initial draws as random_trajectory.
  TargetTrajectory ref;
  Kinematics start;
  for (int i = 0; i < spatial_dim; ++i) start.p[i] = rng.uniform(spec.area_min[i], spec.area_max[i]);
  const double speed0 = rng.uniform(spec.speed_min, spec.speed_max);
  const double heading0 = rng.uniform(spec.heading_min, spec.heading_max);
  start.v = {speed0 * std::cos(heading0), speed0 * std::sin(heading0), 0.0};
  auto push = [&](double len, const std::array<double, 3>& a, double w) {
    if (ref.pieces.empty()) {
      TrajectoryPiece q;
      q.t0 = 0.0;
      q.t1 = len;
      q.start = start;
      q.turn_rate = w;
      q.start.a = w == 0.0 ? a : std::array<double, 3>{0, 0, 0};
      ref.pieces.push_back(q);
    } else {
      ref.append(len, a, w);
    }
  };
  const double lo = 0.5 * spec.speed_min, hi = std::max(1.5 * spec.speed_max, lo);
  double t = 0.0;
  double next_manoeuvre = man.enabled ? manoeuvre_rng.uniform(man.interval_min, man.interval_max)
                                      : std::numeric_limits<double>::infinity();
  while (t < duration - 1e-9) {
    if (t < next_manoeuvre - 1e-9) {  // straight leg: white-noise acceleration per truth step
      const double len = std::min({step, next_manoeuvre - t, duration - t});
      std::array<double, 3> a{0, 0, 0};
      for (int i = 0; i < spatial_dim; ++i) a[i] = spec.process_noise * rng.normal();
      push(len, a, 0.0);
      t += len;
      continue;
    }
    // A manoeuvre: always the same four draws, so the stream stays aligned whatever the kind.
    const double len = std::min(manoeuvre_rng.uniform(man.duration_min, man.duration_max), duration - t);
    const bool turn = manoeuvre_rng.uniform() < man.p_turn;
    const double magnitude = manoeuvre_rng.uniform();
    const double sign = manoeuvre_rng.uniform() < 0.5 ? -1.0 : 1.0;
    if (turn) {
      const double w = sign * man.turn_rate_max * (1.0 + 2.0 * magnitude) / 3.0;
      push(len, {0, 0, 0}, w);
    } else {
      const Kinematics k = ref.pieces.empty() ? start : ref.at(ref.pieces.back().t1);
      const double s0 = std::sqrt(k.v[0] * k.v[0] + k.v[1] * k.v[1] + k.v[2] * k.v[2]);
      double a = sign * man.acceleration_max * magnitude;
      a = std::clamp(a, (lo - s0) / len, (hi - s0) / len);
      std::array<double, 3> acc{0, 0, 0};
      if (s0 > 0.0)
        for (int i = 0; i < 3; ++i) acc[i] = a * k.v[i] / s0;
      push(len, acc, 0.0);
    }
    t += len;
    next_manoeuvre = t + manoeuvre_rng.uniform(man.interval_min, man.interval_max);
  }
  if (ref.pieces.empty()) push(duration, {0, 0, 0}, 0.0);
  // Members: rigid copies of the reference (offset r, rotating with the turns).
  std::vector<TargetTrajectory> out(static_cast<std::size_t>(members));
  for (int j = 0; j < members; ++j) {
    TargetTrajectory& tr = out[j];
    tr.id = first_id + j;
    const double along = (j - 0.5 * (members - 1)) * spec.group_spacing;
    double rx = -std::sin(heading0) * along, ry = std::cos(heading0) * along;
    tr.pieces.reserve(ref.pieces.size());
    for (const TrajectoryPiece& q : ref.pieces) {
      TrajectoryPiece m = q;
      m.start.p[0] += rx;
      m.start.p[1] += ry;
      // v = v_ref + ω ẑ × r: a rigid rotation about the reference's turn centre.
      m.start.v[0] -= q.turn_rate * ry;
      m.start.v[1] += q.turn_rate * rx;
      tr.pieces.push_back(m);
      if (q.turn_rate != 0.0) {
        const double c = std::cos(q.turn_rate * (q.t1 - q.t0)), sn = std::sin(q.turn_rate * (q.t1 - q.t0));
        const double x = rx * c - ry * sn, y = rx * sn + ry * c;
        rx = x;
        ry = y;
      }
    }
  }
  return out;
}

}  // namespace trackassoc
