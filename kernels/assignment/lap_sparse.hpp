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
// Where it pays (bench/bench_lap_sparse.cpp): below a few per cent density at n = 1000 the sparse
// solver beats the dense one on the full matrix.
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

}  // namespace trackassoc
