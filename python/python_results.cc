#include "python_results.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include "core/error.h"
#include "engine/kind_interface/output_spec.h"

namespace poise::python {
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    cells.push_back(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) return cells;
    start = comma + 1;
  }
}

double number(const std::string& cell) {
  if (cell.empty()) return NAN;
  char* end = nullptr;
  const double v = std::strtod(cell.c_str(), &end);
  return end == cell.c_str() ? NAN : v;
}

}  // namespace

SampleTable read_samples_csv(const std::string& path, const std::vector<std::string>& output_names) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot read (the run wrote no samples.csv)");
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split(line);
  if (header.size() < 2 || header[0] != "sample" || header[1] != "status") {
    throw Error(path + ": expected a samples.csv header starting \"sample,status\"");
  }
  std::vector<std::size_t> out_col;
  for (const auto& name : output_names) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) throw Error(path + ": no column " + name + " (an output of the study)");
    out_col.push_back(static_cast<std::size_t>(it - header.begin()));
  }
  const std::size_t first_output = out_col.empty() ? header.size() : *std::min_element(out_col.begin(), out_col.end());
  SampleTable t;
  t.output_names = output_names;
  for (std::size_t c = 2; c < first_output && c < header.size(); ++c) {
    if (header[c] != "message" && header[c] != "solver_steps") t.input_names.push_back(header[c]);
  }
  const std::size_t message_col =
      static_cast<std::size_t>(std::find(header.begin(), header.end(), "message") - header.begin());
  t.inputs.resize(t.input_names.size());
  t.outputs.resize(output_names.size());
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const std::vector<std::string> cells = split(line);
    if (cells.size() < header.size()) continue;  // a row cut short by a stopped run
    t.sample.push_back(number(cells[0]));
    t.ok.push_back(cells[1] == "ok");
    for (std::size_t k = 0; k < t.input_names.size(); ++k) t.inputs[k].push_back(number(cells[2 + k]));
    for (std::size_t k = 0; k < out_col.size(); ++k) {
      t.outputs[k].push_back(t.ok.back() ? number(cells[out_col[k]]) : NAN);
    }
    t.messages.push_back(message_col < cells.size() ? cells[message_col] : "");
  }
  return t;
}

}  // namespace poise::python
