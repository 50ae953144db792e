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

/// The text attribute `name` of the object at `path` in a file ("" if absent or not text).
inline std::string read_h5_text_attribute(const std::string& file, const std::string& path, const std::string& name) {
  std::string out;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return out;
  if (H5Aexists_by_name(f, path.c_str(), name.c_str(), H5P_DEFAULT) > 0) {
    const hid_t a = H5Aopen_by_name(f, path.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
    const hid_t t = H5Aget_type(a);
    if (H5Tget_class(t) == H5T_STRING) {
      if (H5Tis_variable_str(t) > 0) {
        char* text = nullptr;
        if (H5Aread(a, t, &text) >= 0 && text) out = text;
        const hid_t space = H5Aget_space(a);
        H5Dvlen_reclaim(t, space, H5P_DEFAULT, &text);
        H5Sclose(space);
      } else {
        out.resize(H5Tget_size(t));
        if (H5Aread(a, t, out.data()) < 0) out.clear();
        out.erase(out.find_last_not_of('\0') + 1);
      }
    }
    H5Tclose(t);
    H5Aclose(a);
  }
  H5Fclose(f);
  return out;
}

}  // namespace poise::test
