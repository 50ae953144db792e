// Construction of the balancing-machine study: inputs and outputs named, the study checked
// against the model, and the rotor-input warnings (balancing_study.h).
#include <algorithm>
#include <string>

#include "core/units.h"
#include "kinds/balancing_machine/balancing_sections.h"
#include "kinds/balancing_machine/balancing_slots.h"
#include "kinds/balancing_machine/balancing_study.h"

namespace poise::kinds::balancing_machine {
using namespace poise::engine;

using namespace detail;
using units::kPi;

namespace {
std::size_t unit_dimensions(const BalancingModel& m) {
  std::size_t d = 0;
  for (const auto& s : kSlots) {
    if (!(m.*s.tol).per_test) d += s.magnitude ? 2 : 1;
  }
  return d;
}

// What the study asks of the model that it does not have: correction planes and test
// surfaces beyond the rotor's, hardware tolerances drawn per test.
void check_against_model(const StudyConfig& config, const BalancingModel& model, std::vector<InputError>& errors) {
  const BalancingSections& sections = balancing_sections(config);
  auto refuse = [&](int line, const std::string& key, const std::string& value, const std::string& expected) {
    errors.emplace_back(SourceLocation{config.file, line, 0}, key, value, expected);
  };
  const int surfaces = model.rotor.surfaces;
  for (const auto& [key, s] : {std::pair{"procedure.plane_1_surface", sections.plane_1_surface},
                               std::pair{"procedure.plane_2_surface", sections.plane_2_surface}}) {
    if (s > surfaces)
      refuse(0, key, std::to_string(s), "a testing surface of the rotor, 1.." + std::to_string(surfaces));
  }
  for (std::size_t e = 0; e < sections.experiments.size(); ++e) {
    const BalancingExperiment& x = sections.experiments[e];
    if (x.type == "stability" && x.surface > surfaces) {
      refuse(0, "experiment[" + std::to_string(e) + "].surface", std::to_string(x.surface),
             "a testing surface of the rotor, 1.." + std::to_string(surfaces));
    }
  }
  for (std::size_t k = 0; k < kSlotCount; ++k) {
    const SlotSpec& s = kSlots[k];
    const bool first_of_key = k == 0 || kSlots[k - 1].tol != s.tol;  // plate keys cover three plates
    if (s.hardware && (model.*s.tol).per_test && first_of_key) {
      errors.emplace_back(SourceLocation{model.file, 0, 0}, std::string("tolerances.") + s.key + ".scope", "\"test\"",
                          "scope = \"unit\": a property of the machine or rotor as built, not of one run");
    }
  }
}

// Outputs named prefix + each declaration's name.
void declare(std::vector<OutputSpec>& outputs, const std::string& prefix,
             std::initializer_list<OutputDeclaration> list) {
  append_outputs(outputs, prefix, std::span<const OutputDeclaration>(list.begin(), list.size()));
}

// One output per plane and position: n_p<plane>_k<position><suffix>.
void readings(std::vector<OutputSpec>& outputs, const std::string& n, int positions, const char* suffix,
              const char* unit, const char* what) {
  for (int p = 1; p <= 2; ++p) {
    for (int k = 0; k < positions; ++k) {
      outputs.push_back({n + "_p" + std::to_string(p) + "_k" + std::to_string(k) + suffix, unit,
                         n + ": " + what + ", plane " + std::to_string(p) + ", position " + std::to_string(k)});
    }
  }
}

// The outputs of one experiment, by its type.
void experiment_outputs(const BalancingExperiment& x, int surfaces, std::vector<OutputSpec>& outputs) {
  const std::string& n = x.name;
  if (x.type == "separation") {
    for (int s = 1; s <= surfaces; ++s) {
      for (int k = 1; k <= 2; ++k) {
        outputs.push_back({n + "_s" + std::to_string(s) + "_sensor" + std::to_string(k) + "_mN", "mN",
                           n + ": effect of the test mass on surface " + std::to_string(s) + " at sensor " +
                               std::to_string(k) + " (mean over the holes)"});
      }
    }
    declare(outputs, n,
            {{"_sensor1_spread_pct", "%", "spread of sensor 1's effect over the surfaces (max - min, of the mean)"},
             {"_sensor2_zero_height_mm", "mm", "height where sensor 2's fitted line crosses zero (the torsion centre)"},
             {"_sensor2_linearity_pct", "%", "linearity of sensor 2 against height"}});
  } else if (x.type == "umar") {
    declare(outputs, n,
            {{"_plane1_kgm", "kg*m", "U_mar of plane 1: (X_max - X_min) r / 2"},
             {"_plane2_kgm", "kg*m", "U_mar of plane 2: (X_max - X_min) r / 2"},
             {"_kgm", "kg*m", "U_mar (Eq. 18): the sum of the planes'"},
             {"_xmax1_g", "g", "largest reading of plane 1"},
             {"_xmin1_g", "g", "smallest reading of plane 1"},
             {"_xmax2_g", "g", "largest reading of plane 2"},
             {"_xmin2_g", "g", "smallest reading of plane 2"},
             {"_true_residual1_kgm", "kg*m", "the rotor's true residual unbalance in plane 1"},
             {"_true_residual2_kgm", "kg*m", "the rotor's true residual unbalance in plane 2"},
             {"_max_reading_error_g", "g", "largest reading error"}});
    readings(outputs, n, x.positions, "_g", "g", "reading");
  } else if (x.type == "stability") {
    declare(outputs, n,
            {{"_residual_gmm", "g*mm", "largest plane residual after balancing first"},
             {"_plane1_max_dev_pct", "%", "largest deviation of plane 1's readings from their mean"},
             {"_plane2_max_dev_pct", "%", "largest deviation of plane 2's readings from their mean"},
             {"_pass_ratio", "1", "1 when the stability test passes, else 0"}});
    readings(outputs, n, x.positions, "_ratio", "1", "reading over the mean");
  } else if (x.type == "urr") {
    declare(outputs, n,
            {{"_plane1_pct", "%", "unbalance reduction ratio of plane 1 after one physical correction"},
             {"_plane2_pct", "%", "unbalance reduction ratio of plane 2 after one physical correction"},
             {"_min_pct", "%", "the smaller of the planes' reduction ratios"},
             {"_pass_ratio", "1", "1 when the reduction ratio meets the claim, else 0"},
             {"_iso_plane1_pct", "%", "ISO 21940-21 reduction ratio of plane 1 (indication of known test masses)"},
             {"_iso_plane2_pct", "%", "ISO 21940-21 reduction ratio of plane 2 (indication of known test masses)"},
             {"_iso_min_pct", "%", "the smaller of the ISO reduction ratios"},
             {"_iso_pass_ratio", "1", "1 when the ISO reduction ratio meets the claim, else 0"}});
  } else if (x.type == "umar_iso") {
    declare(outputs, n,
            {{"_plane1_kgm", "kg*m", "U_mar of plane 1 (both planes loaded): (X_max - X_min) r / 2"},
             {"_plane2_kgm", "kg*m", "U_mar of plane 2 (both planes loaded): (X_max - X_min) r / 2"},
             {"_plane1_max_dev_g", "g", "largest |X - mean| of plane 1"},
             {"_plane2_max_dev_g", "g", "largest |X - mean| of plane 2"},
             {"_plane1_mean_g", "g", "mean reading of plane 1"},
             {"_plane2_mean_g", "g", "mean reading of plane 2"},
             {"_pass_ratio", "1", "1 when every reading lies within mean +- claim / r, else 0"}});
    readings(outputs, n, x.positions, "_g", "g", "reading");
  } else if (x.type == "calibration") {
    for (int s = 1; s <= 2; ++s) {
      for (int p = 1; p <= 2; ++p) {
        const std::string sp = "_s" + std::to_string(s) + "_p" + std::to_string(p);
        const std::string which = "plane " + std::to_string(p) + " at sensor " + std::to_string(s);
        outputs.push_back({n + sp + "_N_per_kgm", "N/kg/m",
                           n + ": influence coefficient |C| of " + which +
                               " (sensor force per unbalance, at the nominal speed), the machine's own calibration"});
        outputs.push_back({n + sp + "_deg", "deg", n + ": phase of the influence coefficient of " + which});
      }
    }
  } else {
    declare(outputs, n,
            {{"_u_error_ic_gmm", "g*mm", "static unbalance error |U^ - U|, influence coefficients"},
             {"_v_error_ic_gmm", "g*mm", "couple unbalance error |V^ - V| / (z2 - z1), influence coefficients"},
             {"_plane_error_ic_pct", "%", "larger plane error |U_p^ - U_p| / |U_p|, influence coefficients"},
             {"_u_error_cf_gmm", "g*mm", "static unbalance error |U^ - U|, corrected closed form (Eq. 13)"},
             {"_v_error_cf_gmm", "g*mm", "couple unbalance error |V^ - V| / (z2 - z1), corrected closed form"},
             {"_plane_error_cf_pct", "%", "larger plane error |U_p^ - U_p| / |U_p|, corrected closed form"},
             {"_interference_ic_per_mm", "1/mm",
              "static unbalance indicated per unit of couple unbalance (ISO I_s,c), influence coefficients"},
             {"_interference_cf_per_mm", "1/mm",
              "static unbalance indicated per unit of couple unbalance (ISO I_s,c), corrected closed form"},
             {"_x_amplitude_um", "um", "amplitude of the horizontal plates' motion for the piece's static unbalance"}});
  }
}

// Every output, each declared once with its unit and meaning: the machine's, then each
// experiment's.
std::vector<OutputSpec> balancing_outputs(const BalancingSections& sections, int surfaces) {
  std::vector<OutputSpec> outputs;
  declare(
      outputs, "",
      {{"omega1_Hz", "Hz", "first natural frequency of the machine as built with rotor R"},
       {"omega2_Hz", "Hz", "second natural frequency of the machine as built with rotor R"},
       {"hard_bearing_ratio", "1",
        "hard-bearing ratio of the machine as built: natural frequency over the balancing speed"},
       {"static_buckling_ratio", "1",
        "buckling factor P_cr / P of the horizontal plates under the weight (the smaller)"},
       {"static_stress_MPa", "MPa", "largest plate stress under the weight of frame and rotor R"},
       {"static_tilt_urad", "urad", "tilt of the swinging part from the rotor's mass-centre offset under the weight"},
       {"weight_stiffness_loss_pct", "%", "share of the horizontal plates' stiffness k5 lost to the weight"},
       {"pendulum_margin_ratio", "1", "pendulum margin K_rot / (m g H): below 1 the swinging part topples"}});
  for (const auto& x : sections.experiments) experiment_outputs(x, surfaces, outputs);
  return outputs;
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
  check_against_model(config_, model_, errors);
  // Inputs: unit-scope draws (a plate tolerance is drawn for each plate).
  for (const auto& s : kSlots) {
    const ScopedTolerance& t = model_.*s.tol;
    if (t.per_test) continue;
    const std::string tolerance = std::string("tolerances.") + s.key;
    declare_input({std::string(s.name) + display_suffix(t.spec),
                   t.spec.display_unit.empty() ? "1" : t.spec.display_unit, "", tolerance});
    if (s.magnitude) declare_input({std::string(s.name) + "_angle_deg", "deg", "its direction", tolerance});
  }
  declare_outputs(balancing_outputs(balancing_sections(config_), model_.rotor.surfaces));
  if (!errors.empty()) throw ValidationError(errors);
  warnings_ = input_warnings();
}

std::vector<std::string> BalancingStudy::tolerance_keys() const {
  std::vector<std::string> keys;
  for (const auto& s : kSlots) {
    const std::string key = std::string("tolerances.") + s.key;
    if ((model_.*s.tol).spec.tolerance > 0.0 && std::find(keys.begin(), keys.end(), key) == keys.end())
      keys.push_back(key);
  }
  return keys;
}

std::vector<std::string> BalancingStudy::input_warnings() const {
  std::vector<std::string> w;
  const BalancingRotor& r = model_.rotor;
  // Denser than lead (11,340 kg/m^3) is no solid rotor: mass or dimensions are likely wrong.
  const double density = r.mass / (kPi * 0.25 * r.diameter * r.diameter * r.height);
  if (density > 11340.0) {
    w.push_back(model_.file + ": key 'rotor.mass' = " + units::format(r.mass, "kg", 4) +
                ": the rotor (solid cylinder " + units::format(r.diameter, "mm", 4) + " x " +
                units::format(r.height, "mm", 4) + ") would have density " + units::format(density, "kg/m^3", 4) +
                ", above lead's 11340 kg/m^3; check the mass, diameter and height");
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
  for (std::size_t e = 0; e < xs.size(); ++e)
    radius_check("experiment[" + std::to_string(e) + "].radius", xs[e].radius);
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
  if (model_.run.response == procedures::BalancingResponse::kSteadyState) {
    return {{"integrator",
             "none: the exact steady state, sampled with the run's noise (solver.response = "
             "\"steady_state\", the fast model)"},
            {"runs_per_sample", runs_per_sample()}};
  }
  return {{"integrator", "CVODE BDF"},
          {"steps", mc.solver_steps},
          {"rhs_evals", mc.rhs_evals},
          {"rtol", model_.run.solver.rtol},
          {"atol_relative_to_response", model_.run.solver.atol},
          {"max_order", model_.run.solver.max_order},
          {"runs_per_sample", runs_per_sample()}};
}

}  // namespace poise::kinds::balancing_machine
