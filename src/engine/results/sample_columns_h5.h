#pragma once
/// samples.h5 of a study whose samples have no wide values (a whole simulated procedure per
/// sample, a closed-form kind): the inputs and outputs of samples.csv as named columns, each
/// with its declared unit and meaning, for h5py and pandas:
///   /sample             uint64  [rows]  sample index of each row (0, 1, ...)
///   /ok                 uint8   [rows]  1 = the sample succeeded, 0 = it failed (values NaN)
///   /inputs/<name>      float64 [rows]  each drawn input; attribute "units"
///   /outputs/<name>     float64 [rows]  each declared output; attributes "units", "description"
///   root attributes: study, kind, study_file, method, poise_version, seed, planned_samples.
/// Written once the run's samples.csv is whole (so a resumed or distributed run writes it the
/// same way), from that file: the values are the CSV's, bit for bit.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/kind_interface/output_spec.h"

namespace poise::engine {

/// Reads `csv_path` (header: sample,status,<inputs>,<outputs>,... as `input_names` and
/// `outputs` say; no input names: the header's columns before the first output) and writes `h5_path`. Returns {"file"
/// (its name in the run folder), "rows", "inputs", "outputs"} for summary.json. Throws WriteError when the file cannot
/// be written.
nlohmann::json write_sample_columns_h5(const std::string& csv_path, const std::string& h5_path,
                                       const std::vector<InputSpec>& inputs, const std::vector<OutputSpec>& outputs,
                                       const std::map<std::string, std::string>& text_attributes,
                                       const std::map<std::string, std::uint64_t>& number_attributes);

}  // namespace poise::engine
