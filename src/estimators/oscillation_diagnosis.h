#pragma once
/// Residual diagnosis of a raw record of one turntable position (Yang 2015 Sec. 5.1, the
/// sixth step): time t, drive current i and gimbal angle phi while the servo drives
/// phidot = A sin(2 pi t / T). Finds effects in the oscillation that the test's model
/// lacks and reports the position's unbalance torque with and without them.
///
/// Base model (the disk rotor's phi equation at one position, supports quasi-static):
///   K_T i(t) = J phi'' + B phi' + C sign(phi') + K (phi - mean phi)
///              + G [cos(phi - mean phi) - 1 - its mean] + M_0 + e(t)
/// (K: gravity's pendulum stiffness m g e cos(theta + eps) plus any cable spring. When the
/// motion is too purely sinusoidal to separate phi'' from phi - mean phi, the phi column
/// carries both (the twice-differenced encoder would add only its quantisation noise, times
/// J: 0.17 mN*m RMS at a 14.6 deg swing, 1 kHz, 21 bits) and is reported as J = -K / omega^2,
/// "spring lumped into J". G: the curvature of gravity's pendulum torque U sin(a + delta) =
/// U sin a cos delta + U cos a sin delta over the swing, G = U sin a; kept where it can show,
/// |M_0| |column| / sigma >= 3 (a 3-sigma matched filter for the largest G the position's
/// torque allows); at a swing of a few degrees it would only trade off with cogging.)
/// phi', phi'' from a local quadratic least-squares fit over `derivative_window` samples on
/// their own time stamps (on a uniform grid, the Savitzky-Golay filter).
/// M_0 is the torque Eq. 21 is after: K_T mean(i) over whole periods equals M_0 when the
/// other terms average out.
/// Candidates, each adding columns, tested like the turntable diagnosis (nested F test,
/// Holm across the round's candidates, delta BIC < 0, forward stepwise):
///   cogging          sin(N phi), cos(N phi), N scanned as one family (Bonferroni over the
///                    scan) over the orders that complete at least one cycle over the swing,
///                    N >= 360 deg / swing (swing = max phi - min phi) and N >= min order, up
///                    to the record's Nyquist limit pi / (max |phi'| dt) (its frequency
///                    N |phi'| / 2 pi below half the sample rate; max order option when > 0).
///                    The orders are scanned twice: over the whole record and on the
///                    samples away from the reversals (|phi'| >= 30 % of its maximum, the base
///                    model refitted there, orders from their own swing's limit, a pick
///                    within max(2, 5 %) of it not taken), where a cogging torque cycles and the friction model's error
///                    at the reversals (another friction law, presliding, the sign's smoothing) does not live. Each
///                    order's removed RSS (drop) is judged against the larger of the white level of the residual its
///                    pair leaves (the classic F test) and the residual's LOCAL noise level (the servo's own current,
///                    e.g. encoder quantisation limit cycling and a sensor filter, and the friction law's misfit are
///                    coloured): sigma^2 = median of the drops of the neighbouring orders (2 to 14 resolution cells 2
///                    pi / swing either side, the window shifted inward at the scan's ends) / (2 ln 2), F = drop / (2
///                    sigma^2) ~ F(2, 2 K), K the independent cells used. Two orders per scan are judged so with their
///                    pair in the model (a strong order's own side lobes would raise its local level): the smallest p
///                    (the whitened matched filter; moved to the largest drop within a cell, the least-squares order,
///                    where its level is then the white one) and the largest drop. The smaller p of the scans,
///                    Bonferroni over all the orders both scanned; the delta BIC on the samples of the scan that found
///                    it. Among the round's candidates cogging is ranked by the p its F would
///                    have were the noise level known (chi^2(2) / 2): a level estimated from
///                    a few cells caps p, not the effect's strength.
///                    A lower order covers part of a cycle and trades off with the constant
///                    and the spring: it is reported as "not identifiable with this swing",
///                    with the swing that would test it. A fitted amplitude above
///                    2 sqrt(2) times the base residual's RMS cannot be what the residual
///                    holds (it is traded off against the base terms) and is refused as
///                    implausible. A best order within max(2, 5 %) of the swing's limit is
///                    not added either: the structure then most likely belongs to a lower
///                    order the swing cannot identify. Motor cogging or detent torque.
///   offset_drift     t - mean(t); current-sensor offset drift (amplifier warm-up)
///   coulomb_asymmetry  [direction > 0]: direction-dependent friction. The direction is the
///                    sign of the smoothed rate; where the rate is exactly zero (a quantised
///                    encoder standing still for a window) it is the last nonzero one's, so
///                    friction and asymmetry columns stay in {1, sign} and an asymmetry is
///                    not turned into a spurious column (or into cogging).
/// A candidate whose columns lie (numerically) in the span of the model is reported as not
/// identifiable, with the reason: at one position a constant friction asymmetry is the
/// unbalance torque's alias. A cable's stiffness adds to gravity's in K; only the part of K
/// that does not follow cos(theta + eps) across positions is the cable's.
#include <string>
#include <vector>

