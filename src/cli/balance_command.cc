#include "cli/balance_command.h"

#include <cmath>
#include <iostream>
#include <memory>
#include <numbers>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/balance_campaign.h"
#include "core/error.h"
#include "core/format.h"
#include "engine/study_files/toml_reader.h"

namespace poise::cli {
namespace {
using estimators::Phasor;
using nlohmann::json;

const char* kBalanceHelp = R"(What it does:
  Reads a balancing campaign: the once-per-revolution (1X) readings of each sensor, amplitude
  and phase, on runs with known masses added in known planes, and fits the influence
  coefficients of every sensor and plane by complex least squares over all of those runs,
  with the rotor's own readings jointly:

      v[run][sensor] = a[sensor] + sum over planes of h[sensor][plane] * w[run][plane]

  (w = mass at its angle). With more runs than 1 + planes the residuals give each figure a
  standard error. Then the least-squares correction of the rotor (the masses that minimise
  the sum of the squared residual readings over every sensor, trial masses removed) and the
  residual it leaves, and, for a run whose masses are unknown, its unbalance relative to the
  calibrated rotor. The condition number of the influence matrix says whether the planes are
  separable on these sensors.

Campaign file: see cli/balance_campaign.h, or the worked examples:
  poise balance tests/data/real/feese2004_compressor/campaign.toml
  poise balance tests/data/real/kelm2016_compressor/campaign.toml --json

Output: the coefficients (amplitude unit per gram) with standard errors, the correction per
plane (grams at the plane's radius, angle in the campaign's sense), the predicted residual
per sensor and its RMS; --json prints one JSON object instead.
Exit status: 0 success, 2 invalid input (file, line, key and what was expected).
)";

double degrees(const Phasor& z) {
  double d = std::arg(z) * 180.0 / std::numbers::pi;
  if (d < 0.0) d += 360.0;
  return d;
}

std::string phasor_text(const Phasor& z, const std::string& unit) {
  return unit.empty() ? fmt::format("{} @ {:.1f} deg", significant(std::abs(z), 4), degrees(z))
                      : fmt::format("{} {} @ {:.1f} deg", significant(std::abs(z), 4), unit, degrees(z));
}

json phasor_json(const Phasor& z) { return {{"amplitude", std::abs(z)}, {"angle_deg", degrees(z)}}; }

json result_json(const BalancingCampaign& c, const estimators::InfluenceCalibration& cal,
                 const estimators::Correction& corr) {
  json h = json::array();
  for (std::size_t s = 0; s < c.sensors.size(); ++s) {
    for (std::size_t p = 0; p < c.planes.size(); ++p) {
      json e{{"sensor", c.sensors[s]}, {"plane", c.planes[p]}, {"value", phasor_json(cal.h[s][p].value)}};
      e["standard_error"] = cal.h[s][p].se ? json(*cal.h[s][p].se) : json(nullptr);
      h.push_back(e);
    }
  }
  json masses = json::array(), residual = json::array();
  for (std::size_t p = 0; p < c.planes.size(); ++p) {
    masses.push_back(
        {{"plane", c.planes[p]}, {"mass_g", std::abs(corr.masses[p])}, {"angle_deg", degrees(corr.masses[p])}});
  }
  for (std::size_t s = 0; s < c.sensors.size(); ++s) {
    residual.push_back({{"sensor", c.sensors[s]}, {"reading", phasor_json(corr.residual[s])}});
  }
  return {{"campaign", c.name},
          {"amplitude_unit", c.amplitude_unit},
          {"runs_used", cal.runs},
          {"degrees_of_freedom", cal.dof},
          {"influence_coefficients", h},
          {"influence_unit", c.amplitude_unit + " per g"},
          {"condition_number", cal.condition},
          {"correction", masses},
          {"predicted_residual", residual},
          {"predicted_residual_rms", corr.residual_rms}};
}

void print_text(const BalancingCampaign& c, const estimators::InfluenceCalibration& cal,
                const estimators::Correction& corr) {
  std::cout << "Campaign '" << c.name << "' (" << c.file << "): " << cal.runs << " readings of runs with known masses, "
            << c.sensors.size() << " sensors, " << c.planes.size() << " planes; " << cal.dof << " degrees of freedom"
            << (cal.dof == 0 ? " (as many readings as unknowns: no standard errors; another run would give them)" : "")
            << ".\nInfluence coefficients [" << c.amplitude_unit << " per g]:\n";
  for (std::size_t s = 0; s < c.sensors.size(); ++s) {
    for (std::size_t p = 0; p < c.planes.size(); ++p) {
      std::cout << "  " << c.sensors[s] << " from " << c.planes[p] << ": " << phasor_text(cal.h[s][p].value, "")
                << (cal.h[s][p].se ? " (se " + significant(*cal.h[s][p].se, 2) + ")" : std::string()) << '\n';
    }
  }
  std::cout << "Planes' separation: condition number " << significant(cal.condition, 3) << " of the influence matrix"
            << (cal.condition > 100.0 ? " (the planes are hardly separable on these sensors)" : "") << ".\n";
  double before = 0.0;
  for (const auto& a : cal.initial) before += std::norm(a.value);
  before = std::sqrt(before / static_cast<double>(cal.initial.size()));
  std::cout << "Predicted residual after correction:";
  for (std::size_t s = 0; s < c.sensors.size(); ++s) {
    std::cout << (s ? ", " : " ") << c.sensors[s] << " " << phasor_text(corr.residual[s], c.amplitude_unit);
  }
  std::cout << ".\n";
  std::string answer = "Correction (trial masses removed):";
  for (std::size_t p = 0; p < c.planes.size(); ++p) {
    answer += (p ? ", " : " ") + c.planes[p] + " " + phasor_text(corr.masses[p], "g");
  }
  std::cout << answer << "; the predicted residual RMS " << significant(corr.residual_rms, 3) << " " << c.amplitude_unit
            << " (from " << significant(before, 3) << " " << c.amplitude_unit << ").\n";
}

int run_balance(const std::string& path, bool as_json) {
  try {
    const BalancingCampaign c = read_balancing_campaign(path);
    const estimators::InfluenceCalibration cal = estimators::calibrate(c.runs, c.planes.size());
    const estimators::Correction corr = estimators::correction(cal);
    if (as_json) {
      std::cout << result_json(c, cal, corr).dump(2) << '\n';
    } else {
      print_text(c, cal, corr);
    }
    return 0;
  } catch (const engine::ValidationError& e) {
    std::cerr << "poise: " << e.what() << '\n';
    return 2;
  } catch (const InputError& e) {
    std::cerr << "poise: " << e.what() << '\n';
    return 2;
  } catch (const Error& e) {
    std::cerr << "poise: " << path << ": " << e.what() << '\n';
    return 2;
  }
}

}  // namespace

BalanceHandler add_balance_command(CLI::App& app) {
  struct Options {
    std::string campaign;
    bool json = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand(
      "balance", "influence coefficients, correction masses and residual from a balancing campaign's readings");
  sub->add_option("CAMPAIGN", opt->campaign, "campaign file (TOML) naming the readings file")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_flag("--json", opt->json, "print the results as one JSON object");
  sub->footer(kBalanceHelp);
  return [sub, opt]() -> std::optional<int> {
    if (!*sub) return std::nullopt;
    return run_balance(opt->campaign, opt->json);
  };
}

}  // namespace poise::cli
