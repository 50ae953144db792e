#include "python_model.h"

#include <pybind11/numpy.h>

#include <cmath>

namespace py = pybind11;

namespace poise::python_module {
namespace {

// The first line of the Python exception in flight ("ValueError: math domain error").
std::string exception_line(const py::error_already_set& e) {
  std::string text = e.what();
  return text.substr(0, text.find('\n'));
}

}  // namespace

void call_model_function(const py::object& f, const std::vector<std::string>& input_names,
                         const std::vector<std::string>& output_names, std::span<const double> inputs, std::size_t n,
                         std::span<double> outputs, std::vector<std::string>& failures) {
  py::gil_scoped_acquire gil;
  const std::size_t p = input_names.size(), q = output_names.size();
  py::dict in;
  for (std::size_t k = 0; k < p; ++k) {
    py::array_t<double> a(static_cast<py::ssize_t>(n));
    auto w = a.mutable_unchecked<1>();
    for (std::size_t r = 0; r < n; ++r) w(static_cast<py::ssize_t>(r)) = inputs[r * p + k];
    in[py::str(input_names[k])] = a;
  }
  auto fail_all = [&](const std::string& why) { failures.assign(n, why); };
  py::object result;
  try {
    result = f(in);
  } catch (py::error_already_set& e) {
    fail_all("the model function raised " + exception_line(e));
    return;
  }
  if (!py::isinstance<py::dict>(result)) {
    fail_all("the model function returned " + std::string(py::str(result.get_type().attr("__name__"))) +
             ", not a dict of its outputs");
    return;
  }
  const py::dict d = result.cast<py::dict>();
  for (std::size_t k = 0; k < q; ++k) {
    if (!d.contains(output_names[k])) {
      fail_all("the model function's result has no output " + output_names[k]);
      return;
    }
    py::array_t<double, py::array::forcecast> a;
    try {
      a = py::array_t<double, py::array::forcecast>::ensure(d[py::str(output_names[k])]);
    } catch (py::error_already_set& e) {
      fail_all("the model function's " + output_names[k] + " is not numbers: " + exception_line(e));
      return;
    }
    if (!a || (a.size() != 1 && static_cast<std::size_t>(a.size()) != n)) {
      fail_all("the model function gave " + (a ? std::to_string(a.size()) : std::string("no")) + " values of " +
               output_names[k] + " for a batch of " + std::to_string(n));
      return;
    }
    const double* v = a.data();
    for (std::size_t r = 0; r < n; ++r) {
      const double x = v[a.size() == 1 ? 0 : r];
      outputs[r * q + k] = x;
      if (!std::isfinite(x) && failures[r].empty()) {
        failures[r] = "the model function gave no number for " + output_names[k] + " (" + std::to_string(x) + ")";
      }
    }
  }
}

}  // namespace poise::python_module
