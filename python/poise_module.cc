// _poise: the C++ side of the Python package poise (python/poise/__init__.py is what a user
// imports). Every function here is the command line's own code path: a run writes the same
// folder as `poise run` and its samples are read back from that samples.csv; budget,
// mass_properties and diagnose return the objects their --json prints, converted directly. The GIL is released
// while Poise computes. Errors cross as _poise.NativeError(category, message, file, line,
// key), which __init__.py turns into poise.InputError or poise.Error.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "balancing/campaign_analysis.h"
#include "cli/balance_command.h"
#include "cli/budget_command.h"
#include "cli/diagnose_command.h"
#include "cli/error_mechanisms_command.h"
#include "cli/fit_command.h"
#include "cli/mass_properties_command.h"
#include "cli/record_command.h"
#include "core/diagnostics.h"
#include "core/error.h"
#include "core/version.h"
#include "engine/kind_interface/input_evaluation.h"
#include "engine/kind_interface/programs_allowed.h"
#include "engine/kind_interface/study_kind.h"
#include "engine/results/fault_injection.h"
#include "engine/run/study_runner.h"
#include "engine/study_files/study_config.h"
#include "engine/study_files/toml_reader.h"
#include "geometry/mesh_check.h"
#include "kinds/python/python_model_function.h"
#include "kinds/registry.h"
#include "optimize/optimization_study.h"
#include "python_model.h"
#include "python_results.h"

namespace py = pybind11;

