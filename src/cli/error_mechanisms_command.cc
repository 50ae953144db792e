#include "cli/error_mechanisms_command.h"

#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <set>

#include "core/error.h"
#include "estimators/sine_fit.h"
#include "estimators/torque_table.h"

namespace poise::cli {
namespace {

using estimators::ErrorMechanism;
using estimators::MechanismSigmas;
using estimators::UnbalanceTestRecord;
using nlohmann::json;

constexpr double kDeg = 3.141592653589793 / 180.0;
// NdFeB: remanence, so K_T, falls by about 0.12% per kelvin (sintered grades 0.09-0.13 %/K).
constexpr double kNdFeBPerKelvin = 0.0012;

const ErrorMechanism kCandidates[] = {ErrorMechanism::kScaleAndZero, ErrorMechanism::kAdditive,
                                      ErrorMechanism::kAdditiveAlongAcross};

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

json sigmas_json(ErrorMechanism m, const MechanismSigmas& s) {
  json j = json::object();
  if (m == ErrorMechanism::kScaleAndZero || m == ErrorMechanism::kScaleZeroAndAdditive) {
    j["kt_scale_pct"] = 100.0 * s.scale;
    j["gimbal_zero_deg"] = s.zero / kDeg;
    j["magnet_temperature_swing_K"] = s.scale / kNdFeBPerKelvin;
  }
  if (m == ErrorMechanism::kAdditive || m == ErrorMechanism::kScaleZeroAndAdditive) {
    j["additive_mNm"] = 1e3 * s.along;
  }
  if (m == ErrorMechanism::kAdditiveAlongAcross) {
    j["additive_along_mNm"] = 1e3 * s.along;
    j["additive_across_mNm"] = 1e3 * s.across;
  }
  return j;
}

std::vector<UnbalanceTestRecord> of_table(const std::vector<UnbalanceTestRecord>& all, const std::string& table,
                                          bool keep) {
  std::vector<UnbalanceTestRecord> out;
  for (const auto& t : all) {
    if ((t.table == table) == keep) out.push_back(t);
  }
  return out;
}

// P(chi-bar-square > x) for `extra` variance components on their boundary: a 50:50 mixture
// of chi2(extra - 1) and chi2(extra) (Self and Liang 1987; exact for one component, the usual
// approximation for two).
double chibar_p(double x, int extra) {
  if (x <= 0) return 1.0;
  using boost::math::chi_squared;
  const double upper = boost::math::cdf(boost::math::complement(chi_squared(extra), x));
  const double lower = extra > 1 ? boost::math::cdf(boost::math::complement(chi_squared(extra - 1), x)) : 0.0;
  return 0.5 * upper + 0.5 * lower;
}

}  // namespace

json compare_error_mechanisms(const UnbalanceTestData& data, double position_noise, const std::string& calibrate,
                              int draws) {
  std::vector<std::string> tables;
  for (const auto& t : data.tests) {
    if (std::find(tables.begin(), tables.end(), t.table) == tables.end()) tables.push_back(t.table);
  }
  json out;
  out["position_noise_mNm"] = 1e3 * position_noise;
  out["tests"] = data.tests.size();
  // (4) The printed error rows and the RMSE per table, recomputed from measured - load.
  json checks = json::array();
  for (const auto& m : data.mismatches) {
    checks.push_back({{"table", m.table}, {"test", m.number}, {"column", m.column}, {"printed", m.printed},
                      {"recomputed", m.recomputed},
                      {"note", "the printed error differs from measured - load of its own row"}});
  }
  out["printed_error_checks"] = checks;
  json rmse = json::array();
  for (const auto& name : tables) {
    double st = 0, sa = 0;
    const auto rows = of_table(data.tests, name, true);
    for (const auto& t : rows) {
      st += std::pow(t.torque - t.load_torque, 2);
      sa += std::pow(std::remainder(t.angle - t.load_angle, 2 * 3.141592653589793), 2);
    }
    json r{{"table", name}, {"rmse_torque_mNm", 1e3 * std::sqrt(st / static_cast<double>(rows.size()))},
           {"rmse_angle_deg", std::sqrt(sa / static_cast<double>(rows.size())) / kDeg}};
    for (const auto& p : data.printed_rmse) {
      if (p.table == name) {
        r["rmse_torque_from_printed_errors_mNm"] = p.torque_mNm;
        r["rmse_angle_from_printed_errors_deg"] = p.angle_deg;
      }
    }
    rmse.push_back(r);
  }
  out["rmse_recomputed"] = rmse;
  // (1) Calibrate on one table, validate on the others: every choice of table.
  json cv = json::array();
  std::map<std::string, double> held_out_total;
  for (const auto& cal : tables) {
    const auto on = of_table(data.tests, cal, true);
    json row{{"calibration_table", cal}, {"mechanisms", json::array()}};
    for (ErrorMechanism m : kCandidates) {
      const MechanismSigmas s = estimators::fit_mechanism(on, m, position_noise);
      json mj{{"mechanism", estimators::to_string(m)}, {"parameters", sigmas_json(m, s)},
              {"calibration_target", {{"table", cal}, {"log_likelihood", estimators::mechanism_log_likelihood(on, s, position_noise)}}},
              {"validation", json::array()}};
      double total = 0;
      for (const auto& other : tables) {
        if (other == cal) continue;
        const double ll = estimators::mechanism_log_likelihood(of_table(data.tests, other, true), s, position_noise);
        mj["validation"].push_back({{"table", other}, {"log_likelihood", ll}});
        total += ll;
      }
      mj["validation_log_likelihood"] = total;
      held_out_total[estimators::to_string(m)] += total;
      row["mechanisms"].push_back(mj);
    }
    if (cal == calibrate) cv.insert(cv.begin(), row);
    else cv.push_back(row);
  }
  out["calibrate_on_one_validate_on_others"] = cv;
  out["validation_log_likelihood_summed_over_calibration_tables"] = held_out_total;
  // (2) Joint fits on all tables, AIC and likelihood-ratio tests.
  json joint = json::array();
  std::map<ErrorMechanism, double> ll_joint;
  std::map<ErrorMechanism, MechanismSigmas> fitted;
  double best_aic = INFINITY;
  for (ErrorMechanism m : {ErrorMechanism::kScaleAndZero, ErrorMechanism::kAdditive, ErrorMechanism::kAdditiveAlongAcross,
                           ErrorMechanism::kScaleZeroAndAdditive}) {
    fitted[m] = estimators::fit_mechanism(data.tests, m, position_noise);
    ll_joint[m] = estimators::mechanism_log_likelihood(data.tests, fitted[m], position_noise);
    const double aic = 2.0 * estimators::parameter_count(m) - 2.0 * ll_joint[m];
    best_aic = std::min(best_aic, aic);
    joint.push_back({{"mechanism", estimators::to_string(m)}, {"parameters", sigmas_json(m, fitted[m])},
                     {"free_sigmas", estimators::parameter_count(m)}, {"log_likelihood", ll_joint[m]}, {"aic", aic}});
  }
  for (auto& j : joint) j["delta_aic"] = j["aic"].get<double>() - best_aic;
  out["joint_fit_all_tables"] = joint;
  const double lr_add = 2.0 * (ll_joint[ErrorMechanism::kScaleZeroAndAdditive] - ll_joint[ErrorMechanism::kScaleAndZero]);
  const double lr_sz = 2.0 * (ll_joint[ErrorMechanism::kScaleZeroAndAdditive] - ll_joint[ErrorMechanism::kAdditive]);
  out["likelihood_ratio_tests"] = {
      {{"question", "is the additive error needed beside scale and zero?"}, {"null", "scale_and_zero"},
       {"alternative", "scale_zero_and_additive"}, {"statistic", lr_add}, {"p_value", chibar_p(lr_add, 1)}},
      {{"question", "are the scale and zero errors needed beside the additive one?"}, {"null", "additive"},
       {"alternative", "scale_zero_and_additive"}, {"statistic", lr_sz}, {"p_value", chibar_p(lr_sz, 2)}}};
  // (3) Predictive checks under the joint fits.
  json pc = json::array();
  for (ErrorMechanism m : kCandidates) {
    for (const auto& name : tables) {
      const auto rows = of_table(data.tests, name, true);
      const auto c = estimators::predictive_check(rows, fitted[m], position_noise, draws, 2015);
      json j{{"mechanism", estimators::to_string(m)}, {"table", name}};
      bool one_load = true;
      for (const auto& t : rows) one_load = one_load && std::abs(t.load_torque - rows.front().load_torque) < 1e-12;
      if (!one_load) {
        j["spearman_abs_torque_error_vs_load"] = c.spearman_torque;
        j["share_as_falling_torque"] = c.p_spearman_torque;
        j["spearman_abs_angle_error_vs_load"] = c.spearman_angle;
        j["share_as_falling_angle"] = c.p_spearman_angle;
      }
      j["pearson_torque_vs_angle_error"] = c.pearson_torque_angle;
      j["share_as_correlated"] = c.p_pearson;
      pc.push_back(j);
    }
  }
  out["predictive_checks"] = pc;
  out["predictive_draws"] = draws;
  // Which mechanism the data support: the best validation log-likelihood (held-out tables).
  std::string best;
  double best_ll = -INFINITY;
  for (const auto& [name, ll] : held_out_total) {
    if (ll > best_ll) {
      best_ll = ll;
      best = name;
    }
  }
  out["supported"] = best;
  return out;
}

namespace {

void print_text(const json& r, std::ostream& o) {
  char b[400];
  std::snprintf(b, sizeof b, "Per-test error mechanisms against %zu measured tests (per-position noise %.3f mN*m from Table 1)\n\n",
                r["tests"].get<std::size_t>(), r["position_noise_mNm"].get<double>());
  o << b;
  o << "Printed error rows checked against measured - load:\n";
  if (r["printed_error_checks"].empty()) o << "  all agree within the rounding\n";
  for (const auto& c : r["printed_error_checks"]) {
    std::snprintf(b, sizeof b, "  %s test %d: %s printed %+.2f, its own row gives %+.2f (FLAGGED, kept as printed)\n",
                  c["table"].get<std::string>().c_str(), c["test"].get<int>(), c["column"].get<std::string>().c_str(),
                  c["printed"].get<double>(), c["recomputed"].get<double>());
    o << b;
  }
  for (const auto& t : r["rmse_recomputed"]) {
    std::snprintf(b, sizeof b, "  %s: RMSE_MT %.2f mN*m, RMSE_b %.2f deg from measured - load", t["table"].get<std::string>().c_str(),
                  t["rmse_torque_mNm"].get<double>(), t["rmse_angle_deg"].get<double>());
    o << b;
    if (t.contains("rmse_angle_from_printed_errors_deg")) {
      std::snprintf(b, sizeof b, " (%.2f mN*m, %.2f deg from the printed error rows)", t["rmse_torque_from_printed_errors_mNm"].get<double>(),
                    t["rmse_angle_from_printed_errors_deg"].get<double>());
      o << b;
    }
    o << "\n";
  }
  auto params = [](const json& p) {
    std::string s;
    for (const auto& [k, v] : p.items()) s += (s.empty() ? "" : ", ") + k + " " + std::to_string(v.get<double>()).substr(0, 6);
    return s;
  };
  o << "\nCalibrated on one table (calibration_target: its own log-likelihood is no evidence),\nvalidated on the others (ln L, higher is better):\n";
  for (const auto& row : r["calibrate_on_one_validate_on_others"]) {
    o << "  calibrated on " << row["calibration_table"].get<std::string>() << ":\n";
    for (const auto& m : row["mechanisms"]) {
      std::snprintf(b, sizeof b, "    %-22s ln L calibration_target %7.2f; validation", m["mechanism"].get<std::string>().c_str(),
                    m["calibration_target"]["log_likelihood"].get<double>());
      o << b;
      for (const auto& v : m["validation"]) {
        std::snprintf(b, sizeof b, " %s %.1f", v["table"].get<std::string>().c_str(), v["log_likelihood"].get<double>());
        o << b;
      }
      std::snprintf(b, sizeof b, "; sum %.1f\n      (%s)\n", m["validation_log_likelihood"].get<double>(), params(m["parameters"]).c_str());
      o << b;
    }
  }
  o << "  validation ln L summed over the choices of calibration table:";
  for (const auto& [k, v] : r["validation_log_likelihood_summed_over_calibration_tables"].items()) {
    std::snprintf(b, sizeof b, " %s %.1f;", k.c_str(), v.get<double>());
    o << b;
  }
  o << "\n\nJoint fits on all tables:\n";
  for (const auto& j : r["joint_fit_all_tables"]) {
    std::snprintf(b, sizeof b, "  %-24s k=%d  ln L %8.2f  AIC %8.2f  dAIC %7.2f  (%s)\n", j["mechanism"].get<std::string>().c_str(),
                  j["free_sigmas"].get<int>(), j["log_likelihood"].get<double>(), j["aic"].get<double>(),
                  j["delta_aic"].get<double>(), params(j["parameters"]).c_str());
    o << b;
  }
  for (const auto& t : r["likelihood_ratio_tests"]) {
    std::snprintf(b, sizeof b, "  %s LR = %.2f, p = %.3g\n", t["question"].get<std::string>().c_str(),
                  t["statistic"].get<double>(), t["p_value"].get<double>());
    o << b;
  }
  o << "\nPredictive checks (share of " << r["predictive_draws"].get<int>()
    << " simulated copies under the joint fit as extreme as the data):\n";
  for (const auto& c : r["predictive_checks"]) {
    std::snprintf(b, sizeof b, "  %-22s %s:", c["mechanism"].get<std::string>().c_str(), c["table"].get<std::string>().c_str());
    o << b;
    if (c.contains("spearman_abs_torque_error_vs_load")) {
      std::snprintf(b, sizeof b, " |dMT| vs load rho_s %+.2f (share %.4f), |db| vs load %+.2f (share %.4f);",
                    c["spearman_abs_torque_error_vs_load"].get<double>(), c["share_as_falling_torque"].get<double>(),
                    c["spearman_abs_angle_error_vs_load"].get<double>(), c["share_as_falling_angle"].get<double>());
      o << b;
    }
    std::snprintf(b, sizeof b, " dMT-db r %+.2f (share %.4f)\n", c["pearson_torque_vs_angle_error"].get<double>(),
                  c["share_as_correlated"].get<double>());
    o << b;
  }
  o << "\nSupported (best validation log-likelihood): " << r["supported"].get<std::string>() << "\n";
}

}  // namespace

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
  sub->add_option("--calibrate", opt->calibrate, "list this calibration table first, e.g. \"Table 4\" (default: all in file order)");
  sub->add_option("--draws", opt->draws, "simulated copies per predictive check (default 20000)")->check(CLI::Range(100, 10000000));
  sub->add_flag("--json", opt->json, "print the comparison as one JSON object");
  sub->footer(kHelp);
  return [sub, opt]() -> std::optional<int> {
    if (!*sub) return std::nullopt;
    namespace fs = std::filesystem;
    try {
      UnbalanceTestData data;
      read_unbalance_tests((fs::path(opt->dir) / "tables2_3_loading_tests.csv").string(), data);
      read_unbalance_tests((fs::path(opt->dir) / "tables4_5_repeatability.csv").string(), data);
      const auto t1 = estimators::read_torque_table((fs::path(opt->dir) / "table1_loading_test_36pt.csv").string());
      const auto fit = estimators::fit_sine(t1.theta_rad, t1.torque_Nm);
      std::set<std::string> names;
      for (const auto& t : data.tests) names.insert(t.table);
      if (!opt->calibrate.empty() && !names.count(opt->calibrate)) {
        std::string list;
        for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
        throw UsageError("--calibrate \"" + opt->calibrate + "\": no such table (expected one of " + list + ")");
      }
      const json r = compare_error_mechanisms(data, fit.sigma, opt->calibrate, opt->draws);
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
