// The formula study kind: a mechanism of the user's own, its outputs written as formulas with
// units in the model file (kinds/formula/formula_model.h). The engine does everything else as
// for every closed-form kind (engine/kind_interface/closed_form_study.h): sampling, samples.csv
// and samples.h5, statistics, requirements and their answer, sweeps, sensitivity, the report.
#include <cmath>
#include <memory>

#include <muParser.h>

#include "core/error.h"
#include "engine/kind_interface/closed_form_study.h"
#include "engine/kind_interface/procedure_kind.h"
#include "kinds/formula/formula_model.h"

namespace poise::kinds::formula {
using namespace poise::engine;
namespace {

double atan2_of(double y, double x) { return std::atan2(y, x); }
double hypot_of(double x, double y) { return std::hypot(x, y); }
double floor_of(double x) { return std::floor(x); }
double ceil_of(double x) { return std::ceil(x); }
double pow_of(double x, double y) { return std::pow(x, y); }

// One thread's parsers: each formula compiled once by muParser, its names bound to this
// function's own values (parameters, then quantities), evaluated in the file's order.
class FormulaFunction final : public ClosedFormFunction {
 public:
  explicit FormulaFunction(const FormulaModel& m) : model_(m) {
    const std::size_t n_parameters = m.declaration.parameters.size();
    values_.assign(n_parameters + m.quantities.size(), 0.0);
    std::map<std::string, double*> slot;
    for (std::size_t k = 0; k < n_parameters; ++k) slot[m.declaration.parameters[k].name] = &values_[k];
    for (std::size_t k = 0; k < m.quantities.size(); ++k) slot[m.quantities[k].name] = &values_[n_parameters + k];
    for (const auto* group : {&m.quantities, &m.outputs}) {
      for (const NamedFormula& f : *group) {
        auto p = std::make_unique<mu::Parser>();
        p->DefineFun("atan2", atan2_of);
        p->DefineFun("hypot", hypot_of);
        p->DefineFun("floor", floor_of);
        p->DefineFun("ceil", ceil_of);
        p->DefineFun("pow", pow_of);
        p->DefineConst("pi", units::kPi);  // muParser 2.3.3's _pi has 13 digits: 3.141592653589
        try {
          for (const std::string& name : f.checked.names) p->DefineVar(name, slot.at(name));
          p->SetExpr(f.checked.muparser_text);
        } catch (const mu::Parser::exception_type& e) {
          throw Error("muParser refused the formula of " + f.name + " (" + f.checked.muparser_text +
                      "): " + e.GetMsg());
        }
        parsers_.push_back(std::move(p));
      }
    }
  }

  void compute(std::span<const double> parameters, std::span<double> outputs) override {
    std::copy(parameters.begin(), parameters.end(), values_.begin());
    const std::size_t n_parameters = parameters.size(), n_quantities = model_.quantities.size();
    for (std::size_t k = 0; k < n_quantities; ++k) values_[n_parameters + k] = evaluate(k, model_.quantities[k]);
    for (std::size_t k = 0; k < outputs.size(); ++k) outputs[k] = evaluate(n_quantities + k, model_.outputs[k]);
  }

 private:
  double evaluate(std::size_t k, const NamedFormula& f) {
    double x = NAN;
    try {
      x = parsers_[k]->Eval();
    } catch (const mu::Parser::exception_type& e) {
      throw Error("no value: " + f.name + " = " + f.text + ": " + e.GetMsg());
    }
    // A division by zero or a function outside its domain (sqrt or ln of a negative) gives
    // no number: the sample fails with the formula that gave none.
    if (!std::isfinite(x)) {
      throw Error(std::string("no value: ") + f.name + " = " + f.text + " is " +
                  (std::isnan(x) ? "not a number" : "infinite") +
                  " at this draw (a division by zero or a function outside its domain)");
    }
    return x;
  }

  const FormulaModel& model_;
  std::vector<double> values_;
  std::vector<std::unique_ptr<mu::Parser>> parsers_;
};

// The read model and its formulas for the report, shared by the study's functions.
std::shared_ptr<const FormulaModel> load(const std::string& path, const std::map<std::string, std::string>& overrides) {
  auto m = std::make_shared<FormulaModel>(read_formula_model(path, overrides));
  for (const NamedFormula& q : m->quantities) m->declaration.formulas.emplace_back(q.name, q.text);
  for (const NamedFormula& o : m->outputs) m->declaration.formulas.emplace_back(o.name + " [" + o.unit + "]", o.text);
  return m;
}

class FormulaKind final : public ProcedureKind {
 public:
  std::string name() const override { return "formula"; }
  std::string summary() const override {
    return "a mechanism of your own without C++: parameters with units and tolerances, outputs as formulas with "
           "units, checked when read (model: e.g. models/bearing_stack_formula.toml)";
  }
  std::unique_ptr<KindSections> read_sections(TomlReader&, const StudyConfig&) const override {
    return std::make_unique<ClosedFormSections>();
  }
  std::string validate(const StudyConfig& cfg) const override {
    const std::shared_ptr<const FormulaModel> m = load(cfg.model_path, cfg.overrides);
    // muParser compiles a formula at its first evaluation: do it now, at the nominal values,
    // so that nothing the check let through is refused mid-run.
    FormulaFunction f(*m);
    std::vector<double> out(m->outputs.size());
    try {
      f.compute(m->model.values, out);
    } catch (const Error&) {
      // A nominal design without a value is the samples' to report, each with its reason.
    }
    return validate_closed_form(cfg, m->declaration, m->model) + " Formulas: " + std::to_string(m->quantities.size()) +
           " quantities, " + std::to_string(m->outputs.size()) + " outputs, units checked.";
  }
  std::unique_ptr<ProcedureStudy> make_study(const StudyConfig& cfg,
                                             const std::map<std::string, std::string>& model_overrides,
                                             std::size_t samples, std::uint64_t seed) const override {
    std::shared_ptr<const FormulaModel> m = load(cfg.model_path, model_overrides);
    return make_closed_form_study(
        cfg, m->declaration, m->model, [m] { return std::make_unique<FormulaFunction>(*m); }, samples, seed);
  }
};

}  // namespace

std::unique_ptr<StudyKind> make_formula_kind() { return std::make_unique<FormulaKind>(); }

}  // namespace poise::kinds::formula
