// The segment pass's graph and rule (a) (see segment_graph.hpp).
#include "engine/pipeline/segment_graph.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

#include "kernels/core/error.hpp"
#include "kernels/statistics/chi_square.hpp"

namespace trackassoc {

DuplicateStatistic duplicate_statistic(const AlignedTracks& a, int32_t i, int32_t j, double t_lo,
                                       double t_hi) {
  const int32_t D = a.dim;
  require(i >= 0 && i < a.n_tracks() && j >= 0 && j < a.n_tracks(), "duplicate_statistic",
          "track index out of range");
  Eigen::VectorXd diff(D);
  Eigen::MatrixXd C(D, D);
  DuplicateStatistic out;
  const AlignedTracks::Span both = common_span(a.span(i), a.span(j));  // the times both can exist
  for (int32_t k = both.begin; k < both.end; ++k) {
    const int64_t ci = a.cell(i, k), cj = a.cell(j, k);
    if (a.times[k] < t_lo || a.times[k] > t_hi || !a.valid[ci] || !a.valid[cj]) continue;
    const double *xi = a.state_at(ci), *xj = a.state_at(cj);
    for (int32_t c = 0; c < D; ++c) diff[c] = xi[c] - xj[c];
    const double *pi = a.cov_at(ci), *pj = a.cov_at(cj);  // packed upper triangles
    for (int32_t r = 0, q = 0; r < D; ++r)
      for (int32_t c = r; c < D; ++c, ++q) C(r, c) = C(c, r) = pi[q] + pj[q];
    const Eigen::LLT<Eigen::MatrixXd> llt(C);
    const double d2 =
        llt.info() == Eigen::Success ? diff.dot(llt.solve(diff)) : std::numeric_limits<double>::infinity();
    out.max_d2 = std::max(out.max_d2, d2);
    ++out.times;
  }
  return out;
}

namespace segments {

SegmentGraph build_graph(const SparseSDProblem& p, const TrackTable& tracks, double coast_growth) {
  SegmentGraph g{p, {}, {}, {}, {}, {}, {}, {}, {}, {}};
  const int32_t N = p.nodes(), S = p.S();
  g.first.assign(N, kInf);
  g.last.assign(N, -kInf);
  g.first_row.assign(N, 0);
  g.last_row.assign(N, 0);
  std::unordered_map<int32_t, int32_t> sensor_index;
  for (int32_t s = 0; s < S; ++s) sensor_index[p.sensor_ids[s]] = s;
  // (engine/pipeline/coasted_tail.hpp; none without the rule)
  std::vector<LatestReports>& latest = g.latest;
  latest.resize(coast_growth > 0.0 ? static_cast<std::size_t>(N) : 0);
  const int D = tracks.dim(), m = D / 2;
  for (std::size_t r = 0; r < tracks.size(); ++r) {
    auto it = sensor_index.find(tracks.sensor[r]);
    if (it == sensor_index.end()) continue;
    const int32_t u = g.node(it->second, tracks.track[r]);
    if (u < 0) continue;
    if (tracks.t[r] < g.first[u]) g.first[u] = tracks.t[r], g.first_row[u] = r;
    if (tracks.t[r] > g.last[u]) g.last[u] = tracks.t[r], g.last_row[u] = r;
    if (coast_growth > 0.0) {  // (0: no tail, the held end is the last report)
      double variance = 0.0;   // the trace of the position block (SoA columns: one per packed entry)
      for (int c = 0; c < m; ++c) variance += tracks.cov[packed_index(D, c, c)][r];
      latest[u].add(tracks.t[r], variance, r);
    }
  }
  g.held_last = g.last;
  g.held_row = g.last_row;
  for (int32_t u = 0; u < static_cast<int32_t>(latest.size()); ++u)
    if (latest[u].n > 0) {
      const int k = latest[u].held(coast_growth);
      g.held_last[u] = latest[u].t[k], g.held_row[u] = latest[u].row[k];
    }
  g.links.resize(N);
  for (int32_t a = 0; a < S; ++a)
    for (int32_t b = a + 1; b < S; ++b) {
      const std::size_t slot = static_cast<std::size_t>(a) * S + b;
      const SparsePairStatistic& st = p.pairs[slot];
      for (std::size_t q = 0; q < st.size(); ++q) {
        const int32_t u = p.offset[a] + st.a[q], v = p.offset[b] + st.b[q];
        const double c = p.link[slot][q];
        g.links[u].push_back({v, c});
        g.links[v].push_back({u, c});
        g.link_of[SegmentGraph::key(u, v)] = c;
      }
      if (slot < p.doubtful.size()) {
        const SparsePairStatistic& d = p.doubtful[slot];
        for (std::size_t q = 0; q < d.size(); ++q)
          g.link_of[SegmentGraph::key(p.offset[a] + d.a[q], p.offset[b] + d.b[q])] =
              doubtful_pair_entry(p.doubtful_link[slot][q]);
      }
    }
  return g;
}

OverlapRule make_overlap_rule(const SparseSDProblem& p, const SegmentOptions& o, const TrackTable& tracks,
                              const MergeGate& continuation) {
  OverlapRule r{&tracks,
                continuation,
                o.max_overlap_s,
                o.takeover_s,
                o.coast_growth,
                std::vector<uint8_t>(p.S(), 0),
                chi_square_quantile(o.duplicate_probability, p.dim),
                o.min_duplicate_times};
  check_duplicate_sensors(o, p.sensor_ids);
  for (const int32_t id : o.duplicate_sensors)
    r.duplicates[std::find(p.sensor_ids.begin(), p.sensor_ids.end(), id) - p.sensor_ids.begin()] = 1;
  return r;
}

}  // namespace segments
}  // namespace trackassoc
