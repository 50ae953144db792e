#include "engine/kind_interface/closed_form_study.h"

#include <cmath>
#include <mutex>
#include <sstream>

#include "core/error.h"
#include "engine/results/result_io.h"
#include "engine/study_files/model_overrides.h"

namespace poise::engine {
namespace {}  // namespace

void ClosedFormFunction::compute_batch(std::span<const std::size_t> ids, std::span<const double> parameters,
                                       std::span<double> outputs, std::vector<std::string>& failures) {
  const std::size_t n = ids.size(), p = n ? parameters.size() / n : 0, q = n ? outputs.size() / n : 0;
  failures.assign(n, "");
  for (std::size_t r = 0; r < n; ++r) {
    try {
      compute(parameters.subspan(r * p, p), outputs.subspan(r * q, q));
    } catch (const Error& e) {
      failures[r] = e.what();
    }
  }
}

ClosedFormModel read_closed_form_model(const ClosedFormDeclaration& d, TomlReader& root) {
  ClosedFormModel model;
  model.header = read_model_header(root, d.name);
  TomlReader p = root.table("parameters");
  for (const auto& par : d.parameters) {
    // A dimensionless value may be a plain number or carry a dimensionless unit ("23.6 ppm").
    const bool plain = par.dimension == units::kDimensionless && !(p.has(par.name) && p.raw()[par.name].is_string());
    model.values.push_back(plain ? p.number(par.name) : p.quantity(par.name, par.dimension));
  }
  if (root.has_or_schema("tolerances")) {
    TomlReader t = root.table("tolerances");
    for (std::size_t k = 0; k < d.parameters.size(); ++k) {
      const ClosedFormParameter& par = d.parameters[k];
      if (!t.has(par.name) && !t.schema_only()) continue;
      bool range = false;
      if (t.has(par.name) && t.raw()[par.name].is_table()) {
        const TomlReader sub = t.table(par.name);
        range = sub.has("min") || sub.has("max");
      }
      model.drawn.push_back({k, read_tolerance(t, par.name, par.dimension, par.display_unit), range});
    }
  }
  return model;
}

namespace {

// A deviation as the drawing gives it: "normal, +-0.05 mm read as 3sigma ...", and for
// asymmetric limits the limits and the centre first ("-0.12 to 0 mm, centred on -0.06 mm: ...").
std::string deviation_text(const ToleranceSpec& spec, double factor, const std::string& unit) {
  const sampling::Distribution& d = spec.dist;
  std::string text = d.describe(spec.display_factor, spec.display_unit);
  if (d.nominal() == 0.0 || d.kind() == sampling::DistributionKind::kFixed) return text;
  return format_significant((d.nominal() - d.tolerance()) / factor, 6) + " to " +
         format_significant((d.nominal() + d.tolerance()) / factor, 6) + unit + ", centred on " +
         format_significant(d.nominal() / factor, 6) + unit + ": " + text;
}

std::string column_name(const ClosedFormParameter& p) {
  std::string unit = p.display_unit;
  for (auto& ch : unit) {
    if (ch == '*' || ch == '/' || ch == '^') ch = '_';
  }
  return unit.empty() || unit == "1" ? p.name : p.name + "_" + unit;
}

double display_factor(const std::string& unit) { return unit_quantity(unit).value; }

// The study of a closed-form kind: each sample draws the toleranced parameters from its
// design point and evaluates the kind's formula.
class ClosedFormStudy final : public ProcedureStudyBase<ClosedFormStudy> {
 public:
  ClosedFormStudy(StudyConfig cfg, ClosedFormDeclaration declaration, ClosedFormModel model,
                  ClosedFormFunctions functions, std::size_t samples, std::uint64_t seed, std::size_t batch)
      : cfg_(std::move(cfg)),
        declaration_(std::move(declaration)),
        model_(std::move(model)),
        functions_(std::move(functions)),
        batch_(std::max<std::size_t>(batch, 1)),
        samples_(samples),
        design_(make_design(cfg_, seed, samples, std::max<std::size_t>(model_.drawn.size(), 1))) {
    const ClosedFormDeclaration& d = declaration_;
    for (const auto& dr : model_.drawn) {
      const ClosedFormParameter& p = d.parameters[dr.parameter];
      declare_input(
          {column_name(p), p.display_unit.empty() ? "1" : p.display_unit, p.description, "tolerances." + p.name});
      input_factor_.push_back(display_factor(p.display_unit));
    }
    for (const auto& o : d.outputs) output_factor_.push_back(display_factor(o.unit));
    declare_outputs(d.outputs);
  }

