// Sparse 2-D linear assignment for gated cost matrices: candidate lists in CSR form, solved by
// Jonker–Volgenant's augmenting row reduction and a Dijkstra shortest augmenting path with a
// binary heap (the sparse variant of JV 1987, "LAPJVsp", in the rectangular form of Crouse 2016).
//
// Algorithm: Jonker & Volgenant, "A shortest augmenting path algorithm for dense and sparse linear
// assignment problems", Computing 38 (1987) 325–340; Crouse, "On implementing 2D rectangular
// assignment algorithms", IEEE TAES 52(4) 2016. The duals start at v = 0 (no column reduction, so
// the rectangular and square cases are one code path); two passes of augmenting row reduction over
// each row's candidates, then one heap Dijkstra per row still free, which touches only the
// candidates of the rows it scans: O(E log E) per augmentation instead of the dense O(n·m), E the
// number of candidates. Absent entries are forbidden (+inf); the result is the dense
// solve_lap's on the matrix with +inf off the candidate lists (same optimum, same LapResult
// contract: rectangular, allow_unassigned, infeasibility, duals on the candidates).
// allow_unassigned is solved with one private dummy column per row (cost 0 after the shift
// c − 2·unassigned_cost, only candidates cheaper than 2·unassigned_cost kept), so the problem
// stays sparse: rows × (cols + rows) with E + rows entries.
// Where it pays (bench/bench_lap_sparse.cpp): below ~8 % density at n = 1000 the sparse solver
// beats the dense one on the full matrix (1650× at 0.19 %, 2.5× at 4.4 %).
#pragma once

#include <cstdint>
#include <span>

#include "kernels/assignment/lap.hpp"

namespace trackassoc {

// CSR view of a rows×cols cost matrix: the candidates of row r are col[row_start[r] ..
// row_start[r+1]) with costs cost[...]. Columns within a row distinct (any order); costs finite or
// +inf (dropped); NaN or −inf is an InputError.
struct SparseCostView {
  int32_t rows = 0, cols = 0;
  std::span<const int32_t> row_start;  // rows + 1 offsets, row_start[0] = 0, non-decreasing
  std::span<const int32_t> col;        // row_start[rows] column indices in [0, cols)
  std::span<const double> cost;        // row_start[rows] costs
  void validate() const;               // InputError naming the first bad field
};

LapResult solve_sparse_lap(const SparseCostView& matrix, const LapOptions& options = {});

// A gated problem given as a dense row-major matrix (forbidden entries +inf, the solve_lap
// contract): solved by solve_sparse_lap on its finite entries when both sides are at least
// `min_side` and at most `max_density` of its entries are finite, and by the dense solve_lap
// otherwise. The optimum is the same either way (of several optimal assignments the two may
// return different ones). Counting the finite entries and building the CSR cost O(rows·cols),
// which the dense solver spends per augmentation. Defaults from bench/bench_lap_sparse.cpp
// (gated geometric n = 1000, one run): the sparse solver is 2.5× faster at 4.4 % density, even
// at 8.5 % (the crossover) and 1.9× slower at 16 %.
struct GatedLapOptions {
  double max_density = 0.05;  // finite entries / (rows·cols); 0 = always dense
  int32_t min_side = 100;     // both sides at least this for the sparse solver
  void validate() const;      // InputError naming the field
};
LapResult solve_gated_lap(std::span<const double> cost, int32_t rows, int32_t cols,
                          const LapOptions& options = {}, const GatedLapOptions& gated = {});
// The same choice for a problem given by its candidates (built without the dense matrix, e.g.
// through a spatial grid): solve_sparse_lap, or solve_lap on the dense form when it is small or
// dense.
LapResult solve_gated_lap(const SparseCostView& matrix, const LapOptions& options = {},
                          const GatedLapOptions& gated = {});
// Whether solve_gated_lap solves a rows × cols problem with `finite` finite entries by the dense
// solve_lap (it then holds the rows × cols matrix: callers count it against a memory budget).
bool solve_gated_lap_is_dense(int32_t rows, int32_t cols, std::size_t finite,
                              const GatedLapOptions& gated = {});

}  // namespace trackassoc
