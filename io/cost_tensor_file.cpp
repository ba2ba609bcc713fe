#include "io/cost_tensor_file.hpp"

#include <cmath>

#include "io/atomic_file.hpp"
#include "io/hdf5_wrapper.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {

CostTensor3 read_cost_tensor_hdf5(const std::string& path) {
  h5::File file = h5::File::open_read_only(path);
  const h5::Group root = file.root();
  std::vector<hsize_t> dims;
  std::vector<float> values = root.read_floats("cost", 3, dims);
  for (hsize_t d : dims)
    if (d > static_cast<hsize_t>(std::numeric_limits<int32_t>::max()))
      throw InputError(path + ": /cost: dimension " + std::to_string(d) + " too large");
  CostTensor3 b;
  b.n1 = static_cast<int32_t>(dims[0]);
  b.n2 = static_cast<int32_t>(dims[1]);
  b.n3 = static_cast<int32_t>(dims[2]);
  for (std::size_t e = 0; e < values.size(); ++e) {
    const float x = values[e];
    if (std::isnan(x) || x == -std::numeric_limits<float>::infinity()) {
      const std::size_t i = e / (dims[1] * dims[2]), j = (e / dims[2]) % dims[1], k = e % dims[2];
      throw InputError(path + ": /cost[" + std::to_string(i) + ", " + std::to_string(j) + ", " +
                       std::to_string(k) + "] is " + std::to_string(x) +
                       "; expected a finite cost or +inf (forbidden tuple)");
    }
  }
  b.cost = std::move(values);
  // The attribute lives on the dataset; open it as a group-like object through the C API.
  h5::Handle set(H5Dopen2(root.id(), "cost", H5P_DEFAULT), H5Dclose);
  if (set.valid() && H5Aexists(set.get(), "miss_cost") > 0) {
    h5::Handle attr(H5Aopen(set.get(), "miss_cost", H5P_DEFAULT), H5Aclose);
    h5::Handle type(attr.valid() ? H5Aget_type(attr.get()) : H5I_INVALID_HID, H5Tclose);
    const H5T_class_t cls = type.valid() ? H5Tget_class(type.get()) : H5T_NO_CLASS;
    double miss = 0.0;
    if ((cls != H5T_FLOAT && cls != H5T_INTEGER) || H5Aread(attr.get(), H5T_NATIVE_DOUBLE, &miss) < 0)
      throw InputError(path + ": /cost attribute miss_cost: expected a number");
    if (std::isnan(miss) || miss == -std::numeric_limits<double>::infinity())
      throw InputError(path + ": /cost attribute miss_cost: expected a finite number or +inf, found " +
                       std::to_string(miss));
    b.miss_cost = static_cast<float>(miss);
  }
  return b;
}

void write_cost_tensor_hdf5(const std::string& path, const CostTensor3& b) {
  write_atomically(path, [&](const std::string& tmp) {
    h5::File file = h5::File::create(tmp);
    const h5::Group root = file.root();
    const hsize_t dims[3] = {static_cast<hsize_t>(b.n1), static_cast<hsize_t>(b.n2),
                             static_cast<hsize_t>(b.n3)};
    h5::Handle space(H5Screate_simple(3, dims, nullptr), H5Sclose);
    h5::Handle set(space.valid() ? H5Dcreate2(root.id(), "cost", H5T_IEEE_F32LE, space.get(), H5P_DEFAULT,
                                              H5P_DEFAULT, H5P_DEFAULT)
                                 : H5I_INVALID_HID,
                   H5Dclose);
    if (!set.valid()) throw InputError(tmp + ": /cost: cannot create the dataset");
    if (!b.cost.empty() &&
        H5Dwrite(set.get(), H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, b.cost.data()) < 0)
      throw InputError(tmp + ": /cost: cannot write");
    if (std::isfinite(b.miss_cost)) {
      h5::Handle aspace(H5Screate(H5S_SCALAR), H5Sclose);
      h5::Handle attr(
          H5Acreate2(set.get(), "miss_cost", H5T_IEEE_F64LE, aspace.get(), H5P_DEFAULT, H5P_DEFAULT),
          H5Aclose);
      const double miss = b.miss_cost;
      if (!attr.valid() || H5Awrite(attr.get(), H5T_NATIVE_DOUBLE, &miss) < 0)
        throw InputError(tmp + ": /cost attribute miss_cost: cannot write");
    }
    set.close();
    file.close();
  });
}

}  // namespace trackassoc
