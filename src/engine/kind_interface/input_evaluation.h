#pragma once
/// A study's outputs at input values a caller gives, rather than at sampled ones: what
/// poise.Study.evaluate (python/) and a metamodel built on it need. The inputs are the
/// columns of the study's samples.csv, in their units; the outputs are the study's declared
/// outputs, in theirs. A kind that can (StudyKind::input_evaluator) hands the engine an
/// InputEvaluator; the engine spreads the points over threads in chunks, so a caller pays no
/// per-point overhead beyond the kind's own computation.
///
/// Reproducibility: evaluating a run's sampled inputs gives that run's outputs (to the
/// rounding of the inputs as samples.csv prints them) for a kind whose samples have no
/// randomness beyond their inputs. A kind with such randomness (per-test draws, sensor noise)
/// says so (has_own_randomness), and point k then gets the draws of the run's sample k.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <exception>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "engine/kind_interface/output_spec.h"

namespace poise::engine {

/// The points' inputs, one column per input, read in place: column j's value at point k is
/// data[j][k * stride[j]] (stride 1: an array of the points; 0: one value for every point;
/// the number of inputs: a row-major points x inputs matrix).
struct InputColumns {
  std::vector<const double*> data;
  std::vector<std::size_t> stride;
  std::size_t first = 0;  ///< the point data[j][0] holds (a chunk's own copy starts at its first point)
  double at(std::size_t j, std::size_t k) const { return data[j][(k - first) * stride[j]]; }
  /// The columns of a row-major matrix with `inputs` columns.
  static InputColumns row_major(const double* matrix, std::size_t inputs);
};

class InputEvaluator {
 public:
  virtual ~InputEvaluator() = default;
  /// The inputs as declared (name as samples.csv has it, unit, description), in order.
  virtual const std::vector<InputSpec>& inputs() const = 0;
  /// Their names ("yaw_radial_runout_A_um"), in order.
  virtual const std::vector<std::string>& input_names() const = 0;
  /// The outputs with their units, in order.
  virtual const std::vector<OutputSpec>& outputs() const = 0;
  /// The nominal unit's inputs (every tolerance at its centre: deviations and magnitudes
  /// zero), in input_names() order.
  virtual std::vector<double> nominal_inputs() const = 0;
  /// Whether a sample draws beyond its inputs (then point k gets sample k's draws).
  virtual bool has_own_randomness() const { return false; }
  /// Points [begin, end) of `inputs` (input_names() order), their output values into `values`
  /// row-major (outputs() columns). A point without a physical answer gets NaN outputs and
  /// its reason appended to `failures` as (point, reason).
  virtual void evaluate_points(const InputColumns& inputs, double* values, std::size_t begin, std::size_t end,
                               std::vector<std::pair<std::size_t, std::string>>& failures) const = 0;
};

/// Points [begin, end) one at a time, for an evaluator's evaluate_points: each point's inputs,
/// times `factors` (display unit to SI; empty: as given), go to compute(x, y), which writes the
/// point's outputs into y (n_outputs values at values + k * n_outputs); a point whose compute
/// throws gets NaN outputs and its reason in `failures`.
template <class Compute>
void evaluate_each_point(const InputColumns& inputs, std::span<const double> factors, std::size_t n_inputs,
                         std::size_t n_outputs, double* values, std::size_t begin, std::size_t end,
                         std::vector<std::pair<std::size_t, std::string>>& failures, Compute compute) {
  std::vector<double> x(n_inputs);
  for (std::size_t k = begin; k < end; ++k) {
    const std::span<double> y(values + k * n_outputs, n_outputs);
    for (std::size_t j = 0; j < n_inputs; ++j) x[j] = inputs.at(j, k) * (factors.empty() ? 1.0 : factors[j]);
    try {
      compute(k, std::span<const double>(x), y);
    } catch (const std::exception& e) {
      std::fill(y.begin(), y.end(), NAN);
      failures.emplace_back(k, e.what());
    }
  }
}

/// Failed points of evaluate_inputs, in point order.
struct InputEvaluationFailures {
  std::size_t count = 0;
  std::vector<std::pair<std::size_t, std::string>> first;  ///< (point, reason), the first 100
};

/// All `points` points (outputs row-major, points x outputs().size()) on `threads` threads
/// (0 = all cores), in chunks. The result does not depend on the thread count.
InputEvaluationFailures evaluate_inputs(const InputEvaluator& evaluator, const InputColumns& inputs, std::size_t points,
                                        std::span<double> outputs, int threads);

}  // namespace poise::engine
