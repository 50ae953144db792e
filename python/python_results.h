#pragma once
/// What the Python module reads back from a run's folder: samples.csv as columns (the same
/// numbers as the file, one value per sample row; a failed sample's outputs NaN).
#include <cstddef>
#include <string>
#include <vector>

namespace poise::python {

struct SampleTable {
  std::vector<std::string> input_names, output_names;
  std::vector<double> sample;                        ///< each row's sample index
  std::vector<bool> ok;                              ///< status "ok"
  std::vector<std::vector<double>> inputs, outputs;  ///< per column, one value per row
  std::vector<std::string> messages;                 ///< a failed sample's reason ("" for ok)
};

/// samples.csv of a run: the input columns lie between "status" and the first declared
/// output; the declared outputs are read by name (solver_steps and message are not outputs).
/// Throws poise::Error when the file is missing or lacks a declared output.
SampleTable read_samples_csv(const std::string& path, const std::vector<std::string>& output_names);

}  // namespace poise::python
