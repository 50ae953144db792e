#pragma once
/// Internal to oscillation_diagnosis.cc: the record's signals and checks
/// (oscillation_signals.cc) and the cogging scan (oscillation_cogging.cc); the method is in
/// oscillation_diagnosis.h.
#include <Eigen/Dense>
#include <string>

#include "estimators/oscillation_diagnosis.h"

namespace poise::estimators::osc {

/// The samples the model uses (the derivative window's edges dropped).
struct Signals {
  Eigen::VectorXd y;          ///< K_T i, N m
  Eigen::VectorXd phi, rate, acc, t;  ///< rad, rad/s (Savitzky-Golay), rad/s^2, s
  Eigen::VectorXd direction;  ///< sign of the rate, a zero rate taking the last nonzero sign
  double dt = 0.0;            ///< sampling step, s
  std::size_t n = 0;
};

/// Checks the record and options (messages in oscillation_diagnosis.h) and derives the signals.
Signals derive_signals(const OscillationRecord& rec, const OscillationOptions& opt);

struct Fit {
  Eigen::VectorXd beta;
  Eigen::MatrixXd cov;
  double rss = 0.0;
};

Fit least_squares(const Eigen::MatrixXd& x, const Eigen::VectorXd& y);

/// p of the nested F test adding q columns (n points, p1 columns in the larger model).
double f_test_p(double rss0, double rss1, long q, long n, long p1);

/// Smallest fraction of a candidate column's norm left after projecting out the model's
/// columns: ~0 means the candidate is (numerically) in the model's span.
double independence(const Eigen::MatrixXd& model, const Eigen::MatrixXd& cand);

/// [model cols].
Eigen::MatrixXd joined(const Eigen::MatrixXd& model, const Eigen::MatrixXd& cols);

/// sin(N phi), cos(N phi).
Eigen::MatrixXd cogging_columns(const Eigen::VectorXd& phi, int order);

/// The cogging orders scanned: from max(min option, 360 deg / swing) to the record's Nyquist
/// limit pi / (max |phi'| dt) (capped by the max option when > 0). Notes the orders the swing
/// cannot identify in out.not_identifiable.
struct OrderRange {
  int min_order = 0, max_order = -1;
  bool limited_by_swing = false;  ///< min_order above the option's minimum
};
OrderRange cogging_orders(const Signals& s, const OscillationOptions& opt, OscillationDiagnosis& out);

/// The order that removes the most residual sum of squares (resid: residual of model, hence
/// orthogonal to its columns), and how many orders were examinable.
struct OrderScan {
  int best = 0, count = 0;
};
OrderScan scan_orders(const Eigen::MatrixXd& model, const Eigen::VectorXd& resid,
                      const Eigen::VectorXd& phi, const OrderRange& range);

/// The F test p of cogging of `order` on the samples away from the reversals (|phi'| at least
/// kMovingFraction of its maximum), with the model's columns fitted on them too.
inline constexpr double kMovingFraction = 0.3;
double p_away_from_reversals(const Signals& s, const Eigen::MatrixXd& model, int order);

}  // namespace poise::estimators::osc
