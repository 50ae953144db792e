#include "engine/results/sample_columns_h5.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "engine/results/checked_file.h"
#include "engine/results/hdf5_handles.h"

namespace poise::engine {
namespace {
using hdf5::Id;

// One column of values as a 1-D dataset (contiguous: a procedure run has few samples).
void write_column(hid_t where, const std::string& name, hid_t file_type, hid_t mem_type, const void* data,
                  std::size_t rows, const std::string& units, const std::string& description) {
  const hsize_t dims[1] = {rows};
  Id space(H5Screate_simple(1, dims, nullptr), H5Sclose);
  Id d(H5Dcreate2(where, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  if (!d.ok()) throw Error(hdf5::failed("cannot create dataset " + name));
  if (rows > 0 && H5Dwrite(d.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) {
    throw Error(hdf5::failed("cannot write dataset " + name));
  }
  if (!units.empty()) hdf5::text_attribute(d.get(), "units", units);
  if (!description.empty()) hdf5::text_attribute(d.get(), "description", description);
}

double cell_value(const std::string& cell) {
  if (cell.empty() || cell == "nan") return NAN;
  try {
    return std::stod(cell);
  } catch (const std::exception&) {
    return NAN;
  }
}

}  // namespace

nlohmann::json write_sample_columns_h5(const std::string& csv_path, const std::string& h5_path,
                                       const std::vector<InputSpec>& input_specs,
                                       const std::vector<OutputSpec>& outputs,
                                       const std::map<std::string, std::string>& text_attributes,
                                       const std::map<std::string, std::uint64_t>& number_attributes) {
  std::ifstream in(csv_path);
  if (!in) throw Error(csv_path + ": cannot be read back for samples.h5");
  std::string line;
  std::getline(in, line);  // header
  const std::size_t n_in = input_specs.size(), n_out = outputs.size();
  std::vector<std::uint64_t> sample;
  std::vector<std::uint8_t> ok;
  std::vector<std::vector<double>> inputs(n_in), values(n_out);
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (cells.size() < 2 + n_in + n_out && std::getline(ss, cell, ',')) cells.push_back(cell);
    if (cells.size() < 2 + n_in + n_out) break;  // a partial last row (a run stopped while writing)
    sample.push_back(std::stoull(cells[0]));
    ok.push_back(cells[1] == "ok" ? 1 : 0);
    for (std::size_t k = 0; k < n_in; ++k) inputs[k].push_back(cell_value(cells[2 + k]));
    for (std::size_t k = 0; k < n_out; ++k) values[k].push_back(cell_value(cells[2 + n_in + k]));
  }
  hdf5::quiet();
  const std::string tmp = h5_path + ".tmp";
  try {
    Id file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, hdf5::unlocked_access()), H5Fclose);
    if (!file.ok()) throw Error(hdf5::failed("cannot create the file"));
    for (const auto& [k, v] : text_attributes) hdf5::text_attribute(file.get(), k, v);
    for (const auto& [k, v] : number_attributes) hdf5::number_attribute(file.get(), k, v);
    const std::size_t rows = sample.size();
    write_column(file.get(), "sample", H5T_STD_U64LE, H5T_NATIVE_UINT64, sample.data(), rows, "",
                 "sample index of each row");
    write_column(file.get(), "ok", H5T_STD_U8LE, H5T_NATIVE_UINT8, ok.data(), rows, "",
                 "1 = the sample succeeded, 0 = it failed (its values are NaN)");
    Id in_group(H5Gcreate2(file.get(), "inputs", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    Id out_group(H5Gcreate2(file.get(), "outputs", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    if (!in_group.ok() || !out_group.ok()) throw Error(hdf5::failed("cannot create the groups"));
    for (std::size_t k = 0; k < n_in; ++k) {
      const InputSpec& spec = input_specs[k];
      write_column(in_group.get(), spec.name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, inputs[k].data(), rows, spec.unit,
                   spec.description.empty()
                       ? "drawn input" + (spec.tolerance.empty() ? std::string() : " (" + spec.tolerance + ")")
                       : spec.description);
    }
    for (std::size_t k = 0; k < n_out; ++k) {
      write_column(out_group.get(), outputs[k].name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, values[k].data(), rows,
                   outputs[k].unit, outputs[k].description);
    }
    in_group.reset();
    out_group.reset();
    if (file.reset() < 0) throw Error(hdf5::failed("cannot close the file"));
  } catch (const Error& e) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw WriteError(h5_path, e.what());
  }
  std::error_code ec;
  std::filesystem::rename(tmp, h5_path, ec);
  if (ec) throw WriteError(h5_path, ec.message());
  return {{"file", std::filesystem::path(h5_path).filename().string()},
          {"rows", sample.size()},
          {"inputs", n_in},
          {"outputs", n_out}};
}

}  // namespace poise::engine
