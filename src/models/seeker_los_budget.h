#pragma once
/// The analytic error budget of Wang et al. 2011 (docs/papers.md), recomputed term by
/// term from its inputs so that a reviewer can set it beside the printed figures and
/// beside the Monte Carlo of the exact chain (seeker_los_chain.h).
///
/// Per axis k (yaw k = 1, pitch k = 2), span L_k, T'' = 206265 arcsec/rad:
///   sigma_k1 = Delta_k1 / L_k * T''                        perpendicularity      Eqs. 1, 4
///   Delta_k6 = sqrt(Delta_k2^2 + Delta_k3^2 + Delta_k4^2 + Delta_k5^2)  run-out RSS
///   sigma_k2 = k' Delta_k6 / L_k * T'' / sqrt(3)           wobble, k' in [k_min, k_max]
///                                                          Eqs. 2, 5 (printed without T'')
///   sigma_k3 = sqrt((Dk1/(sqrt2 L_k) T'')^2 + (Dk2/(sqrt2 L_k) T'')^2)  random wobble  Eqs. 3, 6
///   delta_k  = sqrt(sigma_k1^2 + sigma_k2^2 + sigma_k3^2)
///   delta_3  = Delta_3 / L_3 * T'' / sqrt(3)               optical axis           Eq. 7
/// Propagation (paper Sec. 3, the theodolite axis-error formulas):
///   Da = sqrt((d1 tan b sin a)^2 + (d2 tan b)^2 + (d3 / cos b)^2),   Db = d1 cos a
///   Eq. 8:  D = sqrt(a^2/(a^2+b^2) Da^2 + b^2/(a^2+b^2) Db^2)      (0/0 at a = b = 0)
/// Three combinations of Da and Db over the field are reported:
///   los_eq8_*  Eq. 8 as printed;
///   los_*      sqrt(Da^2 + Db^2): the one that reproduces the printed range 10.47-17.82''
///              (least at |a| = 30, b = 0 with k_min; greatest at a = 0, |b| = 30 with k_max,
///              using the printed delta_1, delta_2), so it is what the paper computed;
///   los_gc_*   sqrt((Da cos b)^2 + Db^2): the angle between true and nominal LOS, since a
///              yaw-angle error Da moves the LOS by Da cos b on the sky.
/// Corrections found while recomputing (details in the study notes and the report):
///   * Eqs. 2 and 5 omit T''; the printed sigma_12, sigma_22 values include it.
///   * sigma_12, sigma_22 and delta_1 were computed from Delta_16 rounded to 0.0044 mm
///     (e.g. 2.556'' -> 2.56'' against 2.565'' unrounded): within 1%, flagged "close".
///   * sigma_21 = 0.004/56 T'' = 14.73'', not the printed 18.41''; delta_2 and the greatest
///     LOS figure follow (16.66'' instead of 17.82'').
///   * Eq. 8 is not what produced the printed range (see los_*), and its yaw weighting is
///     not the angle on the sky (see los_gc_*).
#include <string>
#include <vector>

namespace poise::models {

struct WangBudgetAxisInputs {
  double span = 0.0;              ///< L (m)
  double perpendicularity = 0.0;  ///< Delta_k1 (m) over the span
  double radial_runout = 0.0;     ///< Delta_k2 (m)
  double face_runout = 0.0;       ///< Delta_k3 (m)
  double clearance = 0.0;         ///< Delta_k4 (m)
  double bore_roundness = 0.0;    ///< Delta_k5 (m)
  double ball_roundness = 0.0;    ///< Delta k1 (m)
  double seat_deformation = 0.0;  ///< Delta k2 (m)
};

struct WangBudgetInputs {
  WangBudgetAxisInputs yaw, pitch;
  double k_min = 0.4, k_max = 0.96;                                 ///< load-deformation factor k'
  double optical_axis_error = 0.0;                                  ///< Delta_3 (m)
  double barrel_length = 0.0;                                       ///< L_3 (m)
  double alpha_min = 0, alpha_max = 0, beta_min = 0, beta_max = 0;  ///< rad
  std::size_t grid_points = 61;                                     ///< per axis, for min/max over the field of regard
  double pixel_ifov = 0.0;                                          ///< rad per pixel
};

/// One line of the budget. Values in `unit` (arcsec, mm or px).
struct BudgetTerm {
  std::string key;  ///< e.g. "sigma_11", matches the model file's [declared] keys
  std::string description;
  std::string equation;  ///< where it comes from in the paper
  double value = 0.0;
  std::string unit;
};

struct WangBudget {
  std::vector<BudgetTerm> terms;
  /// Grid maps (row-major alpha x beta, arcsec) of the combined figure at k_max.
  std::vector<double> alpha, beta;
  std::vector<double> eq8_map_kmax, rss_map_kmax, great_circle_map_kmax;
  const BudgetTerm& term(const std::string& key) const;  ///< throws if absent
};

/// Least and greatest of the three combinations over the field for given axis totals
/// (arcsec), e.g. the paper's printed delta_1, delta_2 to check that they reproduce its range.
struct WangGridFigures {
  double eq8_min = 0, eq8_max = 0, rss_min = 0, rss_max = 0, gc_min = 0, gc_max = 0;
};
WangGridFigures wang_grid_figures(double d1_min, double d1_max, double d2_min, double d2_max, double d3,
                                  const WangBudgetInputs& in);

/// Throws poise::Error for non-positive spans, lengths or IFOV, or k_min > k_max.
WangBudget compute_wang_budget(const WangBudgetInputs& in);

}  // namespace poise::models