  // One thread's function and buffers; with batches, the outputs of the range of samples the
  // driver gave the thread (begin_range), computed at once.
  struct Workspace {
    const ClosedFormStudy* study = nullptr;
    std::unique_ptr<ClosedFormFunction> function;
    std::vector<double> u, values;
    std::size_t begin = 0, end = 0;  // the batch computed: samples [begin, end)
    std::vector<std::size_t> ids;
    std::vector<double> rows_in, rows_out;
    std::vector<std::string> failures;
    void begin_range(std::size_t first, std::size_t n) { study->compute_range(first, n, *this); }
  };
  std::unique_ptr<Workspace> make_workspace() const {
    auto ws = std::make_unique<Workspace>();
    ws->study = this;
    ws->function = functions_();
    ws->u.resize(design_.dimension());
    return ws;
  }
  std::size_t samples_per_task() const override { return batch_ > 1 ? batch_ : 64; }

  // Sample i's parameters (SI) into ws.values and its inputs (display units) into `inputs`.
  void draw(std::size_t i, Workspace& ws, std::span<double> inputs) const {
    ws.values = model_.values;
    design_.point(i, ws.u);
    for (std::size_t k = 0; k < model_.drawn.size(); ++k) {
      const auto& dr = model_.drawn[k];
      const double x = dr.spec.dist.quantile(ws.u[k]);
      ws.values[dr.parameter] = dr.range ? x : ws.values[dr.parameter] + x;
      inputs[k] = ws.values[dr.parameter] / input_factor_[k];
    }
  }

  // Samples [first, first + n) through the function at once (a batch study only).
  void compute_range(std::size_t first, std::size_t n, Workspace& ws) const {
    if (batch_ <= 1) return;
    const std::size_t p = model_.values.size(), q = declaration_.outputs.size();
    ws.ids.resize(n);
    ws.rows_in.resize(n * p);
    ws.rows_out.assign(n * q, NAN);
    std::vector<double> inputs(model_.drawn.size());
    for (std::size_t r = 0; r < n; ++r) {
      ws.ids[r] = first + r;
      draw(first + r, ws, inputs);
      std::copy(ws.values.begin(), ws.values.end(), ws.rows_in.begin() + static_cast<long>(r * p));
    }
    try {
      ws.function->compute_batch(ws.ids, ws.rows_in, ws.rows_out, ws.failures);
    } catch (const Error& e) {
      ws.failures.assign(n, e.what());
    }
    ws.begin = first;
    ws.end = first + n;
  }

  void compute(std::size_t i, Workspace& ws, SampleResult& out) const {
    const ClosedFormDeclaration& d = declaration_;
    start_sample(i, out);  // the driver reuses its result slots: no allocation per sample
    if (batch_ > 1 && !(i >= ws.begin && i < ws.end)) compute_range(i, 1, ws);  // a replay, or outside the range
    draw(i, ws, out.inputs);
    try {
      if (batch_ > 1) {
        const std::size_t r = i - ws.begin, q = d.outputs.size();
        if (!ws.failures[r].empty()) throw Error(ws.failures[r]);
        std::copy(ws.rows_out.begin() + static_cast<long>(r * q), ws.rows_out.begin() + static_cast<long>((r + 1) * q),
                  out.outputs.begin());
      } else {
        ws.function->compute(ws.values, out.outputs);
      }
      for (std::size_t k = 0; k < out.outputs.size(); ++k) out.outputs[k] /= output_factor_[k];
    } catch (const Error& e) {
      out.ok = false;
      out.message = e.what();
      out.outputs.assign(d.outputs.size(), NAN);
    }
  }

