// Joint registration and association; see engine/pipeline/registration_stage.hpp.
#include "engine/pipeline/registration_stage.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <span>
#include <string>

#include "io/memory_budget.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/local_track_rows.hpp"
#include "kernels/statistics/chi_square.hpp"

namespace trackassoc {

namespace {

// Rows of every local track, in time order (kernels/core/local_track_rows.hpp). --memory-budget
// (io/memory_budget.hpp) is checked first; the tracks are counted as the changes of key from row to
// row (no allocation: exact when the table is grouped by track, as files are written, and an upper
// bound otherwise).
LocalTrackRows rows_of_tracks(const TrackTable& t) {
  std::size_t tracks = 0;
  for (std::size_t r = 0; r < t.size(); ++r)
    tracks += r == 0 || t.sensor[r] != t.sensor[r - 1] || t.track[r] != t.track[r - 1];
  require_memory_beside_held(0.0, bytes_of_local_track_rows(t.size(), tracks),
                             "the registration stage's rows per local track (" + std::to_string(t.size()) +
                                 " reports, at most " + std::to_string(tracks) + " local tracks)");
  return local_track_rows(t);
}

bool positions_unknown(const TrackFile& file) {
  return file.recording.sensors_unknown.find("position") != std::string::npos;
}

std::vector<std::array<double, 3>> sites_of(const TrackFile& file) {
  std::vector<std::array<double, 3>> sites;
  for (const Sensor& s : file.sensors) sites.push_back(s.position);
  return sites;
}

// The registration model for `file`: `fit`, or a translation and a clock offset when the file says
// the sensor positions are unknown (/sensors attr unknown).
RegistrationOptions model_for(const TrackFile& file, const RegistrationOptions& fit) {
  RegistrationOptions o = fit;
  if (positions_unknown(file)) {
    o.polar = false;
    o.site_offset = true;
  }
  return o;
}

}  // namespace

void RegistrationStageOptions::validate() const {
  require(max_rounds >= 2 && max_rounds <= 20, "registration.max_rounds", "expected 2..20");
  require(significance > 0.0 && significance < 1.0, "registration.significance",
          "expected a level in (0, 1)");
  require(max_observations_per_pair >= 1, "registration.max_observations_per_pair", "expected >= 1");
  require(std::isfinite(max_gap) && max_gap > 0.0, "registration.max_gap", "expected a finite gap > 0 [s]");
  require(std::isfinite(pattern_radius) && pattern_radius > 0.0, "registration.pattern_radius",
          "expected a finite radius > 0 [m]");
  require(pattern_tracks >= 1, "registration.pattern_tracks", "expected >= 1");
  require(std::isfinite(min_effect) && min_effect >= 0.0, "registration.min_effect",
          "expected a finite effect >= 0 [squared sigmas per scan]");
  fit.validate();
}

nlohmann::json RegistrationStageOptions::to_json() const {
  return {{"enabled", enabled},
          {"reassociate", reassociate},
          {"max_rounds", max_rounds},
          {"significance", significance},
          {"min_effect", min_effect},
          {"max_observations_per_pair", max_observations_per_pair},
          {"max_gap", max_gap},
          {"reference_sensor", reference_sensor},
          {"pattern_radius", pattern_radius},
          {"pattern_tracks", pattern_tracks},
          {"polar", fit.polar},
          {"site_offset", fit.site_offset},
          {"clock_offset", fit.clock_offset},
          {"prior_range", fit.prior_range},
          {"prior_azimuth", fit.prior_azimuth},
          {"prior_elevation", fit.prior_elevation},
          {"prior_site_offset", fit.prior_site_offset},
          {"prior_clock", fit.prior_clock},
          {"huber", fit.huber}};
}

RegistrationRecord RegistrationStageResult::to_record(const TrackFile& file, const std::string& association,
                                                      const RegistrationStageOptions& options) const {
  RegistrationRecord r;
  const std::size_t S = file.sensors.size();
  for (const Sensor& s : file.sensors) r.sensor.push_back(s.id);
  r.reference_sensor = file.sensors.at(static_cast<std::size_t>(estimate.reference)).id;
  r.parameters = estimate.parameter_names;
  r.estimate = estimate.bias;
  r.standard_error = estimate.standard_error;
  r.covariance = estimate.covariance;
  r.covariance_scale = estimate.covariance_scale;
  r.pair_observations = estimate.pair_observations;
  if (r.covariance_scale.size() != S * S) r.covariance_scale.assign(S * S, std::nan(""));
  if (r.pair_observations.size() != S * S) r.pair_observations.assign(S * S, 0);
  r.applied = applied;
  r.rounds = rounds;
  r.wald = wald;
  r.wald_dof = wald_dof;
  r.effect = effect;
  r.observations = static_cast<int64_t>(estimate.summary.observations);
  r.association = association;
  r.reference_named = options.reference_sensor >= 0;
  r.options_json = options.to_json().dump();
  return r;
}

namespace {

// Appends the observations of one pair of local tracks, rows A (column a) and B (column b) in
// time order: A's reports inside B's span, B interpolated between its reports around each.
void add_pair_observations(RegistrationObservations& obs, const TrackTable& t, std::span<const std::size_t> A,
                           std::span<const std::size_t> B, int32_t a, int32_t b, int64_t cluster,
                           const RegistrationStageOptions& o) {
  const int D = t.dim(), d = D / 2;
  auto position_cov = [&](std::size_t r, Eigen::MatrixXd& P) {
    for (int i = 0; i < d; ++i)
      for (int j = 0; j < d; ++j) P(i, j) = t.cov[packed_index(D, std::min(i, j), std::max(i, j))][r];
  };
  std::vector<double> xa(d), xb(d), va(d), vb(d);
  Eigen::MatrixXd Pa(d, d), Pb0(d, d), Pb1(d, d);
  std::vector<std::pair<std::size_t, std::size_t>> usable;  // (A index, B index of the report at or after)
  for (std::size_t ia = 0; ia < A.size(); ++ia) {
    const std::size_t r = A[ia];
    auto it =
        std::lower_bound(B.begin(), B.end(), t.t[r], [&](std::size_t x, double v) { return t.t[x] < v; });
    if (it == B.end()) continue;
    if (t.t[*it] != t.t[r] && (it == B.begin() || t.t[*it] - t.t[*std::prev(it)] > o.max_gap)) continue;
    usable.push_back({ia, static_cast<std::size_t>(it - B.begin())});
  }
  const std::size_t n = usable.size(), m = std::min<std::size_t>(n, o.max_observations_per_pair);
  for (std::size_t j = 0; j < m; ++j) {
    const auto [ia, k] = usable[(2 * j + 1) * n / (2 * m)];  // evenly spread, centred
    const std::size_t r = A[ia];
    const std::size_t r1 = B[k], r0 = t.t[r1] == t.t[r] ? r1 : B[k - 1];
    const double w = r1 == r0 ? 0.0 : (t.t[r] - t.t[r0]) / (t.t[r1] - t.t[r0]);
    // The clock column's velocities: central differences of the reported positions, not the
    // reported velocities, whose errors a filter correlates with its position errors (P_pv):
    // regressed on them, the position differences give a clock offset where there is none
    // (docs/design.md §4.10). A's reports before and after; B's two reports around the time, or,
    // when one falls on A's time, those either side of it. Symmetric differences only: at a
    // track's end (or across a gap over 2·max_gap) the reported velocity.
    auto symmetric = [&](std::size_t lo, std::size_t hi) {
      return t.t[hi] > t.t[lo] && t.t[hi] - t.t[lo] <= 2 * o.max_gap;
    };
    const bool chord_a = ia > 0 && ia + 1 < A.size() && symmetric(A[ia - 1], A[ia + 1]);
    std::size_t b0 = r0, b1 = r1;
    if (r0 == r1 && k > 0 && k + 1 < B.size()) b0 = B[k - 1], b1 = B[k + 1];
    const bool chord_b = symmetric(b0, b1);  // false when b0 = b1: no symmetric pair
    auto chord = [&](std::size_t lo, std::size_t hi, int i) {
      return (t.state[i][hi] - t.state[i][lo]) / (t.t[hi] - t.t[lo]);
    };
    for (int i = 0; i < d; ++i) {
      xa[i] = t.state[i][r];
      va[i] = chord_a ? chord(A[ia - 1], A[ia + 1], i) : t.state[d + i][r];
      xb[i] = (1 - w) * t.state[i][r0] + w * t.state[i][r1];
      vb[i] = chord_b ? chord(b0, b1, i) : (1 - w) * t.state[d + i][r0] + w * t.state[d + i][r1];
    }
    position_cov(r, Pa);
    position_cov(r0, Pb0);
    position_cov(r1, Pb1);
    const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> C =
        Pa + (1 - w) * Pb0 + w * Pb1;
    obs.add(a, b, cluster, xa, xb, va, vb,
            std::span<const double>(C.data(), static_cast<std::size_t>(d * d)));
  }
}

// A track's position at time tm (linear between its reports; tm inside its span) and the trace
// of its position covariance there.
void position_at(const TrackTable& t, std::span<const std::size_t> rows, double tm, double* x, double& var) {
  const int D = t.dim(), d = D / 2;
  auto it =
      std::lower_bound(rows.begin(), rows.end(), tm, [&](std::size_t r, double v) { return t.t[r] < v; });
  if (it == rows.end()) it = std::prev(it);
  const std::size_t r1 = *it, r0 = it == rows.begin() ? r1 : *std::prev(it);
  const double w = t.t[r1] == t.t[r0] ? 1.0 : std::clamp((tm - t.t[r0]) / (t.t[r1] - t.t[r0]), 0.0, 1.0);
  var = 0.0;
  for (int i = 0; i < d; ++i) {
    x[i] = (1 - w) * t.state[i][r0] + w * t.state[i][r1];
    var += t.cov[packed_index(D, i, i)][r1];
  }
}

// Members of tuples of two or more: the local tracks an association links to another sensor's.
std::size_t linked_members(const AssociationRecord& rec) {
  std::size_t n = 0;
  const int32_t S = rec.num_sensors;
  for (std::size_t q = 0; q < rec.num_tuples(); ++q) {
    std::size_t m = 0;
    for (int32_t s = 0; s < S; ++s) m += rec.tuples[q * S + s] >= 0;
    if (m >= 2) n += m;
  }
  return n;
}

}  // namespace

RegistrationObservations registration_observations(const TrackFile& file, const AssociationRecord& rec,
                                                   const RegistrationStageOptions& o) {
  RegistrationObservations obs;
  obs.dim = file.tracks.dim() / 2;
  const auto rows = rows_of_tracks(file.tracks);
  const int32_t S = rec.num_sensors;
  for (std::size_t q = 0; q < rec.num_tuples(); ++q)
    for (int32_t a = 0; a < S; ++a)
      for (int32_t b = a + 1; b < S; ++b) {
        const int32_t ta = rec.tuples[q * S + a], tb = rec.tuples[q * S + b];
        if (ta < 0 || tb < 0) continue;
        const std::size_t ia = rows.find({file.sensors[a].id, ta}), ib = rows.find({file.sensors[b].id, tb});
        if (ia == rows.size() || ib == rows.size()) continue;
        add_pair_observations(obs, file.tracks, rows.rows(ia), rows.rows(ib), a, b,
                              static_cast<int64_t>(q) * S * S + a * S + b, o);
      }
  return obs;
}

RegistrationObservations pattern_observations(const TrackFile& file, int32_t reference,
                                              const RegistrationStageOptions& o) {
  const TrackTable& t = file.tracks;
  const int d = t.dim() / 2;
  RegistrationObservations obs;
  obs.dim = d;
  const auto rows = rows_of_tracks(t);
  const int32_t S = static_cast<int32_t>(file.sensors.size());
  std::vector<std::vector<std::span<const std::size_t>>> keys(S);  // per sensor column: its tracks' rows
  std::map<int32_t, int32_t> column;
  for (int32_t s = 0; s < S; ++s) column[file.sensors[s].id] = s;
  for (std::size_t k = 0; k < rows.size(); ++k) keys[column.at(rows.key[k].first)].push_back(rows.rows(k));
  // Each track's bounding box, so that pairs farther apart than pattern_radius everywhere are
  // skipped without interpolating them (the pattern step is O(sample · n) box tests).
  std::vector<std::vector<std::array<double, 6>>> box(S);
  for (int32_t s = 0; s < S; ++s)
    for (const std::span<const std::size_t> track_rows : keys[s]) {
      std::array<double, 6> b{1e300, 1e300, 1e300, -1e300, -1e300, -1e300};
      for (std::size_t r : track_rows)
        for (int i = 0; i < d; ++i)
          b[i] = std::min(b[i], t.state[i][r]), b[3 + i] = std::max(b[3 + i], t.state[i][r]);
      box[s].push_back(b);
    }
  auto near = [&](const std::array<double, 6>& a, const std::array<double, 6>& b) {
    for (int i = 0; i < d; ++i)
      if (a[i] > b[3 + i] + o.pattern_radius || b[i] > a[3 + i] + o.pattern_radius) return false;
    return true;
  };
  const auto& ref = keys[reference];
  const std::size_t sample = std::min<std::size_t>(ref.size(), o.pattern_tracks);
  struct Candidate {
    std::size_t a, b;  // indices into keys[reference], keys[s]
    double diff[3];
    double sigma;
  };
  for (int32_t s = 0; s < S; ++s) {
    if (s == reference) continue;
    std::vector<Candidate> cand;
    for (std::size_t i = 0; i < sample; ++i) {
      const std::size_t ia = sample == ref.size() ? i : i * ref.size() / sample;
      const std::span<const std::size_t> A = ref[ia];
      for (std::size_t ib = 0; ib < keys[s].size(); ++ib) {
        if (!near(box[reference][ia], box[s][ib])) continue;
        const std::span<const std::size_t> B = keys[s][ib];
        const double lo = std::max(t.t[A.front()], t.t[B.front()]),
                     hi = std::min(t.t[A.back()], t.t[B.back()]);
        if (lo > hi) continue;
        double xa[3] = {0, 0, 0}, xb[3] = {0, 0, 0}, va = 0, vb = 0;
        position_at(t, A, 0.5 * (lo + hi), xa, va);
        position_at(t, B, 0.5 * (lo + hi), xb, vb);
        Candidate c{ia, ib, {xa[0] - xb[0], xa[1] - xb[1], xa[2] - xb[2]}, std::sqrt((va + vb) / d)};
        if (std::sqrt(c.diff[0] * c.diff[0] + c.diff[1] * c.diff[1] + c.diff[2] * c.diff[2]) <=
            o.pattern_radius)
          cand.push_back(c);
      }
    }
    if (cand.empty()) continue;
    // The mode of the differences: the candidate with the most others within ρ = 3·(median σ).
    std::vector<double> sig;
    for (const auto& c : cand) sig.push_back(c.sigma);
    std::nth_element(sig.begin(), sig.begin() + sig.size() / 2, sig.end());
    const double rho = 3.0 * sig[sig.size() / 2];
    auto dist = [&](const double* u, const double* v) {
      return std::sqrt((u[0] - v[0]) * (u[0] - v[0]) + (u[1] - v[1]) * (u[1] - v[1]) +
                       (u[2] - v[2]) * (u[2] - v[2]));
    };
    // Counted through a grid of cells of side ρ (the neighbours within ρ lie in the 3^3 cells
    // around): the same counts as comparing every pair, O(candidates × neighbours) instead of
    // O(candidates²) (a dense line of 2 500 targets gave 75 000 candidates per sensor: 65 s).
    std::vector<std::size_t> within(cand.size(), 0);
    if (rho > 0.0) {
      auto cell = [&](const double* u, int k) { return static_cast<int64_t>(std::floor(u[k] / rho)); };
      std::map<std::array<int64_t, 3>, std::vector<std::size_t>> grid;
      for (std::size_t i = 0; i < cand.size(); ++i)
        grid[{cell(cand[i].diff, 0), cell(cand[i].diff, 1), cell(cand[i].diff, 2)}].push_back(i);
      for (std::size_t i = 0; i < cand.size(); ++i) {
        const int64_t c0 = cell(cand[i].diff, 0), c1 = cell(cand[i].diff, 1), c2 = cell(cand[i].diff, 2);
        for (int64_t x = c0 - 1; x <= c0 + 1; ++x)
          for (int64_t y = c1 - 1; y <= c1 + 1; ++y)
            for (int64_t z = c2 - 1; z <= c2 + 1; ++z)
              if (const auto it = grid.find({x, y, z}); it != grid.end())
                for (std::size_t j : it->second) within[i] += dist(cand[i].diff, cand[j].diff) <= rho;
      }
    } else {
      for (std::size_t i = 0; i < cand.size(); ++i)
        for (const auto& c : cand) within[i] += dist(cand[i].diff, c.diff) <= rho;
    }
    std::size_t best = 0, best_count = 0;
    for (std::size_t i = 0; i < cand.size(); ++i)
      if (within[i] > best_count) best = i, best_count = within[i];
    double mode[3] = {0, 0, 0};
    for (const auto& c : cand)
      if (dist(cand[best].diff, c.diff) <= rho)
        for (int k = 0; k < 3; ++k) mode[k] += c.diff[k] / static_cast<double>(best_count);
    // Seeds: mutual nearest to the mode, within ρ of it.
    std::map<std::size_t, std::pair<double, std::size_t>> best_of_a, best_of_b;  // -> (distance, candidate)
    for (std::size_t i = 0; i < cand.size(); ++i) {
      const double e = dist(cand[i].diff, mode);
      if (e > rho) continue;
      auto& ba = best_of_a.try_emplace(cand[i].a, e, i).first->second;
      if (e < ba.first) ba = {e, i};
      auto& bb = best_of_b.try_emplace(cand[i].b, e, i).first->second;
      if (e < bb.first) bb = {e, i};
    }
    for (const auto& [a, e] : best_of_a) {
      const Candidate& c = cand[e.second];
      if (best_of_b.at(c.b).second != e.second) continue;
      add_pair_observations(obs, t, ref[c.a], keys[s][c.b], reference, s,
                            static_cast<int64_t>(s) * (1 << 30) + static_cast<int64_t>(e.second), o);
    }
  }
  return obs;
}

RegistrationEffect registration_effect(const RegistrationObservations& obs, const RegistrationEstimate& e,
                                       const RegistrationOptions& model,
                                       std::span<const std::array<double, 3>> sites) {
  const int d = obs.dim, K = e.k();
  const std::size_t S = static_cast<std::size_t>(e.sensors);
  RegistrationEffect out;
  out.delta.assign(S, 0.0);
  out.pairs.assign(S, 0);
  std::vector<std::size_t> count(S, 0);
  std::vector<std::set<int64_t>> clusters(S);
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const int32_t a = obs.sensor_a[i], b = obs.sensor_b[i];
    const std::size_t o = i * static_cast<std::size_t>(d);
    const std::span<const double> xa(obs.position_a.data() + o, d), xb(obs.position_b.data() + o, d),
        va(obs.velocity_a.data() + o, d), vb(obs.velocity_b.data() + o, d);
    const Eigen::VectorXd m = registration_jacobian(model, d, sites[a], xa, va) * e.sensor_bias(a) -
                              registration_jacobian(model, d, sites[b], xb, vb) * e.sensor_bias(b);
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> C(
        obs.covariance.data() + i * static_cast<std::size_t>(d) * d, d, d);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(C.eval());
    if (ldlt.info() != Eigen::Success) continue;
    const double delta = m.dot(ldlt.solve(m));
    for (const int32_t s : {a, b}) {
      out.delta[s] += delta;
      ++count[s];
      clusters[s].insert(obs.cluster[i]);
    }
  }
  for (std::size_t s = 0; s < S; ++s) {
    if (count[s] > 0) out.delta[s] /= static_cast<double>(count[s]);
    out.pairs[s] = static_cast<int64_t>(clusters[s].size());
    if (static_cast<int32_t>(s) != e.reference && out.pairs[s] > K)
      out.largest = std::max(out.largest, out.delta[s]);
  }
  return out;
}

