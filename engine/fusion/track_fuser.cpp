// Fused tracks of an association: see the header for the time grid and the cross-covariance.
#include "engine/fusion/track_fuser.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <span>

#include "engine/registration/registered_reports.hpp"
#include "io/scenario_json.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/local_track_rows.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/stopwatch.hpp"
#include "kernels/statistics/association_statistic.hpp"
#include "kernels/statistics/cross_covariance.hpp"

namespace trackassoc {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// One member of a tuple: its column, sensor id, track and its rows of /tracks sorted by time;
// `handed_over`: the spans of the later-starting tracks of its target on its sensor, during which
// the association's time slices give the target to them (engine/pipeline/track_segments.hpp).
struct Member {
  int32_t column = 0, sensor = 0, track = 0;
  std::span<const std::size_t> rows;  // its rows of /tracks in time order
  std::vector<std::pair<double, double>> handed_over;
  // The member holds its tuple's slot at time t: inside its span and not handed over.
  bool active(const TrackTable& tracks, double t) const {
    if (t < tracks.t[rows.front()] || t > tracks.t[rows.back()]) return false;
    for (const auto& [a, b] : handed_over)
      if (a <= t && t <= b) return false;
    return true;
  }
};

// The fused rows of one tuple, before they are concatenated in tuple order.
struct TupleRows {
  std::vector<double> t;
  std::vector<VectorXd> x;
  std::vector<MatrixXd> P;
  std::vector<int32_t> sources;
  std::vector<double> omega;  // per row S weights (ci)
  int64_t shrunk = 0;
};

// The rows of one member as a track table of their own (align_tracks reads a whole table).
TrackTable member_table(const TrackTable& tracks, const Member& m) {
  TrackTable sub(tracks.layout);
  sub.reserve(m.rows.size());
  for (std::size_t r : m.rows) {
    sub.sensor.push_back(m.sensor);
    sub.track.push_back(m.track);
    sub.t.push_back(tracks.t[r]);
    sub.truth.push_back(tracks.truth[r]);
    for (std::size_t c = 0; c < tracks.state.size(); ++c) sub.state[c].push_back(tracks.state[c][r]);
    for (std::size_t c = 0; c < tracks.cov.size(); ++c) sub.cov[c].push_back(tracks.cov[c][r]);
  }
  return sub;
}

MatrixXd unpack(const std::vector<double>& packed, std::size_t offset, int d) {
  MatrixXd M(d, d);
  for (int i = 0, p = 0; i < d; ++i)
    for (int j = i; j < d; ++j, ++p) M(i, j) = M(j, i) = packed[offset + p];
  return M;
}

MatrixXd principal_sqrt(const MatrixXd& P) {
  const Eigen::SelfAdjointEigenSolver<MatrixXd> es(P);
  return es.operatorSqrt();
}

// The fused times of a tuple: member report times at which ≥ 2 members are active (the header).
std::vector<double> fused_times(const TrackTable& tracks, const std::vector<Member>& members) {
  std::vector<double> times;
  for (const Member& m : members)
    for (std::size_t r : m.rows) times.push_back(tracks.t[r]);
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  std::erase_if(times, [&](double t) {
    int covering = 0;
    for (const Member& m : members) covering += m.active(tracks, t);
    return covering < 2;
  });
  return times;
}

TupleRows fuse_tuple(const TrackTable& tracks, const std::vector<Member>& members, int32_t S,
                     const TrackFuserOptions& o) {
  TupleRows out;
  const std::vector<double> grid = fused_times(tracks, members);
  if (grid.empty()) return out;
  const int D = tracks.dim(), P = packed_size(D);
  const int32_t K = static_cast<int32_t>(grid.size());
  const std::size_t m = members.size();
  // The latest report at or before each fused time, predicted (the grid lies within the spans, so
  // every member valid at k has one); no lag inflation, which widens a gate, not an estimate.
  AlignmentOptions align;
  align.method = AlignmentMethod::kForward;
  align.process_noise = o.process_noise;
  align.max_extrapolation = std::numeric_limits<double>::max();
  align.lag_inflation = 0.0;
  std::vector<AlignedTracks> a(m);
  for (std::size_t i = 0; i < m; ++i) {
    a[i] = align_tracks(member_table(tracks, members[i]), members[i].sensor, grid, align);
    const AlignedTracks::Span sp = a[i].span(0);
    for (int32_t k = sp.begin; k < sp.end; ++k) {  // not past its span, not while handed over
      const int64_t c = a[i].cell(0, k);
      a[i].valid[c] = a[i].valid[c] && members[i].active(tracks, grid[k]);
    }
  }
  const bool bsc = o.rule == FusionRule::kBarShalomCampo;
  const bool recursion = bsc && o.common_process_noise > 0.0;
  std::vector<std::vector<double>> gain(m);
  std::map<std::pair<std::size_t, std::size_t>, std::vector<double>> cross;  // (i < j) → P_ij per time
  if (recursion) {
    for (std::size_t i = 0; i < m; ++i) {
      // A at the member's own reports, from its consecutive reported covariances (the common
      // times are then its filter's update times, where gain_complements is exact); on the grid,
      // that A at its report times and I elsewhere (its estimate there is a prediction).
      std::vector<double> own;
      for (std::size_t r : members[i].rows) own.push_back(tracks.t[r]);
      own.erase(std::unique(own.begin(), own.end()), own.end());
      const TrackTable sub = member_table(tracks, members[i]);
      const AlignedTracks at_own = align_tracks(sub, members[i].sensor, own, align);
      const std::vector<double> own_gain = gain_complements(at_own, o.common_process_noise);
      gain[i].assign(static_cast<std::size_t>(a[i].cells()) * D * D, 0.0);  // per cell of a[i]
      const AlignedTracks::Span sp = a[i].span(0);
      for (int32_t k = sp.begin; k < sp.end; ++k) {
        const auto at = std::lower_bound(own.begin(), own.end(), grid[k]);
        double* g = &gain[i][static_cast<std::size_t>(a[i].cell(0, k)) * D * D];
        const int64_t oc = at != own.end() && *at == grid[k]
                               ? at_own.cell(0, static_cast<int32_t>(at - own.begin()))
                               : int64_t{-1};
        if (oc >= 0)
          std::copy_n(&own_gain[static_cast<std::size_t>(oc) * D * D], D * D, g);
        else
          for (int r = 0; r < D; ++r) g[r * D + r] = 1.0;
      }
    }
    for (std::size_t i = 0; i < m; ++i)
      for (std::size_t j = i + 1; j < m; ++j)
        cross[{i, j}] = cross_covariance_series(a[i], 0, gain[i], a[j], 0, gain[j], o.common_process_noise);
  }
  for (int32_t k = 0; k < K; ++k) {
    std::vector<std::size_t> present;
    std::vector<VectorXd> xs;
    std::vector<MatrixXd> Ps;
    for (std::size_t i = 0; i < m; ++i) {
      if (!a[i].valid_at(0, k)) continue;
      const int64_t c = a[i].cell(0, k);
      present.push_back(i);
      xs.push_back(Eigen::Map<const VectorXd>(a[i].state_at(c), D));
      Ps.push_back(unpack(a[i].cov, static_cast<std::size_t>(c) * P, D));
    }
    const std::size_t n = present.size();
    if (n < 2) continue;  // cannot happen on the grid; kept as a guard
    FusedEstimate f;
    if (o.rule == FusionRule::kNaive) {
      f = fuse_naive(xs, Ps);
    } else if (o.rule == FusionRule::kCovarianceIntersection) {
      f = fuse_covariance_intersection(xs, Ps, o.ci);
      std::vector<double> w(S, 0.0);
      for (std::size_t q = 0; q < n; ++q) w[members[present[q]].column] = f.omega[q];
      out.omega.insert(out.omega.end(), w.begin(), w.end());
    } else {
      // The joint covariance: blocks P_i on the diagonal, P_ij off it.
      MatrixXd joint = MatrixXd::Zero(n * D, n * D);
      std::vector<MatrixXd> roots;
      if (!recursion)
        for (const MatrixXd& Pi : Ps) roots.push_back(principal_sqrt(Pi));
      MatrixXd off = MatrixXd::Zero(n * D, n * D);
      for (std::size_t p = 0; p < n; ++p) {
        joint.block(p * D, p * D, D, D) = Ps[p];
        for (std::size_t q = p + 1; q < n; ++q) {
          MatrixXd Pij(D, D);
          if (recursion) {
            const std::vector<double>& series = cross.at({present[p], present[q]});
            for (int r = 0; r < D; ++r)
              for (int c = 0; c < D; ++c) Pij(r, c) = series[(static_cast<std::size_t>(k) * D + r) * D + c];
          } else {
            Pij = o.correlation * roots[p] * roots[q];
          }
          off.block(p * D, q * D, D, D) = Pij;
          off.block(q * D, p * D, D, D) = Pij.transpose();
        }
      }
      double scale = 1.0;
      for (int attempt = 0;; ++attempt) {
        const MatrixXd trial = joint + scale * off;
        if (Eigen::LLT<MatrixXd>(trial).info() == Eigen::Success || attempt == 60) {
          out.shrunk += attempt > 0;
          joint = trial;
          break;
        }
        scale *= 0.5;
      }
      f = n == 2 ? fuse_bar_shalom_campo(xs[0], Ps[0], xs[1], Ps[1], joint.block(0, D, D, D))
                 : fuse_with_cross_covariance(xs, joint);
    }
    out.t.push_back(grid[k]);
    out.x.push_back(f.x);
    out.P.push_back(f.P);
    out.sources.push_back(static_cast<int32_t>(n));
  }
  return out;
}

std::string rule_name(const TrackFuserOptions& o) { return enum_name(o.rule); }

}  // namespace