namespace poise::python {
namespace {

// One refused value: where (file, line; "" and 0 where not known), its key, value and what was
// expected, and its message.
struct RefusedValue {
  std::string message, file, key, value, expected;
  int line = 0;
};

// The one exception type that crosses into Python; __init__.py maps it.
struct NativeError {
  std::string category;  ///< "input", "error" or "interrupt"
  std::string message, file, key;
  int line = 0;
  std::vector<RefusedValue> errors;  ///< every refused value of an input error (at least the one above)
};

RefusedValue refused(const InputError& e) {
  return {e.what(), e.where().file, e.key(), e.value(), e.expected(), e.where().line};
}

// Runs f, turning Poise's exceptions into NativeError (with the file, line and key of the
// first refused value of a ValidationError).
template <class F>
auto guarded(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const engine::ValidationError& e) {
    // Every refused value; the first that has a line (else the first) says where.
    NativeError n{"input", e.what(), "", "", 0, {}};
    for (const InputError& one : e.errors()) n.errors.push_back(refused(one));
    const auto with_line =
        std::find_if(n.errors.begin(), n.errors.end(), [](const RefusedValue& r) { return r.line > 0; });
    if (const auto at = with_line != n.errors.end() ? with_line : n.errors.begin(); at != n.errors.end()) {
      n.file = at->file;
      n.line = at->line;
      n.key = at->key;
    }
    throw n;
  } catch (const InputError& e) {
    throw NativeError{"input", e.what(), e.where().file, e.key(), e.where().line, {refused(e)}};
  } catch (const UsageError& e) {
    throw NativeError{"input", e.what(), "", "", 0, {}};
  } catch (const geometry::MeshCheckError& e) {
    throw NativeError{"input", e.what(), "", "", 0, {}};
  } catch (const engine::Interrupted& e) {
    throw NativeError{"interrupt", e.what(), "", "", 0, {}};
  } catch (const std::exception& e) {
    throw NativeError{"error", e.what(), "", "", 0, {}};
  }
}

py::array_t<double> array_of(const std::vector<double>& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

// A JSON value as Python's own objects (dict, list, str, float, int, bool, None), converted
// directly (not printed and parsed again).
py::object python_value(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::object: {
      py::dict d;
      for (const auto& [key, value] : j.items()) d[py::str(key)] = python_value(value);
      return d;
    }
    case nlohmann::json::value_t::array: {
      py::list l;
      for (const auto& value : j) l.append(python_value(value));
      return l;
    }
    case nlohmann::json::value_t::string: return py::str(j.get<std::string>());
    case nlohmann::json::value_t::boolean: return py::bool_(j.get<bool>());
    case nlohmann::json::value_t::number_integer: return py::int_(j.get<std::int64_t>());
    case nlohmann::json::value_t::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case nlohmann::json::value_t::number_float: return py::float_(j.get<double>());
    default: return py::none();
  }
}

// A fresh folder for a run the caller keeps no files of (out=None), removed afterwards.
std::string temporary_run_folder() {
  std::random_device rd;
  const auto base = std::filesystem::temp_directory_path();
  for (int attempt = 0; attempt < 100; ++attempt) {
    const auto dir = base / ("poise-python-" + std::to_string(rd()) + std::to_string(rd()));
    if (std::filesystem::create_directory(dir)) return (dir / "run").string();
  }
  throw Error("cannot make a temporary folder in " + base.string());
}

// A temporary run folder's parent, removed however the call ends ("" = none).
struct RemoveFolder {
  std::string path;
  ~RemoveFolder() {
    std::error_code ec;
    if (!path.empty()) std::filesystem::remove_all(path, ec);
  }
};

// A folder's summary.json as a JSON value (null when it has none).
nlohmann::json summary_of_folder(const std::string& dir) {
  std::ifstream in(std::filesystem::path(dir) / "summary.json");
  return in ? nlohmann::json::parse(in) : nlohmann::json();
}

// poise.run: the study run as `poise run` runs it; the folder's samples and summary read back.
py::dict run(const std::string& study, std::optional<std::size_t> samples, std::optional<std::uint64_t> seed,
             int threads, const std::map<std::string, std::string>& overrides, bool plots,
             std::optional<std::string> out, bool progress, std::size_t sensitivity_base, py::object model,
             bool allow_programs) {
  // The model function and the permission hold for this run only.
  struct RunScope {
    RunScope(const py::object& model, bool allow) {
      if (!model.is_none()) {
        // The engine's threads copy the function without Python's lock: they share one
        // reference to f (an atomic count), and the last one, the global's, goes here, under it.
        auto f = std::make_shared<py::object>(model);
        kinds::python::set_model_function([f](const std::vector<std::string>& in, const std::vector<std::string>& out,
                                              std::span<const double> x, std::size_t n, std::span<double> y,
                                              std::vector<std::string>& failures) {
          python_module::call_model_function(*f, in, out, x, n, y, failures);
        });
      }
      engine::allow_programs(allow);
    }
    ~RunScope() {
      kinds::python::set_model_function({});
      engine::allow_programs(false);
    }
  } const scope(model, allow_programs);
  engine::RunOptions opt;
  opt.sensitivity_base = sensitivity_base;
  opt.samples = samples;
  opt.seed = seed;
  opt.threads = threads;
  opt.overrides = overrides;
  opt.plots = plots;
  opt.progress = progress;
  const bool keep = out.has_value();
  opt.out = keep ? *out : temporary_run_folder();
  std::string dir;
  nlohmann::json summary;
  SampleTable table;
  std::vector<engine::OutputSpec> outputs;
  // out=None: the temporary folder goes however the run ends.
  const RemoveFolder temporary{keep ? std::string() : std::filesystem::path(opt.out).parent_path().string()};
  try {
    guarded([&] {
      py::gil_scoped_release release;
      dir = engine::run_study(study, opt);
      engine::StudyConfig cfg = engine::load_study(study);
      outputs = engine::study_kind(cfg.kind).outputs(cfg);
      table = read_samples_csv((std::filesystem::path(dir) / "samples.csv").string(), engine::output_names_of(outputs));
      summary = summary_of_folder(dir);
      return 0;
    });
  } catch (NativeError& e) {
    if (!keep && e.category == "interrupt") {  // its message names a folder that will be gone
      e.message = "the run was stopped (" + e.message.substr(0, e.message.find(':')) +
                  "); nothing was kept (out=None): give out=FOLDER to keep a stopped run's samples and resume it "
                  "with `poise run --resume FOLDER`";
    }
    throw;
  }
  py::dict r, in, outs, units;
  // The unit each input is declared with (summary.json's sampling.input_units).
  const nlohmann::json declared_units =
      summary.is_object() ? summary.value("/sampling/input_units"_json_pointer, nlohmann::json::object())
                          : nlohmann::json::object();
  for (std::size_t k = 0; k < table.input_names.size(); ++k) {
    in[py::str(table.input_names[k])] = array_of(table.inputs[k]);
    units[py::str(table.input_names[k])] = declared_units.value(table.input_names[k], std::string("1"));
  }
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    outs[py::str(outputs[k].name)] = array_of(table.outputs[k]);
    units[py::str(outputs[k].name)] = outputs[k].unit.empty() ? "1" : outputs[k].unit;
  }
  py::array_t<bool> ok(static_cast<py::ssize_t>(table.ok.size()));
  for (std::size_t k = 0; k < table.ok.size(); ++k) ok.mutable_data()[k] = table.ok[k];
  r["inputs"] = in;
  r["outputs"] = outs;
  r["units"] = units;
  r["sample"] = array_of(table.sample);
  r["ok"] = ok;
  r["messages"] = table.messages;
  r["summary"] = summary.is_null() ? py::object(py::dict()) : python_value(summary);
  r["path"] = keep ? py::object(py::str(dir)) : py::object(py::none());
  return r;
}

