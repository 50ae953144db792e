// The comparison of `poise error-mechanisms`: fits, cross-validation, likelihood-ratio tests
// and predictive checks of the per-test error mechanisms (reading the tables and printing are
// in error_mechanisms_command.cc).
#include "cli/error_mechanisms_command.h"

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

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

// (4) The printed error rows, against measured - load of their own row.
json printed_error_checks(const UnbalanceTestData& data) {
  json checks = json::array();
  for (const auto& m : data.mismatches) {
    checks.push_back({{"table", m.table},
                      {"test", m.number},
                      {"column", m.column},
                      {"printed", m.printed},
                      {"recomputed", m.recomputed},
                      {"note", "the printed error differs from measured - load of its own row"}});
  }
  return checks;
}

// (4) The RMSE per table, recomputed from measured - load, beside the printed one.
json rmse_recomputed(const UnbalanceTestData& data, const std::vector<std::string>& tables) {
  json rmse = json::array();
  for (const auto& name : tables) {
    double st = 0, sa = 0;
    const auto rows = of_table(data.tests, name, true);
    for (const auto& t : rows) {
      st += std::pow(t.torque - t.load_torque, 2);
      sa += std::pow(std::remainder(t.angle - t.load_angle, 2 * 3.141592653589793), 2);
    }
    json r{{"table", name},
           {"rmse_torque_mNm", 1e3 * std::sqrt(st / static_cast<double>(rows.size()))},
           {"rmse_angle_deg", std::sqrt(sa / static_cast<double>(rows.size())) / kDeg}};
    for (const auto& p : data.printed_rmse) {
      if (p.table == name) {
        r["rmse_torque_from_printed_errors_mNm"] = p.torque_mNm;
        r["rmse_angle_from_printed_errors_deg"] = p.angle_deg;
      }
    }
    rmse.push_back(r);
  }
  return rmse;
}

// (1) Calibrated on one table, validated on the others: the rows and each mechanism's
// validation log-likelihood summed over the calibration tables.
struct CrossValidation {
  json rows = json::array();
  std::map<std::string, double> held_out_total;
};

CrossValidation calibrate_on_one(const UnbalanceTestData& data, const std::vector<std::string>& tables,
                                 double position_noise, const std::string& calibrate) {
  CrossValidation r;
  json& cv = r.rows;
  std::map<std::string, double>& held_out_total = r.held_out_total;
  for (const auto& cal : tables) {
    const auto on = of_table(data.tests, cal, true);
    json row{{"calibration_table", cal}, {"mechanisms", json::array()}};
    for (ErrorMechanism m : kCandidates) {
      const MechanismSigmas s = estimators::fit_mechanism(on, m, position_noise);
      json mj{{"mechanism", estimators::to_string(m)},
              {"parameters", sigmas_json(m, s)},
              {"calibration_target",
               {{"table", cal}, {"log_likelihood", estimators::mechanism_log_likelihood(on, s, position_noise)}}},
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
  return r;
}

// (2) Each mechanism fitted on all tables: its sigmas, log-likelihood and AIC.
struct JointFits {
  json rows = json::array();
  std::map<ErrorMechanism, double> log_likelihood;
  std::map<ErrorMechanism, MechanismSigmas> sigmas;
};

JointFits joint_fits(const UnbalanceTestData& data, double position_noise) {
  JointFits r;
  json& joint = r.rows;
  std::map<ErrorMechanism, double>& ll_joint = r.log_likelihood;
  std::map<ErrorMechanism, MechanismSigmas>& fitted = r.sigmas;
  double best_aic = INFINITY;
  for (ErrorMechanism m : {ErrorMechanism::kScaleAndZero, ErrorMechanism::kAdditive,
                           ErrorMechanism::kAdditiveAlongAcross, ErrorMechanism::kScaleZeroAndAdditive}) {
    fitted[m] = estimators::fit_mechanism(data.tests, m, position_noise);
    ll_joint[m] = estimators::mechanism_log_likelihood(data.tests, fitted[m], position_noise);
    const double aic = 2.0 * estimators::parameter_count(m) - 2.0 * ll_joint[m];
    best_aic = std::min(best_aic, aic);
    joint.push_back({{"mechanism", estimators::to_string(m)},
                     {"parameters", sigmas_json(m, fitted[m])},
                     {"free_sigmas", estimators::parameter_count(m)},
                     {"log_likelihood", ll_joint[m]},
                     {"aic", aic}});
  }
  for (auto& j : joint) j["delta_aic"] = j["aic"].get<double>() - best_aic;
  return r;
}

// (2) Likelihood-ratio tests between the joint fits.
json likelihood_ratio_tests(const JointFits& fits) {
  const std::map<ErrorMechanism, double>& ll_joint = fits.log_likelihood;
  const double lr_add =
      2.0 * (ll_joint.at(ErrorMechanism::kScaleZeroAndAdditive) - ll_joint.at(ErrorMechanism::kScaleAndZero));
  const double lr_sz =
      2.0 * (ll_joint.at(ErrorMechanism::kScaleZeroAndAdditive) - ll_joint.at(ErrorMechanism::kAdditive));
  return {{{"question", "is the additive error needed beside scale and zero?"},
           {"null", "scale_and_zero"},
           {"alternative", "scale_zero_and_additive"},
           {"statistic", lr_add},
           {"p_value", chibar_p(lr_add, 1)}},
          {{"question", "are the scale and zero errors needed beside the additive one?"},
           {"null", "additive"},
           {"alternative", "scale_zero_and_additive"},
           {"statistic", lr_sz},
           {"p_value", chibar_p(lr_sz, 2)}}};
}

// (3) Predictive checks under the joint fits, per mechanism and table.
json predictive_checks(const UnbalanceTestData& data, const std::vector<std::string>& tables,
                       const std::map<ErrorMechanism, MechanismSigmas>& fitted, double position_noise, int draws) {
  json pc = json::array();
  for (ErrorMechanism m : kCandidates) {
    for (const auto& name : tables) {
      const auto rows = of_table(data.tests, name, true);
      const auto c = estimators::predictive_check(rows, fitted.at(m), position_noise, draws, 2015);
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
  return pc;
}

// Which mechanism the data support: the best validation log-likelihood (held-out tables).
std::string supported_mechanism(const std::map<std::string, double>& held_out_total) {
  std::string best;
  double best_ll = -std::numeric_limits<double>::infinity();
  for (const auto& [name, ll] : held_out_total) {
    if (ll > best_ll) {
      best_ll = ll;
      best = name;
    }
  }
  return best;
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
  out["printed_error_checks"] = printed_error_checks(data);
  out["rmse_recomputed"] = rmse_recomputed(data, tables);
  // (1) Calibrate on one table, validate on the others: every choice of table.
  const CrossValidation cv = calibrate_on_one(data, tables, position_noise, calibrate);
  out["calibrate_on_one_validate_on_others"] = cv.rows;
  out["validation_log_likelihood_summed_over_calibration_tables"] = cv.held_out_total;
  // (2) Joint fits on all tables, AIC and likelihood-ratio tests.
  const JointFits fits = joint_fits(data, position_noise);
  out["joint_fit_all_tables"] = fits.rows;
  out["likelihood_ratio_tests"] = likelihood_ratio_tests(fits);
  // (3) Predictive checks under the joint fits.
  out["predictive_checks"] = predictive_checks(data, tables, fits.sigmas, position_noise, draws);
  out["predictive_draws"] = draws;
  out["supported"] = supported_mechanism(cv.held_out_total);
  return out;
}

}  // namespace poise::cli