  bool evaluates_inputs() const override { return true; }
  std::vector<InputLimits> input_limits() const override {
    std::vector<InputLimits> out;
    for (std::size_t k = 0; k < model_.drawn.size(); ++k) {
      const auto& dr = model_.drawn[k];
      const sampling::Distribution& d = dr.spec.dist;
      const double base = dr.range ? 0.0 : model_.values[dr.parameter], f = input_factor_[k];
      const double half = d.kind() == sampling::DistributionKind::kFixed ? 0.0 : d.tolerance();
      const double centre = d.kind() == sampling::DistributionKind::kFixed ? d.mean() : d.nominal();
      out.push_back({(base + centre - half) / f, (base + centre + half) / f, (base + d.mean()) / f, d.stddev() / f});
    }
    return out;
  }
  std::vector<double> nominal_inputs() const override {
    std::vector<double> x;
    for (std::size_t k = 0; k < model_.drawn.size(); ++k) {
      const auto& dr = model_.drawn[k];
      x.push_back((dr.range ? dr.spec.dist.quantile(0.5) : model_.values[dr.parameter]) / input_factor_[k]);
    }
    return x;
  }
  void evaluate_point(std::size_t, std::span<const double> inputs, std::span<double> outputs) const override {
    std::vector<std::string> failures;
    evaluate_points(inputs, 1, outputs, failures);
    if (!failures[0].empty()) throw Error(failures[0]);
  }
  void evaluate_points(std::span<const double> inputs, std::size_t n, std::span<double> outputs,
                       std::vector<std::string>& failures) const override {
    const std::size_t p = model_.values.size(), q = declaration_.outputs.size(), m = model_.drawn.size();
    std::vector<double> rows(n * p), si(n * q, NAN);
    std::vector<std::size_t> ids(n);
    for (std::size_t r = 0; r < n; ++r) {
      ids[r] = r;
      std::copy(model_.values.begin(), model_.values.end(), rows.begin() + static_cast<long>(r * p));
      for (std::size_t k = 0; k < m; ++k)
        rows[r * p + model_.drawn[k].parameter] = inputs[r * m + k] * input_factor_[k];
    }
    std::unique_ptr<ClosedFormFunction> f = take_function();
    try {
      f->compute_batch(ids, rows, si, failures);
    } catch (const Error& e) {
      failures.assign(n, e.what());
    } catch (...) {
      give_back(std::move(f));
      throw;
    }
    give_back(std::move(f));
    for (std::size_t r = 0; r < n; ++r) {
      for (std::size_t k = 0; k < q; ++k) {
        outputs[r * q + k] = failures[r].empty() ? si[r * q + k] / output_factor_[k] : NAN;
      }
    }
  }

  std::size_t samples() const { return samples_; }
  std::size_t design_dimension() const { return design_.dimension(); }
  const StudyConfig& config() const override { return cfg_; }
  std::string model_name() const override { return model_.header.name; }
  std::string model_source() const override { return model_.header.source; }
  void report_sections(const McResult&, const std::string&, bool, std::vector<std::string>&,
                       std::ostringstream& html) const override {
    const ClosedFormDeclaration& d = declaration_;
    html << "<h2>Model parameters</h2>\n<table><tr><th class='l'>parameter</th><th>value</th>"
            "<th class='l'>tolerance</th><th class='l'>source</th></tr>\n";
    for (std::size_t k = 0; k < d.parameters.size(); ++k) {
      const ClosedFormParameter& p = d.parameters[k];
      std::string tol = "fixed", source;
      for (const auto& dr : model_.drawn) {
        if (dr.parameter != k) continue;
        const double f = display_factor(p.display_unit);
        const std::string unit = p.display_unit.empty() || p.display_unit == "1" ? "" : " " + p.display_unit;
        tol = dr.range ? "range " + format_significant(dr.spec.dist.lower() / f, 6) + " to " +
                             format_significant(dr.spec.dist.upper() / f, 6) + unit + " (" +
                             sampling::to_string(dr.spec.dist.kind()) + "; the value above is not used)"
                       : "deviation: " + deviation_text(dr.spec, f, unit);
        source = dr.spec.source;
      }
      html << "<tr><td class='l'><code>" << html_escape(p.name) << "</code> " << html_escape(p.description)
           << "</td><td>" << format_significant(model_.values[k] / display_factor(p.display_unit), 6)
           << (p.display_unit.empty() || p.display_unit == "1" ? "" : " " + html_escape(p.display_unit))
           << "</td><td class='l'>" << html_escape(tol) << "</td><td class='l'>" << html_escape(source)
           << "</td></tr>\n";
    }
    html << "</table>\n";
    if (d.formulas.empty()) return;
    html << "<h2>Formulas</h2>\n<table><tr><th class='l'>name</th><th class='l'>formula</th></tr>\n";
    for (const auto& [what, formula] : d.formulas) {
      html << "<tr><td class='l'><code>" << html_escape(what) << "</code></td><td class='l'><code>"
           << html_escape(formula) << "</code></td></tr>\n";
    }
    html << "</table>\n";
  }