AssociationRecord associate_with_registration(
    const TrackFile& file, const RegistrationStageOptions& o,
    const std::function<AssociationRecord(const TrackFile&)>& associate, RegistrationStageResult* result) {
  o.validate();
  RegistrationStageResult local;
  RegistrationStageResult& res = result ? *result : local;
  res = RegistrationStageResult{};
  AssociationRecord rec = associate(file);
  res.rounds = 1;
  if (!o.enabled || file.sensors.size() < 2) return rec;
  const RegistrationOptions model = model_for(file, o.fit);
  const std::vector<std::array<double, 3>> sites = sites_of(file);
  // The reference: the sensor asked for, else the one with the most local tracks.
  RegistrationOptions m = model;
  {
    std::map<int32_t, std::set<int32_t>> tracks_of;
    for (std::size_t r = 0; r < file.tracks.size(); ++r)
      tracks_of[file.tracks.sensor[r]].insert(file.tracks.track[r]);
    std::size_t most = 0;
    for (std::size_t s = 0; s < file.sensors.size(); ++s) {
      const std::size_t n = tracks_of[file.sensors[s].id].size();
      if (n > most) most = n, m.reference_sensor = static_cast<int32_t>(s);
    }
    bool found = o.reference_sensor < 0;
    for (std::size_t s = 0; s < file.sensors.size(); ++s)
      if (file.sensors[s].id == o.reference_sensor)
        m.reference_sensor = static_cast<int32_t>(s), found = true;
    if (!found)
      throw InputError("--reference-sensor: expected a /sensors id of the file, found " +
                       std::to_string(o.reference_sensor));
  }
  auto fit = [&](const RegistrationObservations& obs, RegistrationEstimate& est) {
    if (obs.size() == 0) return false;
    est = fit_registration(obs, sites, m);
    return true;
  };
  // The first fit: on the pattern seeds (bias-tolerant), else on the first association's tuples.
  RegistrationObservations seeds = pattern_observations(file, m.reference_sensor, o);
  if (seeds.size() == 0) seeds = registration_observations(file, rec, o);
  if (!fit(seeds, res.estimate)) return rec;
  res.fitted = true;
  res.wald = res.estimate.wald(res.wald_dof);
  if (res.wald_dof == 0 || res.wald <= chi_square_quantile(1.0 - o.significance, res.wald_dof)) return rec;
  if (!o.reassociate) return rec;
  // Practical significance (step 3b): a correction that moves no sensor's pairs by min_effect
  // cannot split or join true pairs, so the association of step 1 stands.
  res.effect = registration_effect(seeds, res.estimate, m, sites).largest;
  if (res.effect < o.min_effect) return rec;
  const AssociationRecord recorded = rec;
  const RegistrationEstimate tested = res.estimate;
  std::optional<TrackFile> corrected;  // the reports of the latest association
  for (int32_t round = 2; round <= o.max_rounds; ++round) {
    corrected = registered_file(file, res.estimate, model);
    AssociationRecord next = associate(*corrected);
    res.rounds = round;
    const bool same = next.tuples == rec.tuples && next.target == rec.target;
    rec = std::move(next);
    if (same || round == o.max_rounds) break;
    RegistrationEstimate refit;
    if (!fit(registration_observations(file, rec, o), refit)) break;
    res.estimate = std::move(refit);
    res.wald = res.estimate.wald(res.wald_dof);
  }
  // A registration error shows as true pairs split apart: the corrected reports must link more
  // local tracks than the reports as recorded, or the association of step 1 stands.
  res.applied = linked_members(rec) > linked_members(recorded);
  if (res.applied) {
    res.registered = std::move(corrected);
    return rec;
  }
  // Not applied: the estimate reported is the one tested in step 3 (as over MPI ranks).
  res.estimate = tested;
  res.wald = res.estimate.wald(res.wald_dof);
  return recorded;
}

}  // namespace trackassoc