// poise.Study: a study file with its kind; evaluates at given inputs where the kind can.
class Study {
 public:
  Study(const std::string& path, const std::map<std::string, std::string>& overrides,
        std::optional<std::uint64_t> seed) {
    guarded([&] {
      cfg_ = engine::load_study(path);
      if (!overrides.empty()) {
        auto all = cfg_.overrides;
        for (const auto& [k, v] : overrides) all[k] = v;
        cfg_.overrides = engine::apply_study_overrides(cfg_, all);
      }
      const engine::StudyKind& kind = engine::study_kind(cfg_.kind);
      kind.validate(cfg_);
      outputs_ = kind.outputs(cfg_);
      try {
        evaluator_ = kind.input_evaluator(cfg_, {}, seed.value_or(cfg_.seed));
      } catch (const Error& e) {
        why_not_ = e.what();
      }
      return 0;
    });
  }
  std::string kind() const { return cfg_.kind; }
  std::string file() const { return cfg_.file; }
  std::vector<std::string> output_names() const { return engine::output_names_of(outputs_); }
  std::map<std::string, std::string> output_units() const {
    std::map<std::string, std::string> u;
    for (const auto& o : outputs_) u[o.name] = o.unit.empty() ? "1" : o.unit;
    return u;
  }
  std::map<std::string, std::string> output_descriptions() const {
    std::map<std::string, std::string> u;
    for (const auto& o : outputs_) u[o.name] = o.description;
    return u;
  }
  bool evaluates() const { return evaluator_ != nullptr; }
  std::string why_not() const { return why_not_; }
  std::vector<std::string> input_names() const { return need().input_names(); }
  std::vector<std::string> input_units() const {
    std::vector<std::string> u;
    for (const auto& i : need().inputs()) u.push_back(i.unit);
    return u;
  }
  std::vector<double> nominal() const { return need().nominal_inputs(); }
  bool has_own_randomness() const {
    if (evaluator_) return evaluator_->has_own_randomness();
    return guarded([&] { return engine::study_kind(cfg_.kind).has_own_randomness(cfg_); });
  }
  std::vector<std::string> evaluator_outputs() const { return engine::output_names_of(need().outputs()); }

