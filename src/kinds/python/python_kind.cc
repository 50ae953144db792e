// The python study kind: a mechanism computed by a Python function of the user's own, called with
// a batch of samples as NumPy arrays (poise.run(study, model=f)). The model file declares the
// parameters with units and tolerances and the outputs with units
// (engine/kind_interface/declared_model.h):
//
//     [model]
//     kind = "python"
//     name = "bearing stack axial gap"
//     batch = 4096       # samples per call (default 4096)
//
// f(inputs) receives a dict of arrays, one per parameter in the unit its value is written in,
// and returns a dict of arrays (or numbers), one per output in its declared unit; a NaN is a
// sample without an answer. The engine does everything else (streams, requirements,
// sensitivity, sweeps, the report).
#include <memory>
#include <mutex>

#include "core/error.h"
#include "engine/kind_interface/closed_form_study.h"
#include "engine/kind_interface/declared_model.h"
#include "engine/kind_interface/procedure_kind.h"
#include "engine/study_files/model_overrides.h"
#include "kinds/python/python_model_function.h"

namespace poise::kinds::python {
using namespace poise::engine;
namespace {

std::mutex g_mutex;
BatchFunction g_function;

struct PythonModel : DeclaredModel {
  std::size_t batch = 4096;
};

PythonModel read_model(const std::string& path, const std::map<std::string, std::string>& overrides) {
  PythonModel p;
  static_cast<DeclaredModel&>(p) = read_declared_model(path, overrides, "python", [&p](TomlReader& model) {
    p.batch = static_cast<std::size_t>(model.integer("batch", 1, 100000000, 4096));
  });
  return p;
}

// A thread's calls of the function, in the model file's units.
class PythonFunction final : public DeclaredUnitsFunction {
 public:
  PythonFunction(const PythonModel& m, BatchFunction f) : DeclaredUnitsFunction(m.declaration), f_(std::move(f)) {}

 protected:
  void evaluate(std::span<const std::size_t> ids, const std::vector<double>& inputs, std::span<double> outputs,
                std::vector<std::string>& failures) override {
    f_(input_names(), output_names(), inputs, ids.size(), outputs, failures);
  }

 private:
  BatchFunction f_;
};

class PythonKind final : public ProcedureKind {
 public:
  std::string name() const override { return "python"; }
  std::string summary() const override {
    return "a mechanism computed by a Python function of your own on batches of NumPy arrays: "
           "poise.run(study, model=f) (model: e.g. models/bearing_stack_python.toml)";
  }
  std::unique_ptr<KindSections> read_sections(TomlReader&, const StudyConfig&) const override {
    return std::make_unique<ClosedFormSections>();
  }
  std::string validate(const StudyConfig& cfg) const override {
    const PythonModel m = read_model(cfg.model_path, cfg.overrides);
    return validate_closed_form(cfg, m.declaration, m.model) +
           " Its outputs come from a Python function in batches of " + std::to_string(m.batch) +
           ": run it from Python, poise.run(study, model=f).";
  }
  std::unique_ptr<ProcedureStudy> make_study(const StudyConfig& cfg,
                                             const std::map<std::string, std::string>& model_overrides,
                                             std::size_t samples, std::uint64_t seed) const override {
    auto m = std::make_shared<const PythonModel>(read_model(cfg.model_path, model_overrides));
    return make_closed_form_study(
        cfg, m->declaration, m->model,
        [m] {
          BatchFunction f = model_function();
          if (!f) {
            throw UsageError("the model " + m->model.header.file +
                             " computes its outputs with a Python function: run the study from Python, "
                             "poise.run(study, model=f)");
          }
          return std::make_unique<PythonFunction>(*m, f);
        },
        samples, seed, m->batch);
  }
  std::string run(const StudyConfig& cfg, const RunOptions& options) const override {
    check_function(cfg);
    return ProcedureKind::run(cfg, options);
  }
  nlohmann::json replay(const StudyConfig& cfg, std::size_t index, const RunOptions& options) const override {
    check_function(cfg);
    return ProcedureKind::replay(cfg, index, options);
  }

 private:
  static void check_function(const StudyConfig& cfg) {
    if (model_function()) return;
    throw UsageError("the model " + cfg.model_path +
                     " computes its outputs with a Python function (kind = \"python\"): run the study from Python, "
                     "poise.run(\"" +
                     cfg.file + "\", model=f), with f(inputs) -> outputs on dicts of NumPy arrays");
  }
};

}  // namespace

void set_model_function(BatchFunction f) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  g_function = std::move(f);
}

BatchFunction model_function() {
  const std::lock_guard<std::mutex> lock(g_mutex);
  return g_function;
}

std::unique_ptr<StudyKind> make_python_kind() { return std::make_unique<PythonKind>(); }

}  // namespace poise::kinds::python
