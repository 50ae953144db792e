#include "cli/error_mechanisms_command.h"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <set>

#include "core/error.h"
#include "core/format.h"
#include "estimators/sine_fit.h"
#include "estimators/torque_table.h"

namespace poise::cli {
namespace {

using nlohmann::json;

const char* kHelp = R"(What it does:
  Asks measured static-unbalance tests (a known load L at angle a, measured as MT_s and b)
  which per-test error mechanism they support, by likelihood:
    scale_and_zero         K_T scale error k and gimbal-zero error z drawn for each test:
                           MT_s ~ L (1 + k), b ~ a + z (the calibrated kt_drift and gimbal_zero
                           of models/gimbal_simulator_yang2015.toml);
    additive               a 2D random vector d ~ N(0, s_d^2 I) added to the unbalance in each
                           test (any direction, the same size at every load);
    additive_along_across  the same with its own sigmas along and across the unbalance.
  Each test's error vector in the load's frame, r = MT_s cos(b - a) - L, t = MT_s sin(b - a),
  is normal under each candidate, plus the fit's own noise 2 sigma_p^2 / n per component
  (sigma_p: the residual standard deviation of Table 1's 36-point fit, n: the test's
  positions). Details: src/estimators/error_mechanism_likelihood.h.

  ln L is the natural log of the density of (r, t) in N*m: its value depends on that unit,
  differences between mechanisms (the evidence) do not.
  Reported: (1) each mechanism calibrated (maximum likelihood) on one table, its
  log-likelihood there (a calibration target, not evidence) and on each other table
  (validation), for every choice of calibration table; (2) joint fits on all tables with
  AIC = 2 k - 2 ln L and likelihood-ratio tests inside the model that has both mechanisms
  (chi-bar-square p-values, the sigmas being on their boundary 0 under the null);
  (3) predictive checks: how often the fitted mechanism makes |dMT| and |db| fall with the
  load as steeply as the data (Spearman), and dMT and db correlate as strongly (Pearson);
  (4) the printed error rows checked against their own measured and load columns.

Data (the folder holds the files of data/yang2015/, see its README.md):
  tables2_3_loading_tests.csv   Tables 2 (C_A) and 3 (C_B), 36 points
  tables4_5_repeatability.csv   Tables 4 (36 points) and 5 (18 points)
  table1_loading_test_36pt.csv  Table 1, for the per-position noise sigma_p

Example:
  poise error-mechanisms data/yang2015
  poise error-mechanisms data/yang2015 --calibrate "Table 2" --json

Exit status: 0 success, 2 invalid input (the message names the file, line and column).
)";

void print_text(const json& r, std::ostream& o) {
  o << fmt::format(
      "Per-test error mechanisms against {} measured tests (per-position noise {:.3f} mN*m from Table 1)\n\n",
      r["tests"].get<std::size_t>(), r["position_noise_mNm"].get<double>());
  o << "Printed error rows checked against measured - load:\n";
  if (r["printed_error_checks"].empty()) o << "  all agree within the rounding\n";
  for (const auto& c : r["printed_error_checks"]) {
    o << fmt::format("  {} test {}: {} printed {:+.2f}, its own row gives {:+.2f} (FLAGGED, kept as printed)\n",
                     c["table"].get<std::string>(), c["test"].get<int>(), c["column"].get<std::string>(),
                     c["printed"].get<double>(), c["recomputed"].get<double>());
  }
  for (const auto& t : r["rmse_recomputed"]) {
    o << fmt::format("  {}: RMSE_MT {:.2f} mN*m, RMSE_b {:.2f} deg from measured - load", t["table"].get<std::string>(),
                     t["rmse_torque_mNm"].get<double>(), t["rmse_angle_deg"].get<double>());
    if (t.contains("rmse_angle_from_printed_errors_deg")) {
      o << fmt::format(" ({:.2f} mN*m, {:.2f} deg from the printed error rows)",
                       t["rmse_torque_from_printed_errors_mNm"].get<double>(),
                       t["rmse_angle_from_printed_errors_deg"].get<double>());
    }
    o << "\n";
  }
  auto params = [](const json& p) {
    std::string s;
    for (const auto& [k, v] : p.items())
      s += (s.empty() ? "" : ", ") + k + " " + std::to_string(v.get<double>()).substr(0, 6);
    return s;
  };
  o << "\nCalibrated on one table (calibration_target: its own log-likelihood is no evidence),\nvalidated on the "
       "others (ln L, higher is better):\n";
  for (const auto& row : r["calibrate_on_one_validate_on_others"]) {
    o << "  calibrated on " << row["calibration_table"].get<std::string>() << ":\n";
    for (const auto& m : row["mechanisms"]) {
      o << fmt::format("    {:<22} ln L calibration_target {:>7.2f}; validation", m["mechanism"].get<std::string>(),
                       m["calibration_target"]["log_likelihood"].get<double>());
      for (const auto& v : m["validation"]) {
        o << fmt::format(" {} {:.1f}", v["table"].get<std::string>(), v["log_likelihood"].get<double>());
      }
      o << fmt::format("; sum {:.1f}\n      ({})\n", m["validation_log_likelihood"].get<double>(),
                       params(m["parameters"]));
    }
  }
  o << "  validation ln L summed over the choices of calibration table:";
  for (const auto& [k, v] : r["validation_log_likelihood_summed_over_calibration_tables"].items()) {
    o << fmt::format(" {} {:.1f};", k, v.get<double>());
  }
  o << "\n\nJoint fits on all tables:\n";
  for (const auto& j : r["joint_fit_all_tables"]) {
    o << fmt::format("  {:<24} k={}  ln L {:>8.2f}  AIC {:>8.2f}  dAIC {:>7.2f}  ({})\n",
                     j["mechanism"].get<std::string>(), j["free_sigmas"].get<int>(), j["log_likelihood"].get<double>(),
                     j["aic"].get<double>(), j["delta_aic"].get<double>(), params(j["parameters"]));
  }
  for (const auto& t : r["likelihood_ratio_tests"]) {
    o << fmt::format("  {} LR = {:.2f}, p = {:.3g}\n", t["question"].get<std::string>(), t["statistic"].get<double>(),
                     t["p_value"].get<double>());
  }
  o << "\nPredictive checks (share of " << r["predictive_draws"].get<int>()
    << " simulated copies under the joint fit as extreme as the data):\n";
  for (const auto& c : r["predictive_checks"]) {
    o << fmt::format("  {:<22} {}:", c["mechanism"].get<std::string>(), c["table"].get<std::string>());
    if (c.contains("spearman_abs_torque_error_vs_load")) {
      o << fmt::format(" |dMT| vs load rho_s {:+.2f} (share {:.4f}), |db| vs load {:+.2f} (share {:.4f});",
                       c["spearman_abs_torque_error_vs_load"].get<double>(), c["share_as_falling_torque"].get<double>(),
                       c["spearman_abs_angle_error_vs_load"].get<double>(), c["share_as_falling_angle"].get<double>());
    }
    o << fmt::format(" dMT-db r {:+.2f} (share {:.4f})\n", c["pearson_torque_vs_angle_error"].get<double>(),
                     c["share_as_correlated"].get<double>());
  }
  o << "\nSupported (best validation log-likelihood): " << r["supported"].get<std::string>() << "\n";
}

}  // namespace

