#include "cli/balance_command.h"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numbers>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "balancing/balance_report.h"
#include "balancing/campaign.h"
#include "balancing/campaign_analysis.h"
#include "balancing/iso_figures.h"
#include "cli/balance_design.h"
#include "core/error.h"
#include "core/format.h"
#include "engine/study_files/toml_reader.h"

namespace poise::cli {
namespace {

const char* kBalanceHelp = R"(What it does:
  Reads a balancing campaign: the once-per-revolution (1X) readings of each sensor, amplitude
  and phase, on runs with known masses added in known planes, and fits the influence
  coefficients of every sensor and plane by complex least squares over all of those runs,
  with the rotor's own readings jointly:

      v[run][sensor] = a[sensor] + sum over planes of h[sensor][plane] * w[run][plane]

  (w = mass at its angle). With more runs than 1 + planes the residuals give each figure a
  standard error and each answer a 95% confidence region (an ellipse in the complex plane;
  the text gives its largest half axis as "+-"). Answers:
    - the rotor's own unbalance, per plane and as static and couple unbalance (two planes);
    - the least-squares correction (the masses that minimise the sum of the squared residual
      readings over every sensor, trial masses removed) and the reading each sensor will
      show after it, with a 95% prediction region;
    - for each run of unknown masses (omit `masses`), the masses that explain its readings
      beyond the calibrated rotor's;
    - for each check run (`check = true`: masses known, left out of the calibration), the
      same answer beside the masses applied, and whether its region holds them.
  The condition number of the influence matrix says whether the planes are separable on
  these sensors. Then the tests of the linear model (lack of fit against repeats, amplitude
  nonlinearity, phase sense, runout across speeds), ISO 21940-21's URR and U_mar from the
  check runs, and with [design] the real figures placed in a design study's distributions.

Readings as a lab keeps them: a wide table (a row per reading of a run) or a long one (a row
per sensor's reading), amplitude and phase or real and imaginary parts, runs by number or
name, units in the headers, a speed column (each speed calibrated apart), phase lag or lead
and masses' angles with or against rotation as declared.

Campaign file: see src/balancing/campaign.h, or the worked examples:
  poise balance tests/data/real/feese2004_compressor/campaign.toml
  poise balance tests/data/real/kelm2016_compressor/campaign.toml --json

Output: the coefficients (amplitude unit per gram) with standard errors, the answers above
(grams at the plane's radius, angles in the campaign's sense; static and couple in g mm where
every plane's radius is given), and last the answer in one sentence; --json prints one JSON
object instead (its "answer" is the same sentence).
Exit status: 0 success, 2 invalid input (file, line, key and what was expected).
)";

void print_calibration(const balancing::BalancingCampaign& c, const balancing::CampaignAnalysis& a) {
  const auto& cal = a.calibration;
  std::cout << (a.speed_rpm ? "At " + significant(*a.speed_rpm, 5) + " rpm: " : std::string()) << cal.runs
            << " readings of runs with known masses, " << c.sensors.size() << " sensors, " << c.planes.size()
            << " planes; " << cal.dof << (cal.dof == 1 ? " degree" : " degrees") << " of freedom"
            << (cal.dof == 0 ? " (as many readings as unknowns: no standard errors; another run would give them)" : "")
            << ".\nInfluence coefficients [" << c.amplitude_unit
            << " per g; as Poise counts angles: phase lag with the probe's angle added, masses against rotation]:\n";
  for (std::size_t s = 0; s < c.sensors.size(); ++s) {
    for (std::size_t p = 0; p < c.planes.size(); ++p) {
      std::cout << "  " << c.sensors[s] << " from " << c.planes[p] << ": "
                << balancing::phasor_text({cal.h[s][p].value, {}, 0.0, 0.95}, "")
                << (cal.h[s][p].se ? " (se " + significant(*cal.h[s][p].se, 2) + ")" : std::string()) << '\n';
    }
  }
  std::cout << "Planes' separation: condition number " << significant(cal.condition, 3) << " of the influence matrix"
            << (cal.condition > 100.0 ? " (the planes are hardly separable on these sensors)" : "") << ".\n";
}

void print_planes(const balancing::BalancingCampaign& c, const balancing::CampaignAnalysis& a, const std::string& title,
                  const estimators::PlaneAnswers& u) {
  std::cout << title << ":";
  for (std::size_t p = 0; p < c.planes.size(); ++p) {
    std::cout << (p ? ", " : " ") << c.planes[p] << " " << balancing::phasor_text(u.planes[p], "g");
  }
  if (u.static_unbalance) {
    std::cout << "; static " << balancing::phasor_text(*u.static_unbalance, a.moment_unit, a.moment_factor)
              << ", couple " << balancing::phasor_text(*u.couple_unbalance, a.moment_unit, a.moment_factor);
  }
  std::cout << ".\n";
}

// The rotor's own unbalance, and each run the calibration left out beside its masses if known.
void print_unbalance(const balancing::BalancingCampaign& c, const balancing::CampaignAnalysis& a) {
  print_planes(c, a, "The rotor's own unbalance as calibrated", a.initial_unbalance);
  for (const auto& r : a.runs) {
    print_planes(c, a,
                 (r.check ? "Check run '" : "Run '") + r.name + "' (" + std::to_string(r.readings) +
                     (r.readings == 1 ? " reading" : " readings") + "): unbalance relative to the calibrated rotor",
                 r.unbalance);
    if (!r.applied) continue;
    std::cout << "  applied:";
    for (std::size_t p = 0; p < c.planes.size(); ++p) {
      const auto& u = r.unbalance.planes[p];
      std::cout << (p ? ", " : " ") << c.planes[p] << " "
                << balancing::phasor_text({(*r.applied)[p], {}, 0.0, 0.95}, "g")
                << (u.radius() ? (u.contains((*r.applied)[p]) ? " (within the region)" : " (OUTSIDE the region)")
                               : std::string());
    }
    std::cout << ".\n";
  }
}

// The correction on each plane's holes and the readings it leaves.
void print_after_correction(const balancing::BalancingCampaign& c, const balancing::CampaignAnalysis& a) {
  for (std::size_t p = 0; p < c.planes.size(); ++p) {
    if (a.correction_holes[p].empty()) continue;
    std::cout << "Correction in " << c.planes[p] << " on its " << c.plane_holes[p]
              << " holes: " << balancing::holes_text(a.correction_holes[p]) << ".\n";
  }
  std::cout << "Predicted readings after correction, as the instrument will show them (phase "
            << (c.phase_lead ? "lead" : "lag") << ", 95% prediction):";
  for (std::size_t s = 0; s < c.sensors.size(); ++s) {
    std::cout << (s ? ", " : " ") << c.sensors[s] << " "
              << balancing::phasor_text(a.residual_as_read[s], c.amplitude_unit);
  }
  std::cout << ".\n";
}

void print_iso(const balancing::BalancingCampaign& c, const balancing::CampaignAnalysis& a) {
  const balancing::IsoFigures iso = balancing::iso_figures(c, a);
  for (const auto& f : iso.urr) {
    std::cout << "ISO 21940-21 URR of check run '" << f.run << "', " << f.plane << ": " << significant(100.0 * f.urr, 3)
              << "%"
              << (f.lower
                      ? " (95%: " + significant(100.0 * *f.lower, 3) + " to " + significant(100.0 * *f.upper, 3) + "%)"
                      : std::string())
              << ".\n";
  }
  for (const auto& f : iso.umar) {
    std::cout << "ISO 21940-21 U_mar, " << f.plane << " (" << f.positions << " positions): " << significant(f.umar, 3)
              << " " << f.unit
              << (f.lower ? " (95%: " + significant(*f.lower, 3) + " to " + significant(*f.upper, 3) + ")"
                          : std::string())
              << ".\n";
  }
}

void print_model_tests(const balancing::BalancingCampaign& c, const balancing::CampaignAnalysis& a) {
  if (!a.model_tests.empty()) std::cout << "Tests of the linear model (level 0.01 over the tests that ran):\n";
  for (const auto& t : a.model_tests) {
    std::cout << "  " << t.name << ": ";
    if (!t.ran) {
      std::cout << "cannot be tested on these runs; needs " << t.needs << ".\n";
      continue;
    }
    std::cout << (t.significant ? "SIGNIFICANT" : "not significant") << " (p = " << significant(*t.p_value, 2) << ")";
    if (t.significant) {
      std::cout << ": " << t.finding;
      if (t.check_before) {
        std::cout << "; check runs' readings predicted with RMS error " << significant(*t.check_before, 3) << " -> "
                  << significant(*t.check_after, 3) << " " << c.amplitude_unit;
      }
    }
    std::cout << ".\n";
  }
}

void print_speed(const balancing::BalancingCampaign& c, const balancing::CampaignAnalysis& a) {
  print_calibration(c, a);
  print_unbalance(c, a);
  print_after_correction(c, a);
  print_iso(c, a);
  print_model_tests(c, a);
}

void print_text(const balancing::BalancingCampaign& c, const balancing::CampaignAnalyses& a) {
  std::cout << "Campaign '" << c.name << "' (" << c.file << ")";
  if (a.speeds.size() > 1) std::cout << ", " << a.speeds.size() << " speeds (the balancing speed first)";
  std::cout << ".\n";
  for (const auto& s : a.speeds) print_speed(c, s);
  for (const auto& n : a.notes) std::cout << "Note: " << n << ".\n";
  for (const auto& d : a.design) std::cout << "Design study: " << d.sentence << ".\n";
  if (a.calibration) {
    std::cout << "Calibration (labelled so: fitted to these readings, not a validation): " << a.calibration->key
              << ":\n";
    for (const auto& f : a.calibration->figures) {
      std::cout << "  |h| of plane " << f.plane << " at sensor " << f.sensor << ": real " << significant(f.real, 4)
                << " +- " << significant(f.real_se, 2) << " " << f.unit << "; study mean " << significant(f.before, 4)
                << " before, " << significant(f.after, 4) << " after\n";
    }
  }
  std::cout << a.speeds.front().answer << '\n';
}

int run_balance(const std::string& path, bool as_json, const std::string& out) {
  try {
    const BalanceResult result = balance_campaign(path, out);
    const balancing::BalancingCampaign& c = result.campaign;
    const balancing::CampaignAnalyses& a = result.analyses;
    if (as_json) {
      std::cout << balancing::analysis_json(c, a).dump(2) << '\n';
    } else {
      print_text(c, a);
      if (!out.empty()) std::cout << "report: " << out << "/report.html\n";
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

BalanceResult balance_campaign(const std::string& path, const std::string& out) {
  BalanceResult r{balancing::read_balancing_campaign(path), {}};
  r.analyses = balancing::analyse_campaign(r.campaign, design_runner(0));
  if (!out.empty()) {
    try {
      balancing::write_balance_folder(out, r.campaign, r.analyses);
    } catch (const std::filesystem::filesystem_error& e) {
      throw UsageError("--out " + out + ": " + e.code().message() + " (a folder to create, or an empty one)");
    }
  }
  return r;
}

BalanceHandler add_balance_command(CLI::App& app) {
  struct Options {
    std::string campaign, out;
    bool json = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand(
      "balance", "influence coefficients, correction masses and residual from a balancing campaign's readings");
  sub->add_option("CAMPAIGN", opt->campaign, "campaign file (TOML) naming the readings file")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_flag("--json", opt->json, "print the results as one JSON object");
  sub->add_option("--out", opt->out,
                  "write DIR/balance.json (the JSON) and DIR/report.html (the answer first, the readings beside the "
                  "fitted model, before and after, the model tests)");
  sub->footer(kBalanceHelp);
  return [sub, opt]() -> std::optional<int> {
    if (!*sub) return std::nullopt;
    return run_balance(opt->campaign, opt->json, opt->out);
  };
}

}  // namespace poise::cli
