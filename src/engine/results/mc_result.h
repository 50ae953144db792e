#pragma once
/// The one result type of a run of any study kind: each sample's result as computed
/// (SampleResult: drawn inputs, declared outputs, a field where the study has one, the
/// solver's counters) and a run's results gathered (McResult: the ok samples' values by
/// output, failures with their reasons, statistics, a study's own figures, how the run ended).
/// The result folder, the optimizer's objective and the budget's Monte Carlo all read it.
#include <any>
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "sampling/cross_moments.h"
#include "sampling/statistics.h"

namespace poise::engine {

struct SampleResult {
  std::size_t index = 0;
  bool ok = true;
  std::string message;
  std::vector<double> inputs;   ///< unit-scope draws, display units
  std::vector<double> outputs;  ///< output_names() order
  long solver_steps = 0, rhs_evals = 0;
  /// A study's values at every point of a per-sample field (an error at each point of a
  /// grid), for one whose samples have one (empty otherwise): they travel with the sample to
  /// rank 0, where the run's field sink (RunControl::field_sink) takes them.
  std::vector<float> field;
};

struct McResult {
  std::size_t n = 0, failures = 0;
  std::vector<std::pair<std::size_t, std::string>> failed;
  /// Every failure counted by its reason's head (the message up to its first ": ").
  std::map<std::string, std::size_t> failure_reasons;
  std::vector<sampling::Summary> outputs;
  std::vector<std::vector<double>> values;  ///< per output, ok samples in order
  std::vector<std::size_t> ok_index;        ///< sample index of each ok sample (values' order)
  double wall_seconds = 0.0;
  long solver_steps = 0, rhs_evals = 0;
  std::size_t completed = 0;  ///< samples [0, completed) ran (n unless stopped)
  bool interrupted = false;   ///< stopped by SIGINT / SIGTERM
  int signal = 0;
  std::string stop_reason;         ///< why the run stopped before n ("" = it did not)
  std::size_t replicate_size = 0;  ///< summaries by replicate (design.h) when > 0
  /// A study's own figures of the run, of its own type (the maps of a per-sample field), for
  /// its details and report sections; empty for most studies.
  std::any study_figures;
  /// samples.h5 as summary.json describes it, for a study that wrote it itself (null: it wrote
  /// none); unset: the engine writes the inputs and outputs there from samples.csv.
  std::optional<nlohmann::json> samples_h5;
  /// Means and covariances of the ok samples' inputs and outputs (a study of at most 64
  /// inputs and outputs together), for each input's share of an output's variance.
  sampling::CrossMoments moments;
  /// The output names (an in-memory evaluation sets them: StudyKind::evaluate, the optimizer).
  std::vector<std::string> names;

  /// Index of an output by name; throws poise::Error listing the names if absent.
  std::size_t index(const std::string& output) const;
  /// The reason of the first failed sample ("" if none failed).
  std::string first_failure() const { return failed.empty() ? std::string() : failed.front().second; }
};

}  // namespace poise::engine