void TrackFuserOptions::validate() const {
  ci.validate();
  require(rule == FusionRule::kNaive || rule == FusionRule::kBarShalomCampo ||
              rule == FusionRule::kCovarianceIntersection,
          "TrackFuserOptions.rule", "unknown rule");
  require(std::isfinite(process_noise) && process_noise >= 0.0 && process_noise <= 1e3,
          "TrackFuserOptions.process_noise",
          "must be in [0, 1000] m/s², got " + std::to_string(process_noise));
  require(std::isfinite(common_process_noise) && common_process_noise >= 0.0 && common_process_noise <= 1e3,
          "TrackFuserOptions.common_process_noise",
          "must be in [0, 1000] m/s², got " + std::to_string(common_process_noise));
  require(std::isfinite(correlation) && correlation < 1.0, "TrackFuserOptions.correlation",
          "must be in [0, 1) (or < 0: not given), got " + std::to_string(correlation));
  const bool sigma = common_process_noise > 0.0, rho = correlation >= 0.0;
  if (rule == FusionRule::kBarShalomCampo)
    require(sigma != rho, "TrackFuserOptions",
            "rule bsc needs exactly one cross-covariance: common_process_noise (the Bar-Shalom–Campo "
            "recursion) or correlation (rho)");
  else
    require(
        !sigma && !rho, "TrackFuserOptions",
        std::string("common_process_noise and correlation apply to rule bsc only, not ") + enum_name(rule));
}