  // One array per input (input_names() order; each of the points' length, or of length 1 for
  // one value at every point), read in place -> (points x outputs, failure count, the first
  // failures as (point, reason)).
  using Column = py::array_t<double, py::array::c_style | py::array::forcecast>;
  py::tuple evaluate(const std::vector<Column>& columns, std::size_t points, int threads) const {
    const engine::InputEvaluator& ev = need();
    if (columns.size() != ev.input_names().size()) {
      throw NativeError{"input",
                        "evaluate: expected " + std::to_string(ev.input_names().size()) + " input columns, got " +
                            std::to_string(columns.size()),
                        "",
                        "",
                        0,
                        {}};
    }
    engine::InputColumns in;
    for (std::size_t j = 0; j < columns.size(); ++j) {
      const auto size = static_cast<std::size_t>(columns[j].size());
      if (size != points && size != 1) {
        throw NativeError{"input",
                          "evaluate: input " + ev.input_names()[j] + " has " + std::to_string(size) + " values for " +
                              std::to_string(points) + " points",
                          "",
                          ev.input_names()[j],
                          0,
                          {}};
      }
      in.data.push_back(columns[j].data());
      in.stride.push_back(size == 1 ? 0 : 1);
    }
    return run_evaluation(ev, in, points, threads);
  }
  // A points x inputs matrix (C order).
  py::tuple evaluate_matrix(const Column& x, int threads) const {
    const engine::InputEvaluator& ev = need();
    if (x.ndim() != 2 || static_cast<std::size_t>(x.shape(1)) != ev.input_names().size()) {
      throw NativeError{
          "input",
          "evaluate: expected a 2-D array with " + std::to_string(ev.input_names().size()) + " columns, one per input",
          "",
          "",
          0,
          {}};
    }
    return run_evaluation(ev, engine::InputColumns::row_major(x.data(), ev.input_names().size()),
                          static_cast<std::size_t>(x.shape(0)), threads);
  }

 private:
  static py::tuple run_evaluation(const engine::InputEvaluator& ev, const engine::InputColumns& in, std::size_t n,
                                  int threads) {
    const std::size_t m = ev.outputs().size();
    py::array_t<double> y({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(m)});
    double* out = y.mutable_data();
    engine::InputEvaluationFailures f;
    guarded([&] {
      py::gil_scoped_release release;
      f = engine::evaluate_inputs(ev, in, n, std::span<double>(out, n * m), threads);
      return 0;
    });
    return py::make_tuple(y, f.count, f.first);
  }
  const engine::InputEvaluator& need() const {
    if (!evaluator_) throw NativeError{"error", why_not_, cfg_.file, "", 0, {}};
    return *evaluator_;
  }
  engine::StudyConfig cfg_;
  std::vector<engine::OutputSpec> outputs_;
  std::unique_ptr<engine::InputEvaluator> evaluator_;
  std::string why_not_;
};

// `poise optimize`: the optimization file run as the command runs it (optimize/optimization_study.h);
// its answer, exit status and summary.json; the folder kept only with `out`.
py::dict optimize(const std::string& file, std::optional<std::string> out, int threads,
                  std::optional<std::uint64_t> seed, bool plots, bool progress) {
  engine::RunOptions o;
  o.threads = threads;
  o.plots = plots;
  o.progress = progress;
  const bool keep = out.has_value();
  o.out = keep ? *out : temporary_run_folder();
  const RemoveFolder temporary{keep ? std::string() : std::filesystem::path(o.out).parent_path().string()};
  optimize::OptimizationRun r;
  nlohmann::json summary;
  guarded([&] {
    py::gil_scoped_release release;
    r = optimize::run_optimization(file, o, seed);
    summary = summary_of_folder(r.dir);
    return 0;
  });
  py::dict d;
  d["answer"] = r.answer;
  d["exit_status"] = r.exit_status;
  d["summary"] = summary.is_null() ? py::object(py::dict()) : python_value(summary);
  d["path"] = keep ? py::object(py::str(r.dir)) : py::object(py::none());
  return d;
}

// Runs f for a command that refuses every poise::Error of its input as invalid input (exit 2):
// such an error crosses as an input error; a ValidationError, InputError or UsageError stays as
// it is (with its file, line and key).
template <class F>
auto refused_as_input(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const engine::ValidationError&) {
    throw;
  } catch (const InputError&) {
    throw;
  } catch (const UsageError&) {
    throw;
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
}

// `poise fit --json`: a measured torque table's sine fit.
py::object fit(const std::string& data, const std::vector<std::string>& columns,
               const std::vector<std::string>& units) {
  return python_value(guarded([&] {
    py::gil_scoped_release release;
    return refused_as_input([&] { return cli::fit_torque_table(data, {columns, units}); });
  }));
}

