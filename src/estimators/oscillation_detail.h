#pragma once
/// Internal to oscillation_diagnosis.cc: the record's signals and checks
/// (oscillation_signals.cc) and the cogging scan (oscillation_cogging.cc); the method is in
/// oscillation_diagnosis.h.
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "estimators/oscillation_diagnosis.h"
#include "estimators/record_motion.h"

namespace poise::estimators::osc {

/// The samples the model uses (the derivative window's edges dropped).
struct Signals {
  Eigen::VectorXd y;                  ///< K_T i, N m
  Eigen::VectorXd phi, rate, acc, t;  ///< rad, rad/s (Savitzky-Golay), rad/s^2, s
  Eigen::VectorXd direction;          ///< sign of the rate, a zero rate taking the last nonzero sign
  double dt = 0.0;                    ///< the median sampling step, s
  double span_all = 0.0;              ///< rad, max - min of the angle over every row (edges included)
  std::size_t n = 0;
  std::size_t gaps = 0;                       ///< steps of more than 5 median steps (each window within a stretch)
  double gap_total = 0.0, gap_largest = 0.0;  ///< s
  std::size_t gap_largest_line = 0;           ///< file line of the row after the largest gap
};

/// Checks the record and options (messages in oscillation_diagnosis.h) and derives the signals.
Signals derive_signals(const OscillationRecord& rec, const OscillationOptions& opt);

/// The motion of the derived signals (record_motion.h); timed: the record has time stamps.
RecordMotion recognise_motion(const Signals& s, bool timed, int window);

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
OrderScan scan_orders(const Eigen::MatrixXd& model, const Eigen::VectorXd& resid, const Eigen::VectorXd& phi,
                      const OrderRange& range);

/// One scan on the samples (model's rows, y, phi): the model fitted, the orders scanned on its
/// residual (scan_orders), count: the orders examinable. An order's removed RSS (its drop) is
/// judged against the larger of the white level of the residual its pair leaves (the classic
/// F test, F(2, n - p - 2)) and the local noise level there: the median of the drops of the
/// neighbouring orders (kGuardCells resolution cells either side left out, kLocalCells cells
/// either side used; a cell is 2 pi / swing orders, the spacing of independent orders),
/// sigma^2 = median / (2 ln 2) (the median of a chi^2(2) drop is 2 ln 2 sigma^2), F = drop /
/// (2 sigma^2) then F(2, 2 K) with K the independent cells in the neighbourhood (used with at
/// least 2 cells). Where the noise is coloured (the servo's current, the friction law's misfit)
/// the local level holds it; where it is white the classic test keeps its power. Two orders are
/// judged so, with their pair in the model (the neighbours rescanned: a strong order's own
/// side lobes would raise its local level): the smallest p with the scan's own levels, moved
/// to the largest drop within a cell of it (the least-squares order of its peak: the levels of
/// neighbouring orders differ, their p do not rank the orders of one peak), and the largest
/// drop of all; test: the smaller p of the two.
inline constexpr double kGuardCells = 2.0, kLocalCells = 12.0;
struct LocalTest {
  int order = 0;
  double f = 0.0, dof = 0.0, log_p = 0.0, sigma2 = 0.0;  ///< log_p: ln p (p underflows)
  bool white = true;                                     ///< sigma2 the white level
};
struct ScanBest {
  LocalTest test;
  int count = 0;
};
/// local_cells: the neighbourhood's half-width in cells (kLocalCells for a swing; a map of many
/// real orders needs a wider one, or its own orders raise the level of each other). noise: when
/// given, the local level is taken from these noise-only drops over the same range (a record
/// whose halves each cover a turn: the halves' difference, where the real orders cancel;
/// record_map_diagnosis.cc) instead of from the scan's own drops.
ScanBest scan_best(const Eigen::MatrixXd& model, const Eigen::VectorXd& y, const Eigen::VectorXd& phi,
                   const OrderRange& range, double cell, double local_cells = kLocalCells,
                   const OrderScan* noise = nullptr);

/// The samples away from the reversals (|phi'| at least kMovingFraction of its maximum),
/// where a cogging torque cycles and the friction model's error at the reversals (another
/// friction law, presliding, the sign's smoothing) does not live: the model's rows, y, phi.
inline constexpr double kMovingFraction = 0.3;
struct Moving {
  Eigen::MatrixXd model;
  Eigen::VectorXd y, phi;
};
Moving away_from_reversals(const Signals& s, const Eigen::MatrixXd& model);

/// The round's cogging order: scan_best over the whole record and over the samples away from
/// the reversals (mv: the orders from their own swing's limit, their own cell); the smaller p
/// of the two, except that a pick at the whole record's swing limit (the lowest orders scanned,
/// min order + max(2, min order / 20), when limited by the swing) is returned as such (at_edge:
/// to be refused) and the moving samples' pick at their own limit is not taken. count: the
/// orders both scans examined (the Bonferroni family).
/// resolution: half a resolution cell of the scan that picked it, pi / swing orders (orders
/// closer than one cycle over the swing are not told apart: the estimate of a weak order, or
/// one the model's misfit reaches, moves within it).
struct CoggingPick {
  LocalTest test;
  int count = 0;
  double resolution = 0.0;
  bool on_moving = false, at_edge = false;
};
CoggingPick pick_cogging(const Signals& s, const Eigen::MatrixXd& model, const Moving& mv, const OrderRange& range);

}  // namespace poise::estimators::osc
