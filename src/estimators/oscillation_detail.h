#pragma once
/// Internal to oscillation_diagnosis.cc: the record's signals and checks
/// (oscillation_signals.cc) and the cogging scan (oscillation_cogging.cc); the method is in
/// oscillation_diagnosis.h.
#include <Eigen/Dense>
#include <string>
#include <vector>

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

/// The RSS each order's pair removes from resid (resid: residual of model, hence orthogonal
/// to its columns); NaN where the pair lies (numerically) in the model's span.
struct OrderScan {
  int first = 0, count = 0;  ///< drop[k] is order first + k; count: orders examinable
  std::vector<double> drop;
};
OrderScan scan_orders(const Eigen::MatrixXd& model, const Eigen::VectorXd& resid,
                      const Eigen::VectorXd& phi, const OrderRange& range);

/// Each order's removed RSS judged against the residual's local noise level: the median of
/// the drops of the neighbouring orders (kGuardCells resolution cells either side left out,
/// kLocalCells cells either side used; a cell is 2 pi / swing orders, the spacing of
/// independent orders), sigma^2 = median / (2 ln 2) (the median of a chi^2(2) drop is
/// 2 ln 2 sigma^2). F = drop / (2 sigma^2) is then F(2, 2 K) with K the independent cells in
/// the neighbourhood. Where fewer than 2 cells of neighbours exist, the whole residual's
/// variance (white-noise F test, dof_white) is used. The best order: the smallest p.
inline constexpr double kGuardCells = 2.0, kLocalCells = 12.0;
struct LocalTest {
  int order = 0;
  double f = 0.0, dof = 0.0, p = 1.0, sigma2 = 0.0;
};
LocalTest best_local_order(const OrderScan& scan, double cell, double white_var, double dof_white);

/// The samples away from the reversals (|phi'| at least kMovingFraction of its maximum),
/// where a cogging torque cycles and the friction model's error at the reversals (another
/// friction law, presliding, the sign's smoothing) does not live: the model's rows, y, phi.
inline constexpr double kMovingFraction = 0.3;
struct Moving {
  Eigen::MatrixXd model;
  Eigen::VectorXd y, phi;
};
Moving away_from_reversals(const Signals& s, const Eigen::MatrixXd& model);

}  // namespace poise::estimators::osc