json compare_error_mechanisms_in(const std::string& dir, const std::string& calibrate, int draws) {
  namespace fs = std::filesystem;
  UnbalanceTestData data;
  read_unbalance_tests((fs::path(dir) / "tables2_3_loading_tests.csv").string(), data);
  read_unbalance_tests((fs::path(dir) / "tables4_5_repeatability.csv").string(), data);
  const auto t1 = estimators::read_torque_table((fs::path(dir) / "table1_loading_test_36pt.csv").string());
  const auto fit = estimators::fit_sine(t1.theta_rad, t1.torque_Nm);
  std::set<std::string> names;
  for (const auto& t : data.tests) names.insert(t.table);
  if (!calibrate.empty() && !names.count(calibrate)) {
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    throw UsageError("--calibrate \"" + calibrate + "\": no such table (expected one of " + list + ")");
  }
  return compare_error_mechanisms(data, fit.sigma, calibrate, draws);
}

ErrorMechanismsHandler add_error_mechanisms_command(CLI::App& app) {
  struct Options {
    std::string dir = "data/yang2015", calibrate;
    int draws = 20000;
    bool json = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand(
      "error-mechanisms", "which per-test error (K_T scale and zero, or additive) measured unbalance tests support");
  sub->add_option("DIR", opt->dir, "folder with the measured tables (default data/yang2015)");
  sub->add_option("--calibrate", opt->calibrate,
                  "list this calibration table first, e.g. \"Table 4\" (default: all in file order)");
  sub->add_option("--draws", opt->draws, "simulated copies per predictive check (default 20000)")
      ->check(CLI::Range(100, 10000000));
  sub->add_flag("--json", opt->json, "print the comparison as one JSON object");
  sub->footer(kHelp);
  return [sub, opt]() -> std::optional<int> {
    if (!*sub) return std::nullopt;
    try {
      const json r = compare_error_mechanisms_in(opt->dir, opt->calibrate, opt->draws);
      if (opt->json) std::cout << r.dump(2) << '\n';
      else print_text(r, std::cout);
    } catch (const UsageError&) {
      throw;
    } catch (const Error& e) {
      std::cerr << "poise: " << e.what() << "\nNothing was compared.\n";
      return 2;
    }
    return 0;
  };
}

}  // namespace poise::cli
