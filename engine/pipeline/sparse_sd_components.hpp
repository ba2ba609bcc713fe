// One connected component of the sparse S-D pipeline (engine/pipeline/sparse_sd_pipeline.hpp) as a
// self-contained problem: its tracks by sensor, the link costs among them and when each track is
// valid, so that it can be solved where its problem was not built (another MPI rank, docs/design.md §8;
// solve_sd_components_sharded below). The formulation (tuple cost, what is allowed, the dense
// sub-tensor and the sequential LAP merging fallback) is the header's; this file holds it.
#pragma once

#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "engine/distributed/codec.hpp"
#include "engine/distributed/communicator.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/pipeline/tuple_cost.hpp"

namespace trackassoc {

// The link costs between the tracks of two sensors a < b of a component (n_a × n_b, NaN = no gated
// pair): dense when n_a·n_b <= kDenseEntries, else its gated entries only, by row (CSR, columns
// ascending). Both give the same costs; a giant component (3 × 30 000 tracks) would need 7.2 GB
// per pair of sensors dense (issue 30), its gated entries take kilobytes per track.
struct SDLinkMatrix {
  static constexpr std::size_t kDenseEntries = std::size_t{1} << 16;
  int32_t rows = 0, cols = 0;
  bool sparse = false;
  std::vector<double> dense;            // rows × cols, when !sparse
  std::vector<int32_t> row_start, col;  // CSR, when sparse
  std::vector<double> cost;

  // From the gated entries (i, j, cost) of a rows × cols matrix, in any order.
  static SDLinkMatrix from_entries(int32_t rows, int32_t cols,
                                   std::vector<std::tuple<int32_t, int32_t, double>> entries);
  double at(int32_t i, int32_t j) const;
  // Calls f(i, j, cost) for every gated entry, by row, columns ascending.
  template <class F>
  void for_each(F f) const {
    for (int32_t i = 0; i < rows; ++i)
      if (sparse) {
        for (int32_t e = row_start[i]; e < row_start[i + 1]; ++e) f(i, col[e], cost[e]);
      } else {
        for (int32_t j = 0; j < cols; ++j)
          if (const double c = dense[static_cast<std::size_t>(i) * cols + j]; !std::isnan(c)) f(i, j, c);
      }
  }
  // Calls f(j, cost) for every gated entry of row i, columns ascending.
  template <class F>
  void for_row(int32_t i, F f) const {
    if (sparse) {
      for (int32_t e = row_start[i]; e < row_start[i + 1]; ++e) f(col[e], cost[e]);
    } else {
      for (int32_t j = 0; j < cols; ++j)
        if (const double c = dense[static_cast<std::size_t>(i) * cols + j]; !std::isnan(c)) f(j, c);
    }
  }
  std::size_t bytes() const {
    return dense.size() * sizeof(double) + (row_start.size() + col.size()) * sizeof(int32_t) +
           cost.size() * sizeof(double);
  }
  // The gated entries alone (index i·cols + j, by row, columns ascending): how the matrix travels
  // to another rank, since most of a large component's n_a × n_b entries are NaN.
  struct Gated {
    int32_t rows = 0, cols = 0;
    std::vector<uint64_t> index;
    std::vector<double> cost;
  };
  static Gated gated(const SDLinkMatrix& m);
  // Throws std::runtime_error on entries that do not fit rows × cols (a bug of the sender).
  static SDLinkMatrix from_gated(const Gated& g);
};

// The tracks of one component, by sensor, and the link costs among them.
struct SDComponentView {
  int32_t S = 0;
  std::vector<std::vector<int32_t>> tracks;       // tracks[s] = local track indices of sensor s
  std::vector<std::vector<int32_t>> node;         // node[s][i] = problem node of tracks[s][i]
  std::vector<std::vector<int32_t>> first, last;  // first and last valid common time of node[s][i]
  std::vector<SDLinkMatrix> link;                 // slot a·S + b (a < b): n_a × n_b
  double bytes_held = 0.0;  // what the process holds besides the view (the problem), for the memory budget

