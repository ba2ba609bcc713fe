// Fragment stitching by track segment association; see engine/pipeline/track_stitching.hpp.
#include "engine/pipeline/track_stitching.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>

#include "kernels/assignment/lap_sparse.hpp"
#include "kernels/core/error.hpp"
#include "kernels/statistics/chi_square.hpp"

namespace trackassoc {

void TrackStitchOptions::validate() const {
  require(std::isfinite(max_gap_s) && max_gap_s > 0.0, "stitching.max_gap_s", "expected a gap > 0 [s]");
  require(std::isfinite(max_overlap_s) && max_overlap_s >= 0.0, "stitching.max_overlap_s",
          "expected an overlap >= 0 [s]");
  require(std::isfinite(manoeuvre_sigma) && manoeuvre_sigma >= 0.0, "stitching.manoeuvre_sigma",
          "expected σ >= 0 [m/s²]");
  require(std::isfinite(turn_sigma) && turn_sigma >= 0.0, "stitching.turn_sigma", "expected σ >= 0 [m/s²]");
  require(turn_probability >= 0.0 && turn_probability <= 1.0, "stitching.turn_probability",
          "expected a probability in [0, 1]");
  require(gate_probability > 0.0 && gate_probability < 1.0, "stitching.gate_probability",
          "expected a probability in (0, 1)");
  require(std::isfinite(turn_min_evidence), "stitching.turn_min_evidence",
          "expected a finite log-likelihood ratio");
}

namespace {

// Fixed capacity (D ≤ 6): no heap allocation per candidate.
using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;
using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;

// Row r's state and covariance predicted by dt (either sign) with CV and Q(|dt|) of q = σ_a²;
// Q's cross term follows F's direction (Bar-Shalom, Li, Kirubarajan 2001 §6.2.2).
void predict(const TrackTable& t, std::size_t r, double dt, double q, Vector& x, Matrix& P) {
  const int D = t.dim(), d = D / 2;
  const double a = std::fabs(dt), sgn = dt < 0 ? -1.0 : 1.0;
  Matrix F = Matrix::Identity(D, D), Q = Matrix::Zero(D, D), P0(D, D);
  for (int i = 0; i < d; ++i) {
    F(i, d + i) = dt;
    Q(i, i) = q * a * a * a / 3.0;
    Q(i, d + i) = Q(d + i, i) = sgn * q * a * a / 2.0;
    Q(d + i, d + i) = q * a;
  }
  Vector x0(D);
  for (int i = 0; i < D; ++i) x0[i] = t.state[i][r];
  for (int i = 0, k = 0; i < D; ++i)
    for (int j = i; j < D; ++j, ++k) P0(i, j) = P0(j, i) = t.cov[k][r];
  x = F * x0;
  P = F * P0 * F.transpose() + Q;
}

// ln(e^a + e^b) without overflow.
double log_sum_exp(double a, double b) {
  const double m = std::max(a, b);
  return m == -std::numeric_limits<double>::infinity() ? m : m + std::log(std::exp(a - m) + std::exp(b - m));
}

struct Group {
  int32_t target = 0;
  std::size_t first = 0, last = 0;  // rows of the earliest and the latest report
};

}  // namespace

GapStatistic gap_statistic(const TrackTable& t, std::size_t end, std::size_t start, double q) {
  const int D = t.dim();
  const double tm = 0.5 * (t.t[end] + t.t[start]);
  Vector x1, x2;
  Matrix P1, P2;
  predict(t, end, tm - t.t[end], q, x1, P1);
  predict(t, start, tm - t.t[start], q, x2, P2);
  const Vector e = x1 - x2;
  const Eigen::LDLT<Matrix> S(P1 + P2);
  GapStatistic g;
  g.m2 = e.dot(S.solve(e));
  g.log_det = D * std::log(2.0 * std::numbers::pi);
  for (int i = 0; i < D; ++i) g.log_det += std::log(S.vectorD()[i]);
  return g;
}

namespace {

// A conservative pre-gate without a factorisation: the position part's m² is at most the full
// m² (a marginal's Mahalanobis form never exceeds the joint one) and at least |e_p|²/trace(S_pp),
// so |e_p|² > gate·trace(S_pp) means m² > gate. Far pairs (most of them in a wide scene) are
// refused from the diagonal alone; the joins are exactly those without it.
bool surely_outside(const TrackTable& t, std::size_t end, std::size_t start, double q, double gate) {
  const int D = t.dim(), d = D / 2;
  auto packed = [D](int r, int c) { return r * D - r * (r - 1) / 2 + (c - r); };  // r ≤ c
  const double tm = 0.5 * (t.t[end] + t.t[start]);
  double e2 = 0.0, trace = 0.0;
  for (int i = 0; i < d; ++i) {
    double e = 0.0;
    for (const auto& [r, sign] : {std::pair{end, 1.0}, std::pair{start, -1.0}}) {
      const double dt = tm - t.t[r], a = std::fabs(dt);
      e += sign * (t.state[i][r] + dt * t.state[d + i][r]);
      trace += t.cov[packed(i, i)][r] + 2.0 * dt * t.cov[packed(i, d + i)][r] +
               dt * dt * t.cov[packed(d + i, d + i)][r] + q * a * a * a / 3.0;
    }
    e2 += e * e;
  }
  return e2 > gate * trace;
}

}  // namespace

double join_cost(const TrackTable& t, std::size_t end, std::size_t start, const TrackStitchOptions& o,
                 double gate, bool* quiet_gated) {
  if (surely_outside(t, end, start, o.turn_sigma * o.turn_sigma, gate))
    return std::numeric_limits<double>::infinity();
  const GapStatistic turn = gap_statistic(t, end, start, o.turn_sigma * o.turn_sigma);
  if (!(turn.m2 <= gate)) return std::numeric_limits<double>::infinity();
  const GapStatistic quiet = gap_statistic(t, end, start, o.manoeuvre_sigma * o.manoeuvre_sigma);
  if (quiet_gated) *quiet_gated = quiet.m2 <= gate;
  const double minus_inf = -std::numeric_limits<double>::infinity();
  const double l_quiet = o.turn_probability < 1.0
                             ? std::log1p(-o.turn_probability) - 0.5 * (quiet.m2 + quiet.log_det)
                             : minus_inf;
  const double l_turn =
      o.turn_probability > 0.0 ? std::log(o.turn_probability) - 0.5 * (turn.m2 + turn.log_det) : minus_inf;
  return -log_sum_exp(l_quiet, l_turn);
}

TrackStitchSummary stitch_fragments(const TrackFile& file, AssociationRecord& rec,
                                    const TrackStitchOptions& o) {
  o.validate();
  TrackStitchSummary summary;
  const int32_t S = rec.num_sensors;
  if (!o.enabled || S != static_cast<int32_t>(file.sensors.size()) || rec.num_tuples() == 0) return summary;
  const TrackTable& t = file.tracks;
  const std::size_t K = rec.num_tuples();
  std::vector<int32_t> target = rec.target;
  if (target.empty()) {  // every tuple its own target
    target.resize(K);
    std::iota(target.begin(), target.end(), 0);
  }
  // (sensor id, track) -> target number.
  std::map<std::pair<int32_t, int32_t>, int32_t> target_of;
  for (std::size_t k = 0; k < K; ++k)
    for (int32_t s = 0; s < S; ++s)
      if (rec.tuples[k * S + s] >= 0) target_of[{file.sensors[s].id, rec.tuples[k * S + s]}] = target[k];
  std::map<int32_t, Group> by_target;
  for (std::size_t r = 0; r < t.size(); ++r) {
    const auto it = target_of.find({t.sensor[r], t.track[r]});
    if (it == target_of.end()) continue;
    auto [g, fresh] = by_target.try_emplace(it->second);
    Group& G = g->second;
    if (fresh) G.target = it->second, G.first = G.last = r;
    if (t.t[r] < t.t[G.first]) G.first = r;
    if (t.t[r] > t.t[G.last]) G.last = r;
  }
  std::vector<const Group*> groups;
  for (const auto& [k, g] : by_target) groups.push_back(&g);
  const std::size_t G = groups.size();
  summary.groups = static_cast<int32_t>(G);
  std::vector<std::size_t> by_start(G);
  std::iota(by_start.begin(), by_start.end(), 0);
  std::sort(by_start.begin(), by_start.end(),
            [&](std::size_t a, std::size_t b) { return t.t[groups[a]->first] < t.t[groups[b]->first]; });
  std::vector<double> starts;
  for (std::size_t i : by_start) starts.push_back(t.t[groups[i]->first]);
  // "Different targets": a start uniform over the box of the groups' start states.
  const int D = t.dim();
  double log_volume = 0.0;
  for (int i = 0; i < D; ++i) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Group* g : groups)
      lo = std::min(lo, t.state[i][g->first]), hi = std::max(hi, t.state[i][g->first]);
    log_volume += std::log(std::max(hi - lo, 1.0));
  }
  // Candidates (rows: ends, columns: starts) with a cost of positive evidence, in CSR form.
  const double gate = chi_square_quantile(o.gate_probability, D);
  struct Candidate {
    int32_t end, start;
    double cost;
    bool quiet;
  };
  std::vector<Candidate> candidates;
  std::vector<int32_t> rivals_of_end(G, 0), rivals_of_start(G, 0);
  for (std::size_t a = 0; a < G; ++a) {
    const double end = t.t[groups[a]->last];
    auto lo = std::lower_bound(starts.begin(), starts.end(), end - o.max_overlap_s);
    const auto hi = std::upper_bound(lo, starts.end(), end + o.max_gap_s);
    // "A different target": any of the n starts of the window, each uniform over the box, so the
    // density of the alternative is n / V (the density of new starts of MHT's track score).
    const double log_alternative = log_volume - std::log(std::max<double>(1.0, static_cast<double>(hi - lo)));
    for (auto it = lo; it != hi; ++it) {
      const std::size_t b = by_start[static_cast<std::size_t>(it - starts.begin())];
      if (b == a || t.t[groups[b]->last] <= end) continue;           // b must go on after a ends
      if (t.t[groups[a]->first] >= t.t[groups[b]->first]) continue;  // and start after a starts
      bool quiet = false;
      const double c = join_cost(t, groups[a]->last, groups[b]->first, o, gate, &quiet);
      if (!std::isfinite(c)) continue;
      ++summary.candidates;
      ++rivals_of_end[a], ++rivals_of_start[b];
      if (c - log_alternative < 0.0)
        candidates.push_back({static_cast<int32_t>(a), static_cast<int32_t>(b), c - log_alternative, quiet});
    }
  }
  // A join that only the manoeuvring model gates is made only when it is unambiguous (neither side
  // has another gated candidate) and its evidence is at least turn_min_evidence. Its wide gate
  // takes in unrelated starts where traffic is dense, while a lone turning fragment
  // (recorded_recycled) is still joined; see the header for the measurements.
  std::vector<int32_t> row_start{0}, col;
  std::vector<double> cost;
  std::size_t next = 0;
  for (std::size_t a = 0; a < G; ++a) {
    for (; next < candidates.size() && candidates[next].end == static_cast<int32_t>(a); ++next) {
      const Candidate& k = candidates[next];
      if (!k.quiet &&
          (rivals_of_end[k.end] > 1 || rivals_of_start[k.start] > 1 || -k.cost < o.turn_min_evidence))
        continue;
      col.push_back(k.start);
      cost.push_back(k.cost);
    }
    row_start.push_back(static_cast<int32_t>(col.size()));
  }
  if (col.empty()) return summary;
  SparseCostView view;
  view.rows = view.cols = static_cast<int32_t>(G);
  view.row_start = row_start;
  view.col = col;
  view.cost = cost;
  LapOptions lap;
  lap.allow_unassigned = true;  // "no successor" / "no predecessor" at cost 0
  const LapResult joins = solve_gated_lap(view, lap);
  // Union-find over group indices; the root keeps the earliest group's target number.
  std::vector<std::size_t> parent(G);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::size_t a = 0; a < G; ++a) {
    if (joins.row_to_col[a] < 0) continue;
    const std::size_t ra = find(a), rb = find(static_cast<std::size_t>(joins.row_to_col[a]));
    if (ra == rb) continue;
    if (t.t[groups[rb]->first] < t.t[groups[ra]->first])  // the root is the group that starts first
      parent[ra] = rb;
    else
      parent[rb] = ra;
    ++summary.stitches;
  }
  if (summary.stitches == 0) return summary;
  std::map<int32_t, int32_t> renumber;
  for (std::size_t g = 0; g < G; ++g) renumber[groups[g]->target] = groups[find(g)]->target;
  for (auto& number : target) {
    const auto it = renumber.find(number);
    if (it != renumber.end()) number = it->second;
  }
  rec.target = std::move(target);
  return summary;
}

}  // namespace trackassoc
