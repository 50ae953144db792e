#pragma once
/// What the geometry kinds' studies share (engine/kind_interface/procedure_study.h): a sample
/// is the design point drawn through the model's sampler into the drawn inputs (display
/// units) and the outputs of that realization; the same outputs at inputs a caller gives
/// (Study.evaluate). No solver, no randomness of its own.
///
/// Derived provides: config(), samples(), design() (sampling::Design), sampler() (with
/// dimension(), columns(), nominal() and draw(u, values)), realization_of(si) (what draw()
/// returns for those inputs in SI) and outputs_of(realization) (throws poise::Error for a
/// realization without an answer: the sample fails with the reason).
#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <span>
#include <vector>

#include "engine/kind_interface/procedure_study.h"

namespace poise::geometry_studies {

template <class Derived>
class SampledModelStudy : public engine::ProcedureStudyBase<Derived> {
 public:
  struct Workspace {};
  std::unique_ptr<Workspace> make_workspace() const { return std::make_unique<Workspace>(); }
  std::size_t design_dimension() const { return study().sampler().dimension(); }

  void compute(std::size_t i, Workspace&, engine::SampleResult& out) const {
    out = engine::SampleResult{};  // the driver reuses its result slots
    out.index = i;
    out.inputs.assign(design_dimension(), 0.0);
    std::vector<double> u(design_dimension());
    study().design().point(i, u);
    try {
      out.outputs = study().outputs_of(study().sampler().draw(u, out.inputs));
    } catch (const std::exception& e) {
      out.ok = false;
      out.message = e.what();
      out.outputs.assign(this->outputs().size(), NAN);
    }
  }

  bool evaluates_inputs() const override { return true; }
  std::vector<double> nominal_inputs() const override { return study().sampler().nominal(); }
  void evaluate_point(std::size_t, std::span<const double> inputs, std::span<double> outputs) const override {
    std::vector<double> si(inputs.begin(), inputs.end());
    for (std::size_t k = 0; k < si.size(); ++k) si[k] *= study().sampler().columns()[k].display_factor;
    const std::vector<double> o = study().outputs_of(study().realization_of(si));
    std::copy(o.begin(), o.end(), outputs.begin());
  }

 private:
  const Derived& study() const { return static_cast<const Derived&>(*this); }
};

}  // namespace poise::geometry_studies