 private:
  // evaluate_point's functions, reused across calls from any thread.
  std::unique_ptr<ClosedFormFunction> take_function() const {
    {
      const std::lock_guard<std::mutex> lock(pool_mutex_);
      if (!pool_.empty()) {
        std::unique_ptr<ClosedFormFunction> f = std::move(pool_.back());
        pool_.pop_back();
        return f;
      }
    }
    return functions_();
  }
  void give_back(std::unique_ptr<ClosedFormFunction> f) const {
    const std::lock_guard<std::mutex> lock(pool_mutex_);
    pool_.push_back(std::move(f));
  }

  StudyConfig cfg_;
  ClosedFormDeclaration declaration_;
  ClosedFormModel model_;
  ClosedFormFunctions functions_;
  std::size_t batch_ = 1;
  mutable std::mutex pool_mutex_;
  mutable std::vector<std::unique_ptr<ClosedFormFunction>> pool_;
  std::size_t samples_;
  sampling::Design design_;
  std::vector<double> input_factor_, output_factor_;  ///< SI per display unit (not parsed per sample)
};

}  // namespace

std::unique_ptr<ProcedureStudy> make_closed_form_study(const StudyConfig& cfg, ClosedFormDeclaration declaration,
                                                       ClosedFormModel model, ClosedFormFunctions functions,
                                                       std::size_t samples, std::uint64_t seed, std::size_t batch) {
  return std::make_unique<ClosedFormStudy>(cfg, std::move(declaration), std::move(model), std::move(functions), samples,
                                           seed, batch);
}

std::string validate_closed_form(const StudyConfig& cfg, const ClosedFormDeclaration& d, const ClosedFormModel& m) {
  // A parameter drawn from a range has no value to sweep: its range sets it.
  for (const auto& sw : cfg.sweeps) {
    for (const auto& dr : m.drawn) {
      const std::string name = d.parameters[dr.parameter].name;
      if (dr.range && sw.parameter == "parameters." + name) {
        throw ValidationError({InputError(
            SourceLocation{cfg.file, sw.line, 0}, "sweep.parameter", quote_value(sw.parameter),
            "a parameter whose value counts: " + name +
                " is drawn from its range "
                "([tolerances." +
                name + "] min, max); sweep tolerances." + name + ".min and .max, or give it a deviation instead")});
      }
    }
  }
  return cfg.file + ": valid. Study '" + cfg.name + "' (" + cfg.kind + ") on model '" + m.header.name +
         "': " + std::to_string(m.drawn.size()) + " toleranced parameter(s) of " + std::to_string(d.parameters.size()) +
         ", " + std::to_string(d.outputs.size()) + " outputs, " + sampling::to_string(cfg.method) + " design, " +
         std::to_string(cfg.samples) + " samples, seed " + std::to_string(cfg.seed) + ".";
}

}  // namespace poise::engine
