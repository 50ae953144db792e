#pragma once
// Reading a dataset of a samples.h5 through the HDF5 library itself (its own filter
// pipeline, as h5py does), for tests that compare the data of two runs.
#include <hdf5.h>

#include <string>
#include <vector>

namespace poise::test {

/// Every value of a float32 dataset, row-major, with its dimensions; empty if absent.
struct H5Floats {
  std::vector<std::size_t> dims;
  std::vector<float> values;
};

inline H5Floats read_h5_floats(const std::string& path, const std::string& dataset) {
  H5Floats out;
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return out;
  const hid_t d = H5Dopen2(f, dataset.c_str(), H5P_DEFAULT);
  if (d >= 0) {
    const hid_t s = H5Dget_space(d);
    hsize_t dims[4] = {0, 0, 0, 0};
    const int rank = H5Sget_simple_extent_dims(s, dims, nullptr);
    std::size_t n = 1;
    for (int k = 0; k < rank; ++k) {
      out.dims.push_back(dims[k]);
      n *= dims[k];
    }
    out.values.resize(n);
    if (n > 0 && H5Dread(d, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.values.data()) < 0) out.values.clear();
    H5Sclose(s);
    H5Dclose(d);
  }
  H5Fclose(f);
  return out;
}

/// Whether two float datasets hold the same values bit for bit (NaN equal to NaN).
inline bool same_h5_floats(const H5Floats& a, const H5Floats& b) {
  if (a.dims != b.dims || a.values.size() != b.values.size() || a.values.empty()) return false;
  for (std::size_t i = 0; i < a.values.size(); ++i) {
    const bool na = a.values[i] != a.values[i], nb = b.values[i] != b.values[i];
    if (na != nb || (!na && a.values[i] != b.values[i])) return false;
  }
  return true;
}

}  // namespace poise::test
