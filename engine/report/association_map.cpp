#include "engine/report/association_map.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "engine/pipeline/metrics.hpp"

namespace trackassoc::report {
namespace {

using TrackKey = std::pair<int32_t, int32_t>;  // (tuple column, local track)

// Distinct colours for output targets; no red (wrong links) and no grey (unassociated tracks).
constexpr Rgb kTargetColours[] = {rgb(0x1f77b4), rgb(0xff7f0e), rgb(0x2ca02c), rgb(0x9467bd),
                                  rgb(0x8c564b), rgb(0xe377c2), rgb(0xbcbd22), rgb(0x17becf),
                                  rgb(0x393b79), rgb(0xe6ab02), rgb(0x637939), rgb(0x7b4173)};
constexpr Marker kSensorMarkers[] = {Marker::kCircle, Marker::kSquare, Marker::kTriangle, Marker::kDiamond,
                                     Marker::kTriangleDown};
constexpr Rgb kUnassociated = rgb(0xa8a8a8), kWrong = rgb(0xd62728), kInk = rgb(0x222222);

struct Path {
  std::vector<double> t, x, y;  // by time
};

// Rows of `table` grouped by key and ordered by time: x, y of the state in km.
template <typename KeyOf>
std::map<TrackKey, Path> paths_by(std::size_t rows, const std::vector<double>& t,
                                  const std::vector<std::vector<double>>& state, KeyOf key_of) {
  std::map<TrackKey, std::vector<std::size_t>> rows_of;
  for (std::size_t r = 0; r < rows; ++r) {
    const auto key = key_of(r);
    if (key.first >= 0) rows_of[key].push_back(r);
  }
  std::map<TrackKey, Path> paths;
  for (auto& [key, idx] : rows_of) {
    std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return t[a] < t[b]; });
    Path& p = paths[key];
    for (std::size_t r : idx) {
      p.t.push_back(t[r]);
      p.x.push_back(1e-3 * state[0][r]);
      p.y.push_back(1e-3 * state[1][r]);
    }
  }
  return paths;
}

// The report of `p` nearest in time to `t`.
std::size_t nearest_report(const Path& p, double t) {
  const auto it = std::lower_bound(p.t.begin(), p.t.end(), t);
  std::size_t i = static_cast<std::size_t>(it - p.t.begin());
  if (i == p.t.size()) return i - 1;
  if (i > 0 && t - p.t[i - 1] < p.t[i] - t) return i - 1;
  return i;
}

}  // namespace