nlohmann::json TrackFuserOptions::to_json() const {
  nlohmann::json j{{"rule", enum_name(rule)}, {"process_noise", process_noise}};
  if (rule == FusionRule::kCovarianceIntersection)
    j["ci"] = {
        {"criterion", enum_name(ci.criterion)}, {"tolerance", ci.tolerance}, {"max_sweeps", ci.max_sweeps}};
  if (rule == FusionRule::kBarShalomCampo) {
    if (common_process_noise > 0.0) j["common_process_noise"] = common_process_noise;
    if (correlation >= 0.0) j["correlation"] = correlation;
  }
  return j;
}

FusedTrackRecord fuse_association(const TrackTable& tracks, const std::vector<Sensor>& sensors,
                                  const AssociationRecord& association, const TrackFuserOptions& options,
                                  const std::string& name, TrackFuserSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  options.validate();
  const int32_t S = association.num_sensors;
  require(S == static_cast<int32_t>(sensors.size()), "/associations/" + association.name + "/tuples",
          "expected one column per /sensors entry (" + std::to_string(sensors.size()) + "), found " +
              std::to_string(S));
  // Rows of each (sensor, track), by time.
  const LocalTrackRows rows = local_track_rows(tracks);

  const std::size_t K = association.num_tuples();
  std::vector<std::vector<Member>> members(K);
  std::vector<int32_t> truth(K, -1);
  TrackFuserSummary sum;
  sum.tuples = static_cast<int32_t>(K);
  for (std::size_t k = 0; k < K; ++k) {
    bool first = true, agree = true;
    for (int32_t s = 0; s < S; ++s) {
      const int32_t track = association.tuples[k * S + s];
      if (track < 0) continue;
      const std::size_t it = rows.find({sensors[s].id, track});
      require(it != rows.size(), "/associations/" + association.name + "/tuples",
              "row " + std::to_string(k) + ": sensor " + std::to_string(sensors[s].id) + " has no track " +
                  std::to_string(track) + " in /tracks");
      members[k].push_back({s, sensors[s].id, track, rows.rows(it), {}});
      const int32_t id = tracks.truth[rows.rows(it).back()];
      if (first) truth[k] = id;
      agree = agree && id == truth[k];
      first = false;
    }
    if (!agree) truth[k] = -1;
  }

  // Target numbers (segments and duplicates): a member yields its slot to the later-starting
  // tracks of its target on its sensor while they report, as the association's slices do.
  if (association.target.size() == K) {
    // (target, sensor) → the rows of its tracks, each track once (told apart by where its rows are)
    std::map<std::pair<int32_t, int32_t>, std::vector<std::span<const std::size_t>>> of_target;
    for (std::size_t k = 0; k < K; ++k)
      for (const Member& m : members[k]) {
        auto& v = of_target[{association.target[k], m.sensor}];
        if (std::none_of(v.begin(), v.end(), [&](auto o) { return o.data() == m.rows.data(); }))
          v.push_back(m.rows);
      }
    for (std::size_t k = 0; k < K; ++k)
      for (Member& m : members[k])
        for (const std::span<const std::size_t> other : of_target[{association.target[k], m.sensor}])
          if (tracks.t[other.front()] > tracks.t[m.rows.front()])
            m.handed_over.emplace_back(tracks.t[other.front()], tracks.t[other.back()]);
  }

  std::vector<TupleRows> fused(K);
  parallel_for_range(K, 1, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t k = lo; k < hi; ++k)
      if (members[k].size() >= 2) fused[k] = fuse_tuple(tracks, members[k], S, options);
  });

  FusedTrackRecord rec;
  rec.name = name;
  rec.association = association.name;
  rec.rule = rule_name(options);
  rec.ci_criterion =
      options.rule == FusionRule::kCovarianceIntersection ? enum_name(options.ci.criterion) : "";
  rec.cross_covariance = options.rule != FusionRule::kBarShalomCampo ? "none"
                         : options.common_process_noise > 0.0        ? "common-process-noise"
                                                                     : "correlation";
  rec.options_json = options.to_json().dump();
  rec.layout = tracks.layout;
  rec.num_sensors = S;
  rec.tuples = association.tuples;
  const int D = tracks.dim(), P = packed_size(D);
  rec.state.assign(D, {});
  rec.cov.assign(P, {});
  for (std::size_t k = 0; k < K; ++k) {
    const TupleRows& f = fused[k];
    if (members[k].size() < 2)
      ++sum.single_member;
    else if (f.t.empty())
      ++sum.no_overlap;
    else
      ++sum.fused_tuples;
    sum.shrunk_cells += f.shrunk;
    for (std::size_t i = 0; i < f.t.size(); ++i) {
      rec.tuple.push_back(static_cast<int32_t>(k));
      rec.t.push_back(f.t[i]);
      rec.sources.push_back(f.sources[i]);
      rec.truth.push_back(truth[k]);
      for (int c = 0; c < D; ++c) rec.state[c].push_back(f.x[i][c]);
      for (int r = 0, p = 0; r < D; ++r)
        for (int c = r; c < D; ++c, ++p) rec.cov[p].push_back(f.P[i](r, c));
    }
    rec.omega.insert(rec.omega.end(), f.omega.begin(), f.omega.end());
  }
  sum.rows = static_cast<int64_t>(rec.size());
  sum.cross_covariance = rec.cross_covariance;
  sum.runtime_s = seconds_since(start);
  sum.termination = "fused " + std::to_string(sum.fused_tuples) + " of " + std::to_string(sum.tuples) +
                    " tuples (" + std::to_string(sum.single_member) + " with fewer than two members, " +
                    std::to_string(sum.no_overlap) + " whose members never coexist)";
  if (summary) *summary = sum;
  return rec;
}

