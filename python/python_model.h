#pragma once
// The user's Python function of a study of kind "python" (poise.run(study, model=f)), called by
// the engine's threads on batches of samples (kinds/python/python_model_function.h).
#include <pybind11/pybind11.h>

#include <span>
#include <string>
#include <vector>

namespace poise::python_module {

/// One batch through f(inputs) -> outputs: the GIL taken, the inputs as a dict of NumPy arrays
/// (one per input name), each output's array (or number) read back; a batch f raises on, or
/// answers without an output, fails with the reason; a NaN fails its sample.
void call_model_function(const pybind11::object& f, const std::vector<std::string>& input_names,
                         const std::vector<std::string>& output_names, std::span<const double> inputs, std::size_t n,
                         std::span<double> outputs, std::vector<std::string>& failures);

}  // namespace poise::python_module
