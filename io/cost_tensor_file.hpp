// A 3-D assignment cost tensor in HDF5, the second input format of `trackassoc solve3d`.
//
// Layout (readable and writable with h5py):
//   /cost        n1×n2×n3 dataset, any integer or float type (stored as float in memory; docs/design.md §2
//                Precision), first index slowest: b(i, j, k) = cost[i, j, k]. Entries must be finite
//                or +inf (a forbidden tuple); NaN and −inf are errors naming the entry.
//   /cost attrs  miss_cost (optional, number): the cost per missing index of the dummy-index model
//                (assignment_types.hpp); absent = +inf (min(n1,n2,n3) complete tuples).
// e.g.  h5py.File("t.h5", "w")["cost"] = numpy_array_of_shape_n1_n2_n3
#pragma once

#include <string>

#include "kernels/assignment/assignment_types.hpp"

namespace trackassoc {

// Throws InputError naming the file, the dataset and what is wrong.
CostTensor3 read_cost_tensor_hdf5(const std::string& path);
// Writes atomically (io/atomic_file.hpp).
void write_cost_tensor_hdf5(const std::string& path, const CostTensor3& tensor);

}  // namespace trackassoc