TrackFuserSummary fuse_track_file(TrackFile& file, const std::string& association, const std::string& name,
                                  TrackFuserOptions options, const std::string& path) {
  const AssociationRecord* rec = nullptr;
  std::string names;
  for (const auto& a : file.associations) {
    names += (names.empty() ? "" : ", ") + a.name;
    if (a.name == association) rec = &a;
  }
  if (file.associations.empty()) throw InputError("/associations is empty; run `trackassoc associate` first");
  if (association.empty()) {
    if (file.associations.size() != 1)
      throw InputError("--association: the file has " + std::to_string(file.associations.size()) +
                       " associations (" + names + "); name one");
    rec = &file.associations.front();
  }
  if (!rec)
    throw InputError("--association: no /associations/" + association + " in the file (it has " + names +
                     ")");
  std::string source;
  if (options.rule == FusionRule::kBarShalomCampo) {
    if (options.common_process_noise > 0.0)
      source = "given";
    else if (options.correlation >= 0.0)
      source = "given";
    else if (!file.scenario_json.empty()) {
      const Scenario sc = parse_scenario_json(file.scenario_json, "/ attribute scenario");
      options.common_process_noise = sc.tracker.process_noise;
      source = "the scenario's tracker.process_noise";
      require(options.common_process_noise > 0.0, "--rule bsc",
              "the file's scenario has tracker.process_noise 0; give --common-process-noise SIGMA or "
              "--correlation RHO");
    } else {
      throw InputError(
          "--rule bsc: the file carries no process-noise information (no scenario); give the "
          "cross-covariance: "
          "--common-process-noise SIGMA (the targets' white-noise acceleration the local CV filters assume, "
          "m/s²) or --correlation RHO (P_ab = RHO·P_a^½ P_b^½)");
    }
  }
  const std::string out_name = name.empty() ? rec->name : name;
  // The association's registration, when the stage applied it: the same correction of every report.
  const std::optional<RegistrationRecord>& reg = file.registration;
  std::string why;
  std::optional<TrackTable> registered;
  if (!options.registration)
    why = "not applied (switched off): reports as recorded";
  else if (!reg)
    why = "no /registration in the file: reports as recorded";
  else if (reg->association != rec->name)
    why = "/registration belongs to /associations/" + reg->association + ": reports as recorded";
  else if (!reg->applied)
    why = "/registration was not applied by the association: reports as recorded";
  else {
    const RecordedRegistration r = recorded_registration(file, path, *reg);
    // A reference the user named (a sensor they trust) gives its frame; one chosen by the stage
    // (the sensor with the most tracks) the sensors' information-weighted average.
    const bool named = reg->reference_named;
    registered = registered_file(file, r.estimate, r.model,
                                 named ? RegistrationFrame::kReference : RegistrationFrame::kCentroid)
                     .tracks;
    why = named ? "reports corrected by /registration into the frame of reference sensor " +
                      std::to_string(reg->reference_sensor) + " (named by the association)"
                : "reports corrected by /registration into the sensors' information-weighted average frame "
                  "(estimated relative to reference sensor " +
                      std::to_string(reg->reference_sensor) + ", chosen by the stage)";
  }
  TrackFuserSummary summary;
  FusedTrackRecord fused = fuse_association(registered ? *registered : file.tracks, file.sensors, *rec,
                                            options, out_name, &summary);
  summary.cross_covariance_source = source;
  summary.registered = registered.has_value();
  summary.registration = why;
  nlohmann::json j = nlohmann::json::parse(fused.options_json);
  j["registration"] = summary.registered;
  fused.options_json = j.dump();
  std::erase_if(file.fused, [&](const FusedTrackRecord& r) { return r.name == out_name; });
  file.fused.push_back(std::move(fused));
  return summary;
}

}  // namespace trackassoc
