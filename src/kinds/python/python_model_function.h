#pragma once
/// The function a study of kind "python" computes its samples with: the user's Python function,
/// which the Python module hands to the run (poise.run(study, model=f)). The kind knows only
/// this seam, not Python: a batch of rows in, the outputs of each row out.
#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace poise::kinds::python {

/// One batch: `inputs` n x input_names row-major in the units the model file writes the values
/// in; fills `outputs` n x output_names row-major in the outputs' declared units, and for a row
/// without an answer its reason in failures[row] (failures holds n "" when called).
using BatchFunction = std::function<void(const std::vector<std::string>& input_names,
                                         const std::vector<std::string>& output_names, std::span<const double> inputs,
                                         std::size_t n, std::span<double> outputs, std::vector<std::string>& failures)>;

/// The function of the run in progress (set by the Python module for the length of a run; an
/// empty function: none, and a study of kind "python" is refused with what to do).
void set_model_function(BatchFunction f);
BatchFunction model_function();

}  // namespace poise::kinds::python
