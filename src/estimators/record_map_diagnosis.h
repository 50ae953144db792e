#pragma once
/// Residual diagnosis of a record whose motion is a quasi-static map or laps (record_motion.h):
/// the drive torque against angle, with every significant cogging order as a map.
///
/// Model (torque y = K_T i, or the recorded torque):
///   y = M_0 + C d + sum_N [a_N sin(N phi) + b_N cos(N phi)] (+ trend) + e
/// d = +1 forward, -1 backward (the direction of motion; in the model only where the record
/// holds both directions, each in at least 10 % of its moving rows): C is the Coulomb friction
/// torque, M_0 + C the torque forward and M_0 - C backward. Inertia (no acceleration in these
/// motions) and damping (one speed per direction cannot separate it from friction; a
/// quasi-static map has no velocity at its rows) are not fitted: they are listed as not
/// identifiable, with the motion that would show them.
/// Cogging: orders N per turn from the lowest the record completes a cycle of (1 where it
/// covers a turn) to the record's limit (half the rows per turn at the median angle step, and
/// for timed records the sampling's Nyquist limit pi / (max |phi'| dt)), added one at a time,
/// forward stepwise: each round scans every order on the current model's residual and judges
/// the best against the larger of the residual's white and local noise levels (the method of
/// oscillation_diagnosis.h, osc::scan_best), Bonferroni over the orders scanned, and adds it
/// when the adjusted p < alpha and delta BIC < 0; at most `kMaxOrders` orders. The local level
/// is the median over +-40 cells of the neighbouring orders' noise: where each half of the
/// record (in sample order) covers a turn, each order's noise is the difference of its
/// coefficients between the halves (d = Delta^T (G_A^-1 + G_B^-1)^-1 Delta, sigma^2 chi^2(2)
/// for noise alone), in which a steady cogging order cancels, so that a drive's dense spectrum
/// of real orders does not count as noise; otherwise the neighbours' own drops. Amplitude
/// T_N = hypot(a_N, b_N), phase psi_N = atan2(b_N, a_N) (the motor's torque T_N sin(N phi +
/// psi_N) balances the cogging), each with its standard error (delta method) and resolution
/// (half a cycle over the span: orders closer than one cycle over the record are not told
/// apart).
/// Trend: offset_drift (t - mean t) for a timed record that covers both directions or more
/// than two turns; a record of less than two turns in one direction cannot tell a slow drift
/// from the lowest orders (the angle is then nearly a function of time), which is said instead
/// of choosing. Offered each round beside the best order, added on the same test.
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "estimators/oscillation_diagnosis.h"
#include "estimators/record_motion.h"

namespace poise::estimators {

inline constexpr int kMaxOrders = 24;

struct MapOrder {
  int order = 0;
  double amplitude = 0.0, se_amplitude = 0.0;  ///< N m
  double phase = 0.0, se_phase = 0.0;          ///< rad
  double resolution = 0.0;                     ///< orders
  double p_value = 1.0, p_adjusted = 1.0, delta_bic = 0.0;
};

struct MapStep {
  std::string effect;  ///< "order 7", "offset_drift"
  double rmse = 0.0;   ///< N m, the residual RMS with this effect and those before it
};

struct MapDiagnosis {
  RecordMotion motion;
  std::size_t n = 0;
  OscillationParam offset;  ///< M_0, N m (with every effect found)
  bool coulomb_fitted = false;
  OscillationParam coulomb;                          ///< C, N m (half the forward - backward difference)
  OscillationParam torque_forward, torque_backward;  ///< M_0 + C, M_0 - C, N m
  std::vector<MapOrder> orders;                      ///< in the order found
  std::vector<OscillationEffect> trends;             ///< offset_drift when found
  std::vector<std::pair<std::string, std::string>> not_identifiable;  ///< (what, why)
  /// Estimates no physical axis can have (a negative friction), each said as such, not as a finding.
  std::vector<std::string> outside_physics;
  double rmse_constant = 0.0;  ///< N m, residual of the mean alone
  double rmse_base = 0.0;      ///< N m, of the base model (M_0, C)
  double rmse_after = 0.0;     ///< N m, with every effect
  std::vector<MapStep> steps;  ///< the residual after each effect added
  /// For figures: each sample's angle (rad) and its residual of the base model and of the final
  /// one (N m), in record order.
  std::vector<double> angle, residual_base, residual_after;
  double median_step = 0.0;
  std::size_t gaps = 0;
  double gap_total = 0.0, gap_largest = 0.0;
  std::size_t gap_largest_line = 0;
};

/// Diagnoses a steps or laps record (throws poise::Error as diagnose_oscillation does; also for
/// a swing, which diagnose_oscillation reads).
MapDiagnosis diagnose_map(const OscillationRecord& rec, const OscillationOptions& opt);

}  // namespace poise::estimators