// `poise diagnose-record --json`: a raw record's diagnosis, with its text and residuals.
py::dict diagnose_record(const std::string& record, const std::string& kt, const std::vector<std::string>& columns,
                         const std::vector<std::string>& units) {
  const cli::RecordDiagnosis r = guarded([&] {
    py::gil_scoped_release release;
    return refused_as_input([&] { return cli::diagnose_record(record, kt, {columns, units}); });
  });
  py::dict d;
  d["json"] = python_value(r.json);
  d["text"] = r.text;
  d["angle"] = array_of(r.angle);
  d["residual_before"] = array_of(r.residual_before);
  d["residual_after"] = array_of(r.residual_after);
  return d;
}

// `poise error-mechanisms DIR --json`.
py::object error_mechanisms(const std::string& dir, const std::string& calibrate, int draws) {
  return python_value(guarded([&] {
    py::gil_scoped_release release;
    return refused_as_input([&] { return cli::compare_error_mechanisms_in(dir, calibrate, draws); });
  }));
}

// A balancing campaign analysed (balancing/campaign_analysis.h), as `poise balance --json` prints
// it; with `out`, the folder of --out too.
py::object balance(const std::string& path, const std::string& out) {
  nlohmann::json j = guarded([&] {
    py::gil_scoped_release release;
    const cli::BalanceResult r = cli::balance_campaign(path, out);
    return balancing::analysis_json(r.campaign, r.analyses);
  });
  return python_value(j);
}

py::object budget(const std::string& path) {
  return python_value(guarded([&] {
    py::gil_scoped_release release;
    return cli::check_budget_file(path, nullptr, false);
  }));
}

// `poise validate`: the study and its model checked, nothing run; the summary line.
std::string validate(const std::string& study) {
  return guarded([&] {
    py::gil_scoped_release release;
    return engine::validate_study(study);
  });
}

// `poise replay`: sample `index` recomputed alone, as the command prints it.
py::object replay(const std::string& study, std::size_t index, std::optional<std::size_t> samples,
                  std::optional<std::uint64_t> seed) {
  return python_value(guarded([&] {
    py::gil_scoped_release release;
    engine::RunOptions o;
    o.samples = samples;
    o.seed = seed;
    o.progress = false;
    return engine::replay_sample(study, index, o);
  }));
}

py::object mass_properties(const std::vector<std::string>& meshes, const std::vector<std::string>& units,
                           const std::vector<std::string>& densities, int rays, bool drop_duplicates,
                           const std::string& weld, const std::string& max_overlap) {
  return python_value(guarded([&] {
    py::gil_scoped_release release;
    return cli::mass_properties_json({meshes, units, densities, rays, drop_duplicates, weld, max_overlap});
  }));
}

py::object diagnose(const std::string& data, double alpha, int max_harmonic, const std::string& noise,
                    const std::string& load_torque, const std::string& load_angle, const std::string& study,
                    std::size_t study_samples, const std::vector<std::string>& columns,
                    const std::vector<std::string>& units) {
  return python_value(guarded([&] {
    py::gil_scoped_release release;
    cli::DiagnoseRequest r;
    r.data = data;
    r.alpha = alpha;
    r.max_harmonic = max_harmonic;
    r.noise = noise;
    r.load_torque = load_torque;
    r.load_angle = load_angle;
    r.study = study;
    r.study_samples = study_samples;
    r.columns = {columns, units};
    return refused_as_input([&] { return cli::diagnose_json(r); });
  }));
}

}  // namespace
}  // namespace poise::python

