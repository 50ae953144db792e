// The external study kind: a mechanism computed by a program of the user's own (any language),
// spoken to through its standard input and output (kinds/external/external_program.h). Its model
// file declares the parameters with units and tolerances and the outputs with units
// (engine/kind_interface/declared_model.h), and the program:
//
//     [model]
//     kind = "external"
//     name = "bearing stack axial gap"
//     command = ["python3", "stack_model.py"]   # no shell; run in the model file's folder
//     batch = 64                                # samples per request batch (default 64)
//     timeout = "60 s"                          # the longest wait for one answer (default 60 s)
//
// A model that names a program runs it only when the run allows programs (`--allow-programs`,
// Python allow_programs=True); `poise validate` prints the command line it would run.
#include <filesystem>
#include <memory>

#include "core/error.h"
#include "engine/kind_interface/closed_form_study.h"
#include "engine/kind_interface/declared_model.h"
#include "engine/kind_interface/procedure_kind.h"
#include "engine/kind_interface/programs_allowed.h"
#include "engine/study_files/model_overrides.h"
#include "kinds/external/external_program.h"

namespace poise::kinds::external {
using namespace poise::engine;
namespace {

struct ExternalModel : DeclaredModel {
  std::vector<std::string> command;
  std::string folder;  ///< the model file's, where the program runs
  std::size_t batch = 64;
  double timeout_s = 60.0;
};

ExternalModel read_model(const std::string& path, const std::map<std::string, std::string>& overrides) {
  ExternalModel e;
  static_cast<DeclaredModel&>(e) = read_declared_model(path, overrides, "external", [&e](TomlReader& model) {
    e.command = model.string_array("command");
    if (e.command.empty() && !model.schema_only()) {
      model.error("command", "[]", "the program and its arguments, e.g. [\"python3\", \"my_model.py\"] (no shell)");
    }
    e.batch = static_cast<std::size_t>(model.integer("batch", 1, 1000000, 64));
    e.timeout_s = model.quantity("timeout", units::kTime, positive, 60.0);
  });
  e.folder = std::filesystem::absolute(std::filesystem::path(path)).parent_path().lexically_normal().string();
  return e;
}

// One thread's process, in the model file's units.
class ExternalFunction final : public DeclaredUnitsFunction {
 public:
  explicit ExternalFunction(const ExternalModel& m)
      : DeclaredUnitsFunction(m.declaration),
        program_(std::make_unique<ExternalProgram>(m.command, m.folder, input_names(), output_names(), m.timeout_s)) {}

 protected:
  void evaluate(std::span<const std::size_t> ids, const std::vector<double>& inputs, std::span<double> outputs,
                std::vector<std::string>& failures) override {
    const std::vector<Answer> answers = program_->evaluate(std::vector<std::size_t>(ids.begin(), ids.end()), inputs);
    const std::size_t q = output_names().size();
    for (std::size_t r = 0; r < ids.size(); ++r) {
      failures[r] = answers[r].failed;
      if (!failures[r].empty()) continue;
      for (std::size_t k = 0; k < q; ++k) outputs[r * q + k] = answers[r].outputs[k];
    }
  }

 private:
  std::unique_ptr<ExternalProgram> program_;
};

class ExternalKind final : public ProcedureKind {
 public:
  std::string name() const override { return "external"; }
  std::string summary() const override {
    return "a mechanism computed by a program of your own, in any language, through its standard input and "
           "output (JSON lines; runs only with --allow-programs; model: e.g. models/bearing_stack_external.toml)";
  }
  std::unique_ptr<KindSections> read_sections(TomlReader&, const StudyConfig&) const override {
    return std::make_unique<ClosedFormSections>();
  }
  std::string validate(const StudyConfig& cfg) const override {
    const ExternalModel m = read_model(cfg.model_path, cfg.overrides);
    return validate_closed_form(cfg, m.declaration, m.model) + " The model runs the program " +
           ExternalProgram::command_line(m.command, m.folder) + " in batches of " + std::to_string(m.batch) +
           (programs_allowed() ? "." : ", which a run starts only with --allow-programs.");
  }
  std::unique_ptr<ProcedureStudy> make_study(const StudyConfig& cfg,
                                             const std::map<std::string, std::string>& model_overrides,
                                             std::size_t samples, std::uint64_t seed) const override {
    auto m = std::make_shared<const ExternalModel>(read_model(cfg.model_path, model_overrides));
    return make_closed_form_study(
        cfg, m->declaration, m->model, [m] { return std::make_unique<ExternalFunction>(*m); }, samples, seed, m->batch);
  }
  // Everything that computes samples starts the program: refused unless programs are allowed.
  std::string run(const StudyConfig& cfg, const RunOptions& options) const override {
    check_allowed(cfg);
    return ProcedureKind::run(cfg, options);
  }
  nlohmann::json replay(const StudyConfig& cfg, std::size_t index, const RunOptions& options) const override {
    check_allowed(cfg);
    return ProcedureKind::replay(cfg, index, options);
  }
  McResult evaluate(const StudyConfig& cfg, const std::map<std::string, std::string>& model_overrides,
                    std::size_t samples, std::uint64_t seed, int threads) const override {
    check_allowed(cfg);
    return ProcedureKind::evaluate(cfg, model_overrides, samples, seed, threads);
  }
  std::unique_ptr<InputEvaluator> input_evaluator(const StudyConfig& cfg,
                                                  const std::map<std::string, std::string>& model_overrides,
                                                  std::uint64_t seed) const override {
    check_allowed(cfg);
    return ProcedureKind::input_evaluator(cfg, model_overrides, seed);
  }

 private:
  static void check_allowed(const StudyConfig& cfg) {
    if (programs_allowed()) return;
    const ExternalModel m = read_model(cfg.model_path, cfg.overrides);
    throw UsageError("the model " + cfg.model_path +
                     " runs a program of its own: " + ExternalProgram::command_line(m.command, m.folder) +
                     ". A study must not run code when it is opened: run it with --allow-programs if you trust the "
                     "program (Python: allow_programs=True)");
  }
};

}  // namespace

std::unique_ptr<StudyKind> make_external_kind() { return std::make_unique<ExternalKind>(); }

}  // namespace poise::kinds::external