namespace poise::estimators {

struct OscillationRecord {
  std::vector<double> t;           ///< s, increasing (jitter and gaps allowed)
  std::vector<double> current;     ///< A; empty when the record gives the torque
  std::vector<double> torque;      ///< N*m, the drive torque; empty when it gives the current
  std::vector<double> phi;         ///< rad, unwrapped
  std::vector<double> velocity;    ///< rad/s where the file has it; else empty
  std::string file;                ///< for messages; "" = unnamed
  std::vector<std::size_t> lines;  ///< 1-based file line of each sample; empty = unknown
  std::vector<std::string> notes;  ///< what reading the file did (columns, units, unwraps)
  bool no_time = false;            ///< the file has no time: t is the row's order (a map)
};

struct OscillationOptions {
  double kt = 0.0;  ///< N m/A, the nominal torque constant
  double alpha = 0.05;
  int derivative_window = 9;  ///< odd number of samples
  int cogging_min_order = 20;
  int cogging_max_order = 0;  ///< highest order scanned; 0: the record's Nyquist limit
};

struct OscillationParam {
  std::string name;
  double value = 0.0, se = 0.0;
  std::string unit;
};

struct OscillationEffect {
  std::string name;  ///< cogging, offset_drift, coulomb_asymmetry
  int order = 0;     ///< cogging order N
  /// cogging: the order's resolution, half a cycle over the swing (180 deg / swing peak to
  /// peak, in orders): orders closer than one cycle over the swing are not told apart, and the
  /// estimate of a weak order, or of one the model's misfit reaches, moves within it
  double order_resolution = 0.0;
  std::vector<OscillationParam> params;
  double p_value = 1.0, p_adjusted = 1.0, delta_bic = 0.0;
  std::string causes;
};

struct OscillationDiagnosis {
  std::size_t n = 0;                          ///< samples used (the window's edges dropped)
  double torque_eq21 = 0.0;                   ///< K_T mean(i) (N m), Eq. 21
  OscillationParam torque_before;             ///< M_0 of the base model (N m)
  OscillationParam torque_after;              ///< M_0 with the effects found (N m)
  std::vector<OscillationParam> base_before;  ///< J, B, C of the base model
  std::vector<OscillationEffect> effects;
  std::vector<std::pair<std::string, std::string>> not_identifiable;  ///< (candidate, why)
  double rmse_before = 0.0, rmse_after = 0.0;                         ///< torque residual (N m)
  int rounds = 0;
  double median_step = 0.0;                   ///< s, of the time stamps as they are
  std::size_t gaps = 0;                       ///< steps of more than 5 median steps
  double gap_total = 0.0, gap_largest = 0.0;  ///< s
  std::size_t gap_largest_line = 0;           ///< file line of the row after the largest gap
  /// For figures: each sample's angle (rad) and its residual of the base model and of the final
  /// one (N m), in record order.
  std::vector<double> angle, residual_base, residual_after;
};

/// Time stamps are used as they are (jitter; gaps of more than 5 median steps split the
/// record into stretches, each derived on its own). Throws poise::Error for fewer than 8
/// windows of samples, unequal sizes, a time stamp that repeats or goes back (naming the file
/// and line), a non-positive or non-finite K_T, torques that overflow, an
/// even window, or a record with no motion.
OscillationDiagnosis diagnose_oscillation(const OscillationRecord& rec, const OscillationOptions& opt);

}  // namespace poise::estimators