PYBIND11_MODULE(_poise, m) {
  using namespace poise::python;
  m.doc() = "C++ side of the poise package (import poise, not this module)";
  poise::kinds::register_study_kinds();
  // The test hooks of the engine (POISE_INJECT_*), as the `poise` command reads them, and the
  // held sample's, for python/tests (engine/results/fault_injection.h): not part of the API.
  poise::engine::fault_injection::set_from_environment();
  m.def("_test_hold_at_sample",
        [](std::optional<std::size_t> k) { poise::engine::fault_injection::hold_at_sample(k); });
  m.def("_test_hold_reached", [] { return poise::engine::fault_injection::hold_reached(); });
  m.def("_test_release_hold", [] { poise::engine::fault_injection::release_hold(); });
  static py::exception<NativeError> native(m, "NativeError");
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const NativeError& e) {
      py::list errors;
      for (const RefusedValue& r : e.errors) {
        errors.append(py::dict(py::arg("message") = r.message, py::arg("file") = r.file, py::arg("line") = r.line,
                               py::arg("key") = r.key, py::arg("value") = r.value, py::arg("expected") = r.expected));
      }
      py::object args = py::make_tuple(e.category, e.message, e.file, e.line, e.key, errors);
      PyErr_SetObject(native.ptr(), args.ptr());
    }
  });
  m.attr("version") = std::string(poise::kVersion) + " (" + poise::kGitCommit + ")";
  // Warnings are kept for Python (poise.PoiseWarning through the warnings module, raised by
  // poise/__init__.py once the call returns and holds the GIL again); progress stays on stderr.
  static std::mutex warnings_mutex;
  static std::vector<std::string> pending_warnings;
  poise::diagnostics::set_sink([](poise::diagnostics::Kind kind, std::string_view text) {
    if (kind == poise::diagnostics::Kind::kWarning) {
      const std::lock_guard<std::mutex> lock(warnings_mutex);
      pending_warnings.emplace_back(text);
    } else {
      std::fprintf(stderr, "%.*s\n", static_cast<int>(text.size()), text.data());
    }
  });
  m.def("take_warnings", [] {
    const std::lock_guard<std::mutex> lock(warnings_mutex);
    return std::exchange(pending_warnings, {});
  });
  m.def("run", &run, py::arg("study"), py::arg("samples"), py::arg("seed"), py::arg("threads"), py::arg("overrides"),
        py::arg("plots"), py::arg("out"), py::arg("progress"), py::arg("sensitivity_base"), py::arg("model"),
        py::arg("allow_programs"));
  m.def("budget", &budget, py::arg("path"));
  m.def("validate", &validate, py::arg("study"));
  m.def("fit", &fit, py::arg("data"), py::arg("columns"), py::arg("units"));
  m.def("diagnose_record", &diagnose_record, py::arg("record"), py::arg("kt"), py::arg("columns"), py::arg("units"));
  m.def("error_mechanisms", &error_mechanisms, py::arg("dir"), py::arg("calibrate"), py::arg("draws"));
  m.def("optimize", &optimize, py::arg("file"), py::arg("out"), py::arg("threads"), py::arg("seed"), py::arg("plots"),
        py::arg("progress"));
  m.def("replay", &replay, py::arg("study"), py::arg("sample"), py::arg("samples"), py::arg("seed"));
  m.def("balance", &balance, py::arg("path"), py::arg("out"));
  m.def("mass_properties", &mass_properties, py::arg("meshes"), py::arg("units"), py::arg("densities"), py::arg("rays"),
        py::arg("drop_duplicates"), py::arg("weld"), py::arg("max_overlap"));
  m.def("diagnose", &diagnose, py::arg("data"), py::arg("alpha"), py::arg("max_harmonic"), py::arg("noise"),
        py::arg("load_torque"), py::arg("load_angle"), py::arg("study"), py::arg("study_samples"), py::arg("columns"),
        py::arg("units"));
  py::class_<Study>(m, "Study")
      .def(py::init<const std::string&, const std::map<std::string, std::string>&, std::optional<std::uint64_t>>(),
           py::arg("path"), py::arg("overrides"), py::arg("seed"))
      .def_property_readonly("kind", &Study::kind)
      .def_property_readonly("file", &Study::file)
      .def_property_readonly("output_names", &Study::output_names)
      .def_property_readonly("output_units", &Study::output_units)
      .def_property_readonly("output_descriptions", &Study::output_descriptions)
      .def_property_readonly("evaluates", &Study::evaluates)
      .def_property_readonly("why_not", &Study::why_not)
      .def_property_readonly("input_names", &Study::input_names)
      .def_property_readonly("input_units", &Study::input_units)
      .def_property_readonly("has_own_randomness", &Study::has_own_randomness)
      .def_property_readonly("evaluator_outputs", &Study::evaluator_outputs)
      .def("nominal", &Study::nominal)
      .def("evaluate", &Study::evaluate, py::arg("columns"), py::arg("points"), py::arg("threads"))
      .def("evaluate_matrix", &Study::evaluate_matrix, py::arg("x"), py::arg("threads"));
}