void draw_association_map(Canvas& c, const TrackFile& file, const AssociationRecord& rec,
                          const std::string& title) {
  const int32_t S = rec.num_sensors;
  const std::size_t K = rec.num_tuples();
  std::map<int32_t, int32_t> column_of_sensor;
  for (int32_t s = 0; s < static_cast<int32_t>(file.sensors.size()); ++s)
    column_of_sensor[file.sensors[s].id] = s;
  const TrackTable& tt = file.tracks;
  const auto tracks = paths_by(tt.size(), tt.t, tt.state, [&](std::size_t r) {
    const auto it = column_of_sensor.find(tt.sensor[r]);
    return TrackKey{it == column_of_sensor.end() ? -1 : it->second, tt.track[r]};
  });

  // The output target of each track in a tuple of two or more members.
  std::map<TrackKey, int32_t> target_of;
  std::set<int32_t> targets;
  for (std::size_t q = 0; q < K; ++q) {
    int members = 0;
    for (int32_t s = 0; s < S; ++s) members += rec.tuples[q * S + s] >= 0;
    if (members < 2) continue;
    const int32_t g = rec.target.size() == K ? rec.target[q] : static_cast<int32_t>(q);
    targets.insert(g);
    for (int32_t s = 0; s < S; ++s)
      if (rec.tuples[q * S + s] >= 0) target_of[{s, rec.tuples[q * S + s]}] = g;
  }
  // Colours in the order of the targets, so neighbouring numbers differ.
  std::map<int32_t, Rgb> colour_of;
  for (int32_t g : targets)
    colour_of[g] = kTargetColours[colour_of.size() % (sizeof kTargetColours / sizeof kTargetColours[0])];

  AssociationDetail detail;
  const AssociationMetrics metrics = evaluate_association(tt, file.sensors, rec, &detail);
  std::map<TrackKey, Path> missed_truth;
  if (metrics.has_truth && file.truth) {
    const TruthTable& truth = *file.truth;
    const auto all = paths_by(truth.size(), truth.t, truth.state, [&](std::size_t r) {
      return TrackKey{truth.target[r], 0};
    });
    for (const auto& [target, outcome] : detail.outcome)
      if (outcome == TargetOutcome::kMissed && all.count({target, 0}))
        missed_truth[{target, 0}] = all.at({target, 0});
  }

  // The data box: every track and every dashed truth path, 4 % margin, one km as long on both axes.
  PlotArea area;
  area.left = 80, area.top = 64, area.width = 760, area.height = c.height() - 64 - 70;
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  auto extend = [&](const Path& p) {
    for (std::size_t i = 0; i < p.t.size(); ++i)
      x0 = std::min(x0, p.x[i]), x1 = std::max(x1, p.x[i]), y0 = std::min(y0, p.y[i]),
      y1 = std::max(y1, p.y[i]);
  };
  for (const auto& [key, p] : tracks) extend(p);
  for (const auto& [key, p] : missed_truth) extend(p);
  if (!(x0 <= x1)) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  const double pad = 0.04 * std::max({x1 - x0, y1 - y0, 1e-3});
  area.x0 = x0 - pad, area.x1 = x1 + pad, area.y0 = y0 - pad, area.y1 = y1 + pad;
  area.equal_aspect();
  const std::string unit = file.recording.frame == "NED"   ? " (north)"
                           : file.recording.frame == "ENU" ? " (east)"
                                                           : "";
  const std::string unit_y = file.recording.frame == "NED"   ? " (east)"
                             : file.recording.frame == "ENU" ? " (north)"
                                                             : "";
  area.draw_axes(c, "x [km]" + unit, "y [km]" + unit_y);

  auto points_of = [&](const Path& p) {
    std::vector<Point> pts;
    for (std::size_t i = 0; i < p.t.size(); ++i) pts.push_back({area.px(p.x[i]), area.py(p.y[i])});
    return pts;
  };
  // Layers: unassociated tracks, missed targets' truth, associated tracks, wrong links, markers.
  int unassociated = 0;
  for (const auto& [key, p] : tracks)
    if (!target_of.count(key)) {
      c.polyline(points_of(p), {kUnassociated, 1.3});
      ++unassociated;
    }
  for (const auto& [key, p] : missed_truth) c.polyline(points_of(p), {kInk, 1.6, {7, 5}});
  for (const auto& [key, p] : tracks)
    if (target_of.count(key)) c.polyline(points_of(p), {colour_of[target_of[key]], 2.2, {}, 0.9});
  int wrong_links = 0;
  if (metrics.has_truth) {
    const auto truth_of = local_track_truth(tt, file.sensors, rec);
    for (std::size_t q : detail.false_tuple_rows)
      for (int32_t a = 0; a < S; ++a)
        for (int32_t b = a + 1; b < S; ++b) {
          const TrackKey ka{a, rec.tuples[q * S + a]}, kb{b, rec.tuples[q * S + b]};
          if (ka.second < 0 || kb.second < 0 || !tracks.count(ka) || !tracks.count(kb)) continue;
          const int32_t ta = truth_of.count(ka) ? truth_of.at(ka) : -1,
                        tb = truth_of.count(kb) ? truth_of.at(kb) : -1;
          if (ta >= 0 && ta == tb) continue;  // this link is right; another of the tuple is not
          const Path &pa = tracks.at(ka), &pb = tracks.at(kb);
          const double lo = std::max(pa.t.front(), pb.t.front()), hi = std::min(pa.t.back(), pb.t.back());
          const double t =
              lo <= hi ? 0.5 * (lo + hi)
                       : 0.5 * (std::min(pa.t.back(), pb.t.back()) + std::max(pa.t.front(), pb.t.front()));
          const std::size_t ia = nearest_report(pa, t), ib = nearest_report(pb, t);
          const Point a_px{area.px(pa.x[ia]), area.py(pa.y[ia])}, b_px{area.px(pb.x[ib]), area.py(pb.y[ib])};
          c.line(a_px.x, a_px.y, b_px.x, b_px.y, {kWrong, 2.6});
          // A ring around the link: tracks of a formation are a few pixels apart at map scale.
          const double r = 0.5 * std::hypot(a_px.x - b_px.x, a_px.y - b_px.y) + 9.0;
          std::vector<Point> ring;
          for (int k = 0; k <= 40; ++k)
            ring.push_back({0.5 * (a_px.x + b_px.x) + r * std::cos(k * M_PI / 20),
                            0.5 * (a_px.y + b_px.y) + r * std::sin(k * M_PI / 20)});
          c.polyline(ring, {kWrong, 2.0});
          ++wrong_links;
        }
  }
  const int marker_kinds = static_cast<int>(sizeof kSensorMarkers / sizeof kSensorMarkers[0]);
  for (const auto& [key, p] : tracks) {
    const Rgb fill = target_of.count(key) ? colour_of[target_of[key]] : kUnassociated;
    c.marker(area.px(p.x.back()), area.py(p.y.back()), kSensorMarkers[key.first % marker_kinds], 8, fill,
             kInk);
  }

  // Title, the counts, and the legend to the right of the map.
  c.text(area.left, 26, title, kInk, Anchor::kStart, Face::kBold);
  std::string counts = std::to_string(tracks.size()) + " local tracks of " +
                       std::to_string(file.sensors.size()) + " sensors, " + std::to_string(targets.size()) +
                       " output targets, " + std::to_string(unassociated) + " tracks unassociated";
  if (metrics.has_truth)
    counts += "; of " + std::to_string(metrics.targets) +
              " targets seen by 2+ sensors: " + std::to_string(metrics.correct) + " correct, " +
              std::to_string(metrics.false_associations) + " false, " + std::to_string(metrics.missed) +
              " missed";
  c.text(area.left, 48, counts, kInk);

  double lx = area.left + area.width + 24, ly = area.top + 14;
  c.text(lx, ly, "local tracks", kInk, Anchor::kStart, Face::kBold);
  ly += 24;
  for (int k = 0; k < 3; ++k)
    c.line(lx + 8 * k, ly - 4 + 2 * k, lx + 8 * k + 22, ly - 8 + 2 * k, {kTargetColours[k], 2.2});
  c.text(lx + 50, ly, "coloured by output target", kInk);
  ly += 22;
  c.line(lx, ly - 4, lx + 40, ly - 4, {kUnassociated, 1.3});
  c.text(lx + 50, ly, "in no tuple (unassociated)", kInk);
  ly += 30;
  c.text(lx, ly, "last report, by sensor", kInk, Anchor::kStart, Face::kBold);
  for (int32_t s = 0; s < static_cast<int32_t>(file.sensors.size()) && s < 8; ++s) {
    ly += 22;
    c.marker(lx + 20, ly - 4, kSensorMarkers[s % marker_kinds], 8, rgb(0xffffff), kInk);
    c.text(lx + 50, ly, "sensor " + std::to_string(file.sensors[s].id), kInk);
  }
  if (metrics.has_truth) {
    ly += 34;
    c.text(lx, ly, "against truth", kInk, Anchor::kStart, Face::kBold);
    ly += 24;
    c.line(lx + 8, ly - 4, lx + 32, ly - 4, {kWrong, 2.6});
    std::vector<Point> ring;
    for (int k = 0; k <= 40; ++k)
      ring.push_back({lx + 20 + 17 * std::cos(k * M_PI / 20), ly - 4 + 9 * std::sin(k * M_PI / 20)});
    c.polyline(ring, {kWrong, 2.0});
    c.text(lx + 50, ly, "wrongly joined (" + std::to_string(wrong_links) + " links)", kInk);
    ly += 22;
    c.line(lx, ly - 4, lx + 40, ly - 4, {kInk, 1.6, {7, 5}});
    c.text(lx + 50, ly, "missed target (" + std::to_string(missed_truth.size()) + ")", kInk);
  }
}

void write_association_map(const std::string& path, ImageFormat format, const TrackFile& file,
                           const AssociationRecord& record, const std::string& title) {
  write_picture(path, format, kMapWidth, kMapHeight,
                [&](Canvas& canvas) { draw_association_map(canvas, file, record, title); });
}

}  // namespace trackassoc::report