  double link_cost(int32_t a, int32_t i, int32_t b, int32_t j) const {
    if (a > b) std::swap(a, b), std::swap(i, j);
    return link[static_cast<std::size_t>(a) * S + b].at(i, j);
  }
  // The two tracks have common valid times, so the gate tested them (SparseSDProblem::coexist).
  bool overlap(int32_t a, int32_t i, int32_t b, int32_t j) const {
    return valid_intervals_meet(first[a][i], last[a][i], first[b][j], last[b][j]);
  }
  // Entries of the dense sub-tensor, Π(n_s + 1).
  double entries() const;
  // Bytes held by the link matrices.
  std::size_t link_bytes() const;
};

// The cost of the tuple with members (sensor, component index), by the rule of
// engine/pipeline/tuple_cost.hpp (+inf: not allowed).
inline double sd_component_tuple_cost(const SDComponentView& v,
                                      const std::vector<std::pair<int32_t, int32_t>>& m, bool all_pairs) {
  return sd_tuple_cost(
      m.size(), all_pairs,
      [&](std::size_t x, std::size_t y) {
        return v.link_cost(m[x].first, m[x].second, m[y].first, m[y].second);
      },
      [&](std::size_t x, std::size_t y) {
        return v.overlap(m[x].first, m[x].second, m[y].first, m[y].second);
      });
}

SDComponentView sd_component_view(const SparseSDProblem& p, int32_t c);

struct SDComponentResult {
  std::vector<std::vector<int32_t>> tuples;  // problem nodes per tuple (any order)
  std::vector<double> costs;                 // sd_tuple_cost of each tuple
  double objective = 0.0, lower_bound = 0.0;
  bool fallback = false;
  // The component solver's own termination (optimal, gap tolerance, iteration limit, ...; the
  // merging fallback's is heuristic): what `associate` counts per kind.
  Termination termination = Termination::kOptimal;
  std::size_t entries = 0;
  // Solved over its listed tuples (engine/pipeline/sparse_sd_tuples.hpp): how many; 0 otherwise.
  std::size_t listed_tuples = 0;
};

// The component's dense S-D assignment (`solver`, a sparse_sd_solver_names() name) when its
// sub-tensor has at most `max_entries` entries and fits the memory budget; else the relaxation over
// its listed tuples (engine/pipeline/sparse_sd_tuples.hpp) when the list fits; else sequential LAP
// merging. Deterministic.
SDComponentResult solve_sd_component(const SDComponentView& v, const std::string& solver,
                                     const nlohmann::json& solver_options, bool all_pairs,
                                     std::size_t max_entries);

// The last resort for a component whose listed tuples would not fit the memory budget: sequential
// LAP merging (see engine/pipeline/sparse_sd_pipeline.hpp). fallback = true, lower bound NaN.
SDComponentResult solve_sd_component_by_merging(const SDComponentView& v, bool all_pairs);

// Every component of `p` solved here, in parallel (TBB); a component of one track is its own tuple.
std::vector<SDComponentResult> solve_sd_components(const SparseSDProblem& p, const std::string& solver,
                                                   const nlohmann::json& solver_options, bool all_pairs,
                                                   std::size_t max_entries);
// The result of a component of one track (node u).
SDComponentResult single_track_component(int32_t u);

// An estimate of solve_sd_component's cost, for balancing components over ranks: the dense
// sub-tensor's entries, or for the merging fallback the LAP sizes Σ_s (groups × n_s).
double sd_component_cost(const SDComponentView& v, std::size_t max_entries);

// The components of two or more tracks over the ranks of `comm` (docs/design.md §8;
// engine/distributed/shard_items.hpp): rank 0 deals them by sd_component_cost, sends each its view
// and solves its own share; the results are those of solve_sd_components for any number of ranks
// (the solvers are deterministic and get no rank-dependent input). The other ranks run
// serve_sd_components at the same time.
std::vector<SDComponentResult> solve_sd_components_sharded(distributed::Communicator& comm,
                                                           const SparseSDProblem& p,
                                                           const std::string& solver,
                                                           const nlohmann::json& solver_options,
                                                           bool all_pairs, std::size_t max_entries);
void serve_sd_components(distributed::Communicator& comm);

// The components of two or more tracks and their estimated cost (sd_component_cost), as dealt.
struct SDComponentCosts {
  std::vector<int64_t> component;
  std::vector<double> cost;
};
SDComponentCosts sd_component_costs(const SparseSDProblem& p, std::size_t max_entries);

// How components and results travel (engine/distributed/codec.hpp). A view's bytes_held is the
// holding process's own and stays behind.
constexpr auto wire_codec(std::type_identity<SDLinkMatrix::Gated>) {
  return distributed::codec<SDLinkMatrix::Gated>("S-D link entries", &SDLinkMatrix::Gated::rows,
                                                 &SDLinkMatrix::Gated::cols, &SDLinkMatrix::Gated::index,
                                                 &SDLinkMatrix::Gated::cost);
}
constexpr auto wire_codec(std::type_identity<SDLinkMatrix>) {
  return distributed::converted_codec<SDLinkMatrix, SDLinkMatrix::Gated>(
      "S-D link matrix", &SDLinkMatrix::gated, &SDLinkMatrix::from_gated);
}
constexpr auto wire_codec(std::type_identity<SDComponentView>) {
  return distributed::codec<SDComponentView>("S-D component", &SDComponentView::S, &SDComponentView::tracks,
                                             &SDComponentView::node, &SDComponentView::first,
                                             &SDComponentView::last, &SDComponentView::link);
}
constexpr auto wire_codec(std::type_identity<SDComponentResult>) {
  return distributed::codec<SDComponentResult>(
      "S-D component result", &SDComponentResult::tuples, &SDComponentResult::costs,
      &SDComponentResult::objective, &SDComponentResult::lower_bound, &SDComponentResult::fallback,
      &SDComponentResult::termination, &SDComponentResult::entries, &SDComponentResult::listed_tuples);
}

}  // namespace trackassoc
