#include "engine/kind_interface/closed_form_kind.h"

#include "engine/kind_interface/closed_form_study.h"
#include "engine/study_files/model_overrides.h"

namespace poise::engine {
namespace {

// A compiled kind's function: its compute(), which keeps no state.
class KindFunction final : public ClosedFormFunction {
 public:
  explicit KindFunction(const ClosedFormKind& kind) : kind_(kind) {}
  void compute(std::span<const double> parameters, std::span<double> outputs) override {
    const std::vector<double> si = kind_.compute(parameters);
    std::copy(si.begin(), si.begin() + static_cast<long>(std::min(si.size(), outputs.size())), outputs.begin());
  }

 private:
  const ClosedFormKind& kind_;
};

ClosedFormModel load_model(const ClosedFormDeclaration& d, const std::string& path,
                           const std::map<std::string, std::string>& overrides) {
  ModelDocument m = open_model_file(path, overrides);
  TomlReader root(m.doc, m.ctx);
  ClosedFormModel model = read_closed_form_model(d, root);
  finish(m.doc, *m.ctx);
  return model;
}

}  // namespace

ClosedFormKind::ClosedFormKind(ClosedFormDeclaration declaration) : declaration_(std::move(declaration)) {}

std::unique_ptr<KindSections> ClosedFormKind::read_sections(TomlReader&, const StudyConfig&) const {
  return std::make_unique<ClosedFormSections>();
}

std::string ClosedFormKind::validate(const StudyConfig& cfg) const {
  return validate_closed_form(cfg, declaration_, load_model(declaration_, cfg.model_path, cfg.overrides));
}

std::unique_ptr<ProcedureStudy> ClosedFormKind::make_study(const StudyConfig& cfg,
                                                           const std::map<std::string, std::string>& model_overrides,
                                                           std::size_t samples, std::uint64_t seed) const {
  return make_closed_form_study(
      cfg, declaration_, load_model(declaration_, cfg.model_path, model_overrides),
      [this] { return std::make_unique<KindFunction>(*this); }, samples, seed);
}

}  // namespace poise::engine
