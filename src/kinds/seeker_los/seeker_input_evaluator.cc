#include "kinds/seeker_los/seeker_input_evaluator.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "kinds/seeker_los/seeker_clearance.h"
#include "kinds/seeker_los/seeker_los_sections.h"
#include "kinds/seeker_los/seeker_los_study.h"

namespace poise::kinds::seeker_los {
using namespace poise::engine;
using namespace poise::model_files;
namespace {

class SeekerInputEvaluator final : public InputEvaluator {
 public:
  SeekerInputEvaluator(const StudyConfig& cfg, SeekerModel model) : study_(cfg, std::move(model), 1, cfg.seed) {
    for (const auto& c : study_.sampler().columns()) factors_.push_back(c.display_factor);
    for (const auto& o : kSeekerOutputs) outputs_.push_back({o.name, o.unit, o.description});
    const SeekerClearanceSpec& g = seeker_sections(cfg).clearance;
    if (g.clearance_output) {  // a design constraint of the nominal frames: the same at every point
      outputs_.push_back({"min_clearance_mm", "mm", "least clearance of the nominal frames to the housing"});
      clearance_mm_ = 1e3 * nominal_min_clearance(study_.model(), g.clearance_yaw_points, g.clearance_pitch_points);
    }
  }
  const std::vector<InputSpec>& inputs() const override { return study_.inputs(); }
  const std::vector<std::string>& input_names() const override { return study_.input_names(); }
  const std::vector<OutputSpec>& outputs() const override { return outputs_; }
  std::vector<double> nominal_inputs() const override { return study_.sampler().nominal(); }
  void evaluate_points(const InputColumns& inputs, double* values, std::size_t begin, std::size_t end,
                       std::vector<std::pair<std::size_t, std::string>>& failures) const override {
    SeekerLosStudy::Workspace ws = study_.make_workspace();
    evaluate_each_point(inputs, factors_, input_names().size(), outputs_.size(), values, begin, end, failures,
                        [&](std::size_t, std::span<const double> si, std::span<double> y) {
                          study_.evaluate_state(study_.sampler().state_of(si), ws, y.first(kNumSeekerOutputs), {});
                          if (y.size() > kNumSeekerOutputs) y[kNumSeekerOutputs] = clearance_mm_;
                        });
  }

 private:
  SeekerLosStudy study_;
  std::vector<double> factors_;
  std::vector<OutputSpec> outputs_;
  double clearance_mm_ = 0.0;
};

}  // namespace

std::unique_ptr<InputEvaluator> make_seeker_input_evaluator(const StudyConfig& cfg, SeekerModel model) {
  return std::make_unique<SeekerInputEvaluator>(cfg, std::move(model));
}

}  // namespace poise::kinds::seeker_los
