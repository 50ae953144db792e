// A procedure run's samples: collected into its result, sent between MPI ranks, read back on
// resume (procedure_study.h, procedure_resume.h).
#include <algorithm>
#include <charconv>
#include <sstream>
#include <string_view>

#include "core/error.h"
#include "engine/kind_interface/study_evaluation.h"
#include "engine/results/result_io.h"
#include "engine/run/convergence.h"
#include "engine/run/procedure_resume.h"
#include "engine/run/run_plan.h"

namespace poise::engine {
using nlohmann::json;

std::size_t McResult::index(const std::string& output) const {
  const auto it = std::find(names.begin(), names.end(), output);
  if (it != names.end()) return static_cast<std::size_t>(it - names.begin());
  std::string all;
  for (const auto& name : names) all += (all.empty() ? "" : ", ") + name;
  throw Error("no output '" + output + "' in this study; its outputs are: " + all);
}

void collect_samples(McResult& r, std::span<const SampleResult> block) {
  for (const auto& s : block) {
    r.solver_steps += s.solver_steps;
    r.rhs_evals += s.rhs_evals;
    if (!s.ok) {
      ++r.failures;
      if (r.failed.size() < 100) r.failed.emplace_back(s.index, s.message);
      ++r.failure_reasons[s.message.substr(0, s.message.find(": "))];
      continue;
    }
    if (r.values.size() < s.outputs.size()) {
      r.values.resize(s.outputs.size());
      // Sized for every planned sample at once: a growing vector would hold its old and new
      // storage at once (3x); untouched pages (a run stopped early) take no memory.
      for (auto& v : r.values) v.reserve(r.n);
    }
    for (std::size_t k = 0; k < s.outputs.size(); ++k) r.values[k].push_back(s.outputs[k]);
    r.ok_index.push_back(s.index);
    if (s.inputs.size() + s.outputs.size() <= 64) r.moments.add(s.inputs, s.outputs);
  }
}

void summarize_outputs(McResult& r) {
  r.outputs.clear();
  if (r.values.empty() || r.values[0].empty()) return;
  for (const auto& v : r.values) r.outputs.push_back(summarize_output(v, r.ok_index, r.replicate_size));
}

json outputs_json(const McResult& r, const std::vector<OutputSpec>& outputs, bool with_descriptions) {
  json out = json::object();
  for (std::size_t k = 0; k < r.outputs.size() && k < outputs.size(); ++k) {
    json o = summary_json(r.outputs[k]);
    o["unit"] = outputs[k].unit;
    if (with_descriptions && !outputs[k].description.empty()) o["description"] = outputs[k].description;
    out[outputs[k].name] = o;
  }
  return out;
}

std::function<OutputValues(const std::string&)> requirement_values(const McResult& r,
                                                                   const std::vector<OutputSpec>& outputs,
                                                                   const StudyConfig& cfg) {
  return [&r, &outputs, &cfg](const std::string& name) {
    const auto it = std::find_if(outputs.begin(), outputs.end(), [&](const OutputSpec& o) { return o.name == name; });
    const auto k = static_cast<std::size_t>(it - outputs.begin());
    OutputValues ov;
    if (it != outputs.end() && k < r.values.size()) {
      ov = {&r.values[k], &r.ok_index, cfg.replicate_size, r.failures, independent_samples(cfg)};
    }
    return ov;
  };
}

void encode_result(const SampleResult& r, ByteWriter& w) {
  encode_sample_fields(r, w);
  w.put(r.solver_steps);
  w.put(r.rhs_evals);
  w.put_vector(r.field);
}

void decode_result(ByteReader& rd, SampleResult& r) {
  decode_sample_fields(rd, r);
  r.solver_steps = rd.get<long>();
  r.rhs_evals = rd.get<long>();
  rd.get_vector(r.field);
}

namespace {

// A number of a samples.csv cell (as csv_number wrote it: shortest round trip, "nan"); throws
// poise::Error naming the row.
template <class T>
T cell_number(std::string_view cell, const std::string& csv_path, std::size_t row) {
  T v{};
  const auto [end, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
  if (ec != std::errc() || end != cell.data() + cell.size()) {
    throw Error("--resume: " + csv_path + " row " + std::to_string(row) + ": '" + std::string(cell) +
                "' is not a number");
  }
  return v;
}

}  // namespace

std::vector<SampleResult> read_done_samples(const std::string& csv_path, const std::string& header,
                                            std::size_t n_inputs, std::size_t n_outputs, bool solver_steps) {
  const std::size_t n_cells = 2 + n_inputs + n_outputs + (solver_steps ? 2 : 1);
  std::vector<SampleResult> done;
  const std::string text = read_complete_rows(csv_path, header);
  std::vector<std::string_view> cells;
  for (std::size_t at = 0; at < text.size();) {
    std::size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    const std::string_view line(text.data() + at, end - at);
    at = end + 1;
    const std::size_t row = done.size() + 2;
    cells.clear();
    for (std::size_t from = 0;;) {
      const std::size_t comma = line.find(',', from);
      cells.push_back(line.substr(from, comma == std::string_view::npos ? std::string_view::npos : comma - from));
      if (comma == std::string_view::npos) break;
      from = comma + 1;
    }
    if (cells.size() != n_cells) {
      throw Error("--resume: " + csv_path + " row " + std::to_string(row) + " has " + std::to_string(cells.size()) +
                  " cells, expected " + std::to_string(n_cells));
    }
    SampleResult r;
    r.index = cell_number<std::size_t>(cells[0], csv_path, row);
    if (r.index != done.size()) {
      throw Error("--resume: samples.csv rows are not in order at sample " + std::string(cells[0]));
    }
    r.ok = cells[1] == "ok";
    // Only what the statistics and the stop rule read: the inputs stay on disk, and an ok
    // row's message is empty (memory per resumed row: its outputs).
    r.outputs.reserve(n_outputs);
    for (std::size_t k = 0; k < n_outputs; ++k) {
      r.outputs.push_back(cell_number<double>(cells[2 + n_inputs + k], csv_path, row));
    }
    if (solver_steps) r.solver_steps = cell_number<long>(cells[2 + n_inputs + n_outputs], csv_path, row);
    if (!r.ok) r.message = cells.back();
    done.push_back(std::move(r));
  }
  return done;
}

std::size_t add_resumed_counters(const json& manifest, std::size_t resumed, McResult& mc) {
  if (resumed == 0) return 0;
  const auto it = manifest.find("solver_counters");
  if (it == manifest.end() || !it->is_object()) return resumed;
  const std::size_t counted = std::min(it->value("samples", std::size_t{0}), resumed);
  mc.rhs_evals += it->value("rhs_evals", 0L);
  return resumed - counted;
}

}  // namespace poise::engine
