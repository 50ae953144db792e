// Construction of the balancing-machine study: inputs and outputs named, the study checked
// against the model, and the rotor-input warnings (balancing_study.h).
#include <algorithm>
#include <string>

#include "core/units.h"
#include "kinds/balancing_machine/balancing_sections.h"
#include "kinds/balancing_machine/balancing_slots.h"
#include "kinds/balancing_machine/balancing_study.h"

namespace poise::studies {

using namespace balancing_detail;
using units::kPi;

namespace {
std::size_t unit_dimensions(const BalancingModel& m) {
  std::size_t d = 0;
  for (const auto& s : kSlots) {
    if (!(m.*s.tol).per_test) d += s.magnitude ? 2 : 1;
  }
  return d;
}
}  // namespace

BalancingStudy::BalancingStudy(StudyConfig config, BalancingModel model, std::size_t samples, std::uint64_t seed)
    : config_(std::move(config)),
      model_(std::move(model)),
      samples_(samples),
      seed_(seed),
      dimension_(unit_dimensions(model_)),
      design_(make_design(config_, seed_, samples_, std::max<std::size_t>(dimension_, 1))) {
  std::vector<InputError> errors;
  auto refuse = [&](int line, const std::string& key, const std::string& value, const std::string& expected) {
    errors.emplace_back(SourceLocation{config_.file, line, 0}, key, value, expected);
  };
  const int surfaces = model_.rotor.surfaces;
  for (const auto& [key, s] : {std::pair{"procedure.plane_1_surface", balancing_sections(config_).plane_1_surface},
                               std::pair{"procedure.plane_2_surface", balancing_sections(config_).plane_2_surface}}) {
    if (s > surfaces) refuse(0, key, std::to_string(s), "a testing surface of the rotor, 1.." + std::to_string(surfaces));
  }
  for (std::size_t e = 0; e < balancing_sections(config_).experiments.size(); ++e) {
    const BalancingExperiment& x = balancing_sections(config_).experiments[e];
    if (x.type == "stability" && x.surface > surfaces) {
      refuse(0, "experiment[" + std::to_string(e) + "].surface", std::to_string(x.surface),
             "a testing surface of the rotor, 1.." + std::to_string(surfaces));
    }
  }
  for (std::size_t k = 0; k < kSlotCount; ++k) {
    const SlotSpec& s = kSlots[k];
    const bool first_of_key = k == 0 || kSlots[k - 1].tol != s.tol;  // plate keys cover three plates
    if (s.hardware && (model_.*s.tol).per_test && first_of_key) {
      errors.emplace_back(SourceLocation{model_.file, 0, 0}, std::string("tolerances.") + s.key + ".scope", "\"test\"",
                          "scope = \"unit\": a property of the machine or rotor as built, not of one run");
    }
  }
  // Inputs: unit-scope draws (a plate tolerance is drawn for each plate).
  for (const auto& s : kSlots) {
    const ScopedTolerance& t = model_.*s.tol;
    if (t.per_test) continue;
    input_names_.push_back(std::string(s.name) + display_suffix(t.spec));
    if (s.magnitude) input_names_.push_back(std::string(s.name) + "_angle_deg");
    input_tolerances_.resize(input_names_.size(), std::string("tolerances.") + s.key);
  }
  // Outputs.
  output_names_ = {"omega1_Hz",           "omega2_Hz",         "hard_bearing_ratio",
                   "static_buckling_ratio", "static_stress_MPa", "static_tilt_urad",
                   "weight_stiffness_loss_pct", "pendulum_margin_ratio"};
  for (const auto& x : balancing_sections(config_).experiments) {
    const std::string& n = x.name;
    if (x.type == "separation") {
      for (int s = 1; s <= surfaces; ++s) {
        output_names_.push_back(n + "_s" + std::to_string(s) + "_sensor1_mN");
        output_names_.push_back(n + "_s" + std::to_string(s) + "_sensor2_mN");
      }
      for (const char* o : {"_sensor1_spread_pct", "_sensor2_zero_height_mm", "_sensor2_linearity_pct"}) {
        output_names_.push_back(n + o);
      }
    } else if (x.type == "umar") {
      for (const char* o : {"_plane1_kgm", "_plane2_kgm", "_kgm", "_xmax1_g", "_xmin1_g", "_xmax2_g", "_xmin2_g",
                            "_true_residual1_kgm", "_true_residual2_kgm", "_max_reading_error_g"}) {
        output_names_.push_back(n + o);
      }
      for (int p = 1; p <= 2; ++p) {
        for (int k = 0; k < x.positions; ++k) {
          output_names_.push_back(n + "_p" + std::to_string(p) + "_k" + std::to_string(k) + "_g");
        }
      }
    } else if (x.type == "stability") {
      for (const char* o : {"_residual_gmm", "_plane1_max_dev_pct", "_plane2_max_dev_pct", "_pass_ratio"}) {
        output_names_.push_back(n + o);
      }
      for (int p = 1; p <= 2; ++p) {
        for (int k = 0; k < x.positions; ++k) {
          output_names_.push_back(n + "_p" + std::to_string(p) + "_k" + std::to_string(k) + "_ratio");
        }
      }
    } else if (x.type == "urr") {
      for (const char* o : {"_plane1_pct", "_plane2_pct", "_min_pct", "_pass_ratio", "_iso_plane1_pct", "_iso_plane2_pct",
                            "_iso_min_pct", "_iso_pass_ratio"}) {
        output_names_.push_back(n + o);
      }
    } else if (x.type == "umar_iso") {
      for (const char* o : {"_plane1_kgm", "_plane2_kgm", "_plane1_max_dev_g", "_plane2_max_dev_g", "_plane1_mean_g",
                            "_plane2_mean_g", "_pass_ratio"}) {
        output_names_.push_back(n + o);
      }
      for (int p = 1; p <= 2; ++p) {
        for (int k = 0; k < x.positions; ++k) output_names_.push_back(n + "_p" + std::to_string(p) + "_k" + std::to_string(k) + "_g");
      }
    } else {
      for (const char* o : {"_u_error_ic_gmm", "_v_error_ic_gmm", "_plane_error_ic_pct", "_u_error_cf_gmm",
                            "_v_error_cf_gmm", "_plane_error_cf_pct", "_interference_ic_per_mm",
                            "_interference_cf_per_mm", "_x_amplitude_um"}) {
        output_names_.push_back(n + o);
      }
    }
  }
  if (!errors.empty()) throw ValidationError(errors);
  warnings_ = input_warnings();
}

std::vector<std::string> BalancingStudy::input_warnings() const {
  std::vector<std::string> w;
  const BalancingRotor& r = model_.rotor;
  // Denser than lead (11,340 kg/m^3) is no solid rotor: mass or dimensions are likely wrong.
  const double density = r.mass / (kPi * 0.25 * r.diameter * r.diameter * r.height);
  if (density > 11340.0) {
    w.push_back(model_.file + ": key 'rotor.mass' = " + units::format(r.mass, "kg", 4) + ": the rotor (solid cylinder " +
                units::format(r.diameter, "mm", 4) + " x " + units::format(r.height, "mm", 4) + ") would have density " +
                units::format(density, "kg/m^3", 4) + ", above lead's 11340 kg/m^3; check the mass, diameter and height");
  }
  const double outer = 0.5 * r.diameter;
  auto radius_check = [&](const std::string& key, double radius) {
    if (radius > outer) {
      w.push_back(config_.file + ": key '" + key + "' = " + units::format(radius, "mm", 4) +
                  " lies outside the rotor (radius " + units::format(outer, "mm", 4) + " from rotor.diameter of " +
                  model_.file + "): a test mass there cannot be placed in a testing hole");
    }
  };
  radius_check("procedure.calibration_radius", balancing_sections(config_).calibration_radius);
  const auto& xs = balancing_sections(config_).experiments;
  for (std::size_t e = 0; e < xs.size(); ++e) radius_check("experiment[" + std::to_string(e) + "].radius", xs[e].radius);
  return w;
}

std::size_t BalancingStudy::runs_per_sample() const {
  std::size_t runs = 3;  // influence calibration
  for (const auto& x : balancing_sections(config_).experiments) {
    if (x.type == "separation") runs += 1 + static_cast<std::size_t>(model_.rotor.surfaces * x.positions);
    if (x.type == "umar") runs += 2 * static_cast<std::size_t>(x.positions);
    if (x.type == "stability") runs += static_cast<std::size_t>(x.positions) + (x.balance_first ? 1 : 0);
    if (x.type == "urr") runs += 3;  // today's run, and the ISO indication bare and loaded
    if (x.type == "umar_iso") runs += static_cast<std::size_t>(x.positions);
    if (x.type == "accuracy") runs += 2;
  }
  return runs;
}

std::unique_ptr<BalancingStudy::Workspace> BalancingStudy::make_workspace() const {
  return std::make_unique<Workspace>(model_.run.solver);
}

nlohmann::json BalancingStudy::solver_json(const McResult& mc) const {
  return {{"integrator", "CVODE BDF"}, {"steps", mc.solver_steps}, {"rhs_evals", mc.rhs_evals},
          {"rtol", model_.run.solver.rtol}, {"atol_relative_to_response", model_.run.solver.atol},
          {"max_order", model_.run.solver.max_order}, {"runs_per_sample", runs_per_sample()}};
}

}  // namespace poise::studies
