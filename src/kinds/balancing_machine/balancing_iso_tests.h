#pragma once
/// ISO 21940-21 style machine tests of the balancing-machine study, beside the paper's:
///
///   * URR as ISO 21940-21 computes it: the machine's INDICATION of known test unbalances,
///     without a physical correction. Rotor R is measured bare (A_0), then with a test mass in
///     each correction plane (T_1 at 0 deg, T_2 at 90 deg: what the operator knows, the nominal
///     mass at the nominal radius and hole); the indicated test unbalance is the difference of
///     the two indications, D_p = I_p(with) - I_p(bare), and
///       URR_iso,p = 1 - |D_p - T_p| / |T_p|.
///     Placement errors of the test masses (hole radius and angle, mass) are in; correction
///     masses are not involved. Poise's other figure (urr outputs without "iso"), 1 - |after| /
///     |before| after a physical correction with its placement tolerances, also charges the
///     correction masses' placement to the machine.
///   * The two-plane U_mar test: test masses in BOTH correction planes at once (mass m at
///     radius r, plane 2's at plane_2_offset from plane 1's), moved together through K evenly
///     spaced positions; in each position each plane's indicated amount X_p,k (at radius r).
///     A machine that adds nothing reads |R_p + T e^{i phi_k}|: the rotor's residual R_p turns
///     the readings around their mean by up to |R_p|. Per plane: the mean, the largest
///     deviation from it, U_mar,p = (X_max - X_min) r / 2 (Wang's Eq. 18 reading), and the
///     pass criterion as we read the standard: every reading within mean +- claimed U_mar / r.
///     Loading both planes together exercises the plane separation, which the paper's
///     one-plane-at-a-time test (type "umar") does not. Read from the standard's description of
///     the test; its text was not available to quote: the criterion is stated here, not cited.
#include <complex>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "models/spring_plate_machine.h"

namespace poise::kinds::balancing_machine {

/// What the machine indicates for a rotor (plane unbalances, kg m), and a test mass placed in
/// a hole with the run's placement tolerances (mass kg, radius m, angle rad, height m).
struct IsoBench {
  std::function<Eigen::Vector2cd(const std::vector<models::PlaneMass>&)> indicate;
  std::function<models::PlaneMass(double, double, double, double)> place;
  double plane_1_height = 0.0, plane_2_height = 0.0;
};

struct IsoUrr {
  double plane[2] = {0.0, 0.0};  ///< URR_iso per plane (fraction)
};

/// ISO URR of `rotor` with test masses of `mass` at `radius` (0 and 90 deg).
IsoUrr iso_urr(IsoBench& bench, const std::vector<models::PlaneMass>& rotor, double mass, double radius);

struct TwoPlaneUmar {
  double mean[2]{}, max_deviation[2]{}, umar[2]{};  ///< readings in kg at r; umar in kg m
  std::vector<double> readings[2];                  ///< kg at r, per position
  bool pass = false;
};

/// The two-plane U_mar test; `claim` is the claimed U_mar per plane (kg m).
TwoPlaneUmar two_plane_umar(IsoBench& bench, const std::vector<models::PlaneMass>& rotor, double mass, double radius,
                            int positions, double plane_2_offset, double claim);

}  // namespace poise::kinds::balancing_machine
