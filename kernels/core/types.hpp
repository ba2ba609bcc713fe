// The in-memory data model of trackassoc (docs/design.md §3), as structures of arrays.
//
// Kernels see spans of columns and never a row object. A TrackTable has one row per
// (sensor, local track, time); state and covariance are stored column by column:
//   state[c][row]  for c in the state layout ("x,y,vx,vy" or "x,y,z,vx,vy,vz"),
//   cov[c][row]    for c in the packed upper triangle of the D×D covariance, row-major:
//                  (0,0),(0,1),...,(0,D-1),(1,1),(1,2),...,(D-1,D-1).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace trackassoc {

// Spatial dimension of a scenario: 2-D (x, y) or 3-D (x, y, z).
// The state is position then velocity: D = 2·spatial_dim.
enum class StateLayout { kXY_VXVY = 4, kXYZ_VXVYVZ = 6 };

inline int state_dim(StateLayout layout) { return static_cast<int>(layout); }
inline int spatial_dim(StateLayout layout) { return static_cast<int>(layout) / 2; }
inline int packed_size(int d) { return d * (d + 1) / 2; }
inline const char* layout_name(StateLayout layout) {
  return layout == StateLayout::kXY_VXVY ? "x,y,vx,vy" : "x,y,z,vx,vy,vz";
}
// Index of element (r, c), r <= c, of a D×D symmetric matrix in the packed upper triangle.
inline int packed_index(int d, int r, int c) {
  if (r > c) std::swap(r, c);
  return r * d - r * (r - 1) / 2 + (c - r);
}

// Local tracks reported by the sensors: one row per (sensor, local track, time).
struct TrackTable {
  StateLayout layout = StateLayout::kXY_VXVY;
  std::vector<int32_t> sensor;             // a Sensor::id
  std::vector<int32_t> track;              // local track number within its sensor
  std::vector<double> t;                   // report time [s]
  std::vector<std::vector<double>> state;  // [D][rows]
  std::vector<std::vector<double>> cov;    // [D(D+1)/2][rows], packed upper triangle
  std::vector<int32_t> truth;              // target id, -1 where unknown

  explicit TrackTable(StateLayout l = StateLayout::kXY_VXVY) { reset(l); }
  void reset(StateLayout l) {
    layout = l;
    sensor.clear();
    track.clear();
    t.clear();
    truth.clear();
    state.assign(state_dim(l), {});
    cov.assign(packed_size(state_dim(l)), {});
  }
  int dim() const { return state_dim(layout); }
  std::size_t size() const { return t.size(); }
  void reserve(std::size_t n) {
    sensor.reserve(n);
    track.reserve(n);
    t.reserve(n);
    truth.reserve(n);
    for (auto& c : state) c.reserve(n);
    for (auto& c : cov) c.reserve(n);
  }
  // Appends one row. x has D entries, P is the full D×D covariance (only the upper triangle is read).
  void push_back(int32_t s, int32_t trk, double time, const Eigen::VectorXd& x, const Eigen::MatrixXd& P,
                 int32_t truth_id) {
    const int d = dim();
    sensor.push_back(s);
    track.push_back(trk);
    t.push_back(time);
    truth.push_back(truth_id);
    for (int r = 0; r < d; ++r) state[r].push_back(x[r]);
    for (int r = 0, k = 0; r < d; ++r)
      for (int c = r; c < d; ++c, ++k) cov[k].push_back(P(r, c));
  }
  Eigen::VectorXd state_at(std::size_t row) const {
    Eigen::VectorXd x(dim());
    for (int r = 0; r < dim(); ++r) x[r] = state[r][row];
    return x;
  }
  Eigen::MatrixXd cov_at(std::size_t row) const {
    const int d = dim();
    Eigen::MatrixXd P(d, d);
    for (int r = 0, k = 0; r < d; ++r)
      for (int c = r; c < d; ++c, ++k) P(r, c) = P(c, r) = cov[k][row];
    return P;
  }
};

// Ground-truth target states, one row per (target, time).
struct TruthTable {
  StateLayout layout = StateLayout::kXY_VXVY;
  std::vector<int32_t> target;
  std::vector<double> t;
  std::vector<std::vector<double>> state;  // [D][rows]
  explicit TruthTable(StateLayout l = StateLayout::kXY_VXVY) : layout(l), state(state_dim(l)) {}
  std::size_t size() const { return t.size(); }
};

// Polar measurements (docs/design.md §3). elevation is empty for 2-D sensors; target is -1 for clutter.
struct Measurements {
  std::vector<int32_t> sensor;
  std::vector<double> t, range, bearing, elevation;
  std::vector<int32_t> target;
  std::size_t size() const { return t.size(); }
};

struct Sensor {
  int32_t id = 0;
  std::array<double, 3> position{0, 0, 0};  // [m]
  double sigma_range = 100.0;               // [m]
  double sigma_bearing = 0.01745329;        // [rad]
  double sigma_elevation = 0.0;             // [rad], 0 for a 2-D sensor
  double period = 1.0;                      // scan period [s]
  double offset = 0.0;                      // time of the first scan [s]
  double p_detect = 1.0;                    // detection probability per scan
  double clutter_rate = 0.0;                // expected false plots per scan
  double reliability = 1.0;                 // seed 001 reliability weight ω
  friend bool operator==(const Sensor&, const Sensor&) = default;
};

}  // namespace trackassoc
