// The indexed candidate search of fragment stitching; see engine/pipeline/stitch_index.hpp.
#include "engine/pipeline/stitch_index.hpp"

#include <algorithm>
#include <cmath>

namespace trackassoc {

namespace {

constexpr int32_t kLeaf = 16;            // points per leaf
constexpr double kRelativeSlack = 1e-7;  // the bound's widening against rounding (header)

}  // namespace

StitchStartIndex::Reach StitchStartIndex::reach_of(const TrackTable& t, std::size_t row,
                                                   int32_t position) const {
  const int D = t.dim(), d = d_;
  auto packed = [D](int r, int c) { return r * D - r * (r - 1) / 2 + (c - r); };  // r ≤ c
  Reach r;
  r.t = t.t[row];
  r.position = position;
  double v2 = 0.0, c = 0.0;
  for (int i = 0; i < d; ++i) {
    r.x[i] = t.state[i][row];
    v2 += t.state[d + i][row] * t.state[d + i][row];
    r.a += t.cov[packed(i, i)][row];
    r.b += std::fabs(t.cov[packed(i, d + i)][row]);
    c += t.cov[packed(d + i, d + i)][row];
  }
  r.c = std::max(0.0, c);
  if (std::isnan(c)) r.c = c;  // kept non-finite: never pruned
  r.speed = std::sqrt(v2);
  return r;
}

double StitchStartIndex::tau(double a, double b, double c, double h) const {
  return a + h * b + 0.25 * h * h * c + d_ * q_ * h * h * h / 24.0;
}

double StitchStartIndex::reach(const Reach& e, double a, double b, double c, double speed, double h) const {
  const double r =
      0.5 * h * (e.speed + speed) + std::sqrt(gate_ * std::max(0.0, tau(e.a, e.b, e.c, h) + tau(a, b, c, h)));
  return r * (1.0 + kRelativeSlack) + margin_;
}

namespace {

bool finite_reach(double t, const double* x, int d, double a, double b, double c, double speed) {
  bool ok =
      std::isfinite(t) && std::isfinite(a) && std::isfinite(b) && std::isfinite(c) && std::isfinite(speed);
  for (int i = 0; i < d; ++i) ok = ok && std::isfinite(x[i]);
  return ok;
}

}  // namespace

StitchStartIndex::StitchStartIndex(const TrackTable& t, const std::vector<std::size_t>& rows, double q,
                                   double gate, double max_overlap_s, double max_gap_s)
    : d_(t.dim() / 2), q_(q), gate_(gate), overlap_(max_overlap_s), gap_(max_gap_s) {
  times_.reserve(rows.size());
  points_.reserve(rows.size());
  double scale = 0.0, sum_a = 0.0, sum_b = 0.0, sum_c = 0.0, sum_speed = 0.0;
  for (std::size_t p = 0; p < rows.size(); ++p) {
    times_.push_back(t.t[rows[p]]);
    const Reach r = reach_of(t, rows[p], static_cast<int32_t>(p));
    if (!finite_reach(r.t, r.x, d_, r.a, r.b, r.c, r.speed)) {
      unbounded_.push_back(static_cast<int32_t>(p));
      continue;
    }
    for (int i = 0; i < d_; ++i) scale = std::max(scale, std::fabs(r.x[i]));
    sum_a += r.a, sum_b += r.b, sum_c += r.c, sum_speed += r.speed;
    points_.push_back(r);
  }
  if (points_.empty()) return;
  const double n = static_cast<double>(points_.size()), H = std::max({max_overlap_s, max_gap_s, 1.0});
  // The scene's scale for the absolute widening: positions and the farthest reach.
  margin_ = kRelativeSlack * (scale + H * sum_speed / n + 1.0);
  double time_scale =
      (0.5 * H * sum_speed / n + std::sqrt(gate * std::max(0.0, tau(sum_a / n, sum_b / n, sum_c / n, H)))) /
      H;
  if (!(time_scale > 0.0) || !std::isfinite(time_scale)) time_scale = 1.0;
  nodes_.reserve(2 * points_.size() / kLeaf + 2);
  build(0, static_cast<int32_t>(points_.size()), time_scale);
}

int32_t StitchStartIndex::build(int32_t begin, int32_t end, double time_scale) {
  const int32_t id = static_cast<int32_t>(nodes_.size());
  nodes_.emplace_back();
  Node n;
  n.begin = begin, n.end = end;
  n.t_lo = n.t_hi = points_[begin].t;
  for (int i = 0; i < d_; ++i) n.lo[i] = n.hi[i] = points_[begin].x[i];
  for (int32_t k = begin; k < end; ++k) {
    const Reach& r = points_[k];
    n.t_lo = std::min(n.t_lo, r.t), n.t_hi = std::max(n.t_hi, r.t);
    for (int i = 0; i < d_; ++i) n.lo[i] = std::min(n.lo[i], r.x[i]), n.hi[i] = std::max(n.hi[i], r.x[i]);
    n.a = std::max(n.a, r.a), n.b = std::max(n.b, r.b), n.c = std::max(n.c, r.c);
    n.speed = std::max(n.speed, r.speed);
  }
  if (end - begin > kLeaf) {
    // The longest side, time at time_scale metres a second; split at the median.
    int axis = -1;  // -1: time
    double longest = (n.t_hi - n.t_lo) * time_scale;
    for (int i = 0; i < d_; ++i)
      if (n.hi[i] - n.lo[i] > longest) longest = n.hi[i] - n.lo[i], axis = i;
    auto key = [axis](const Reach& r) { return axis < 0 ? r.t : r.x[axis]; };
    const int32_t mid = begin + (end - begin) / 2;
    std::nth_element(points_.begin() + begin, points_.begin() + mid, points_.begin() + end,
                     [&](const Reach& u, const Reach& v) { return key(u) < key(v); });
    n.left = build(begin, mid, time_scale);
    n.right = build(mid, end, time_scale);
  }
  nodes_[id] = n;
  return id;
}

std::pair<int32_t, int32_t> StitchStartIndex::window(double t_end) const {
  // As the scan of the window: starts ≥ t_end − max_overlap_s (lower_bound) and ≤ t_end + max_gap_s
  // (upper_bound).
  const auto lo = std::lower_bound(times_.begin(), times_.end(), t_end - overlap_);
  const auto hi = std::upper_bound(lo, times_.end(), t_end + gap_);
  return {static_cast<int32_t>(lo - times_.begin()), static_cast<int32_t>(hi - times_.begin())};
}

void StitchStartIndex::visit(int32_t id, const Reach& e, double t_lo, double t_hi,
                             std::vector<int32_t>& out) const {
  const Node& n = nodes_[id];
  if (n.t_hi < t_lo || n.t_lo > t_hi) return;
  // The largest gap the node's span allows within the window.
  const double h = std::max(std::fabs(std::max(n.t_lo, t_lo) - e.t), std::fabs(std::min(n.t_hi, t_hi) - e.t));
  const double r = reach(e, n.a, n.b, n.c, n.speed, h);
  double dist2 = 0.0;
  for (int i = 0; i < d_; ++i) {
    const double out_of_box = std::max({0.0, n.lo[i] - e.x[i], e.x[i] - n.hi[i]});
    dist2 += out_of_box * out_of_box;
  }
  if (dist2 > r * r) return;
  if (n.left >= 0) {
    visit(n.left, e, t_lo, t_hi, out);
    visit(n.right, e, t_lo, t_hi, out);
    return;
  }
  for (int32_t k = n.begin; k < n.end; ++k) {
    const Reach& s = points_[k];
    if (!(s.t >= t_lo && s.t <= t_hi)) continue;
    const double r = reach(e, s.a, s.b, s.c, s.speed, std::fabs(s.t - e.t));
    double d2 = 0.0;
    for (int i = 0; i < d_; ++i) d2 += (s.x[i] - e.x[i]) * (s.x[i] - e.x[i]);
    if (d2 <= r * r) out.push_back(s.position);
  }
}

void StitchStartIndex::query(const TrackTable& t, std::size_t end, std::vector<int32_t>& out) const {
  out.clear();
  const Reach e = reach_of(t, end, -1);
  const double t_lo = e.t - overlap_, t_hi = e.t + gap_;
  if (!finite_reach(e.t, e.x, d_, e.a, e.b, e.c, e.speed)) {  // never pruned: the whole window
    const auto [first, last] = window(e.t);
    for (int32_t p = first; p < last; ++p) out.push_back(p);
    return;
  }
  if (!nodes_.empty()) visit(0, e, t_lo, t_hi, out);
  for (int32_t p : unbounded_)
    if (times_[p] >= t_lo && times_[p] <= t_hi) out.push_back(p);
  std::sort(out.begin(), out.end());
}

}  // namespace trackassoc
