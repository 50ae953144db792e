#include <algorithm>
#include <cmath>
#include <limits>

#include "core/units.h"
#include "kinds/balancing_machine/balancing_bench.h"

namespace poise::kinds::balancing_machine::detail {
using namespace poise::engine;
namespace {
using units::kPi;
}  // namespace

// The bench seen by the ISO tests: what the machine displays, and a test mass placed.
IsoBench iso_bench(Bench& bench, double z1, double z2) {
  IsoBench b;
  b.indicate = [&bench](const std::vector<PlaneMass>& m) { return bench.reading(bench.measure(bench.machine_r, m)); };
  b.place = [&bench](double mass, double r, double a, double z) { return bench.place(mass, r, a, z); };
  b.plane_1_height = z1;
  b.plane_2_height = z2;
  return b;
}

std::vector<PlaneMass> with(std::vector<PlaneMass> base, std::initializer_list<PlaneMass> extra) {
  base.insert(base.end(), extra.begin(), extra.end());
  return base;
}

cd unbalance_of(const PlaneMass& m) { return m.mass * m.radius * std::polar(1.0, m.angle); }

double rel_error(cd estimate, cd truth) { return std::abs(estimate - truth) / std::abs(truth); }

/// separation: the sensors' response to a test mass in each surface's holes; its spread and the
/// sensor-2 line against height.
void separation_test(Bench& bench, const BalancingExperiment& x, const RotorR& r, std::vector<double>& out,
                     std::size_t& o) {
  const double pos = x.positions;
  const Eigen::Vector2cd bare = bench.measure(bench.machine_r, r.masses);
  std::vector<double> h, s1, s2;
  for (int s = 1; s <= bench.model.rotor.surfaces; ++s) {
    const double z = bench.model.rotor.surface_height(s);
    double f1 = 0.0, f2 = 0.0;
    for (int hole = 0; hole < x.positions; ++hole) {
      const PlaneMass mass = bench.place(x.mass, x.radius, 2 * kPi * hole / pos, z);
      const Eigen::Vector2cd a = bench.measure(bench.machine_r, with(r.masses, {mass})) - bare;
      f1 += std::abs(a(0)) / pos;
      f2 += std::abs(a(1)) / pos;
    }
    h.push_back(z);
    s1.push_back(f1);
    s2.push_back(f2);
    out[o++] = f1 * 1e3;
    out[o++] = f2 * 1e3;
  }
  const auto [mn, mx] = std::minmax_element(s1.begin(), s1.end());
  double mean1 = 0.0;
  for (double v : s1) mean1 += v / static_cast<double>(s1.size());
  out[o++] = (*mx - *mn) / mean1 * 100.0;
  // Sensor 2 against height: least-squares line F = a (z - z0).
  const double n = static_cast<double>(h.size());
  double sh = 0, sf = 0, shh = 0, shf = 0;
  for (std::size_t j = 0; j < h.size(); ++j) {
    sh += h[j];
    sf += s2[j];
    shh += h[j] * h[j];
    shf += h[j] * s2[j];
  }
  const double slope = (n * shf - sh * sf) / (n * shh - sh * sh);
  const double icpt = (sf - slope * sh) / n;
  out[o++] = -icpt / slope * 1e3;
  double worst = 0.0;
  for (std::size_t j = 0; j < h.size(); ++j) worst = std::max(worst, std::abs(s2[j] - (icpt + slope * h[j])));
  out[o++] = worst / *std::max_element(s2.begin(), s2.end()) * 100.0;
}

/// umar: the indicated unbalance of a test mass stepped round each plane (minimum achievable residual
/// unbalance).
void umar_test(Bench& bench, const BalancingExperiment& x, const RotorR& r, std::vector<double>& out, std::size_t& o) {
  const double pos = x.positions;
  double umar[2], xmax[2], xmin[2], worst = 0.0;
  std::vector<double> readings;
  for (int p = 0; p < 2; ++p) {
    const double z = p == 0 ? r.z1 : r.z2;
    xmax[p] = -std::numeric_limits<double>::infinity();
    xmin[p] = std::numeric_limits<double>::infinity();
    for (int kpos = 0; kpos < x.positions; ++kpos) {
      const PlaneMass mass = bench.place(x.mass, x.radius, 2 * kPi * kpos / pos, z);
      const Eigen::Vector2cd plane = bench.reading(bench.measure(bench.machine_r, with(r.masses, {mass})));
      const double reading = std::abs(plane(p)) / x.radius;  // kg of mass at radius r
      xmax[p] = std::max(xmax[p], reading);
      xmin[p] = std::min(xmin[p], reading);
      readings.push_back(reading * 1e3);
      worst = std::max(worst, std::abs(reading - std::abs(r.residual[p] + unbalance_of(mass)) / x.radius));
    }
    umar[p] = (xmax[p] - xmin[p]) * x.radius / 2.0;
  }
  for (double v : {umar[0], umar[1], umar[0] + umar[1], xmax[0] * 1e3, xmin[0] * 1e3, xmax[1] * 1e3, xmin[1] * 1e3,
                   std::abs(r.residual[0]), std::abs(r.residual[1]), worst * 1e3}) {
    out[o++] = v;
  }
  for (double v : readings) out[o++] = v;
}

/// stability: readings of a test mass stepped round one surface, optionally after balancing first.
void stability_test(Bench& bench, const BalancingExperiment& x, const RotorR& r, std::vector<double>& out,
                    std::size_t& o) {
  const double pos = x.positions;
  std::vector<PlaneMass> rotor = r.masses;
  if (x.balance_first) {
    const Eigen::Vector2cd est = bench.reading(bench.measure(bench.machine_r, rotor));
    rotor.push_back(bench.correction(est(0), x.radius, r.z1));
    rotor.push_back(bench.correction(est(1), x.radius, r.z2));
  }
  const cd left[2] = {r.residual[0] + (x.balance_first ? unbalance_of(rotor[2]) : 0.0),
                      r.residual[1] + (x.balance_first ? unbalance_of(rotor[3]) : 0.0)};
  out[o++] = std::max(std::abs(left[0]), std::abs(left[1])) * 1e6;
  const double zt = bench.model.rotor.surface_height(x.surface);
  std::vector<double> r1, r2;
  for (int kpos = 0; kpos < x.positions; ++kpos) {
    const PlaneMass mass = bench.place(x.mass, x.radius, 2 * kPi * kpos / pos, zt);
    const Eigen::Vector2cd plane = bench.reading(bench.measure(bench.machine_r, with(rotor, {mass})));
    r1.push_back(std::abs(plane(0)));
    r2.push_back(std::abs(plane(1)));
  }
  std::vector<double> ratios;
  double dev[2];
  bool pass = true;
  for (int p = 0; p < 2; ++p) {
    const auto& rp = p == 0 ? r1 : r2;
    double mean = 0.0;
    for (double v : rp) mean += v / pos;
    dev[p] = 0.0;
    for (double v : rp) {
      ratios.push_back(v / mean);
      dev[p] = std::max(dev[p], std::abs(v / mean - 1.0));
    }
    pass = pass && dev[p] <= x.band;
  }
  out[o++] = dev[0] * 100.0;
  out[o++] = dev[1] * 100.0;
  out[o++] = pass ? 1.0 : 0.0;
  for (double v : ratios) out[o++] = v;
}

/// urr: unbalance reduction ratio, one correction run and the ISO 21940-21 indication of known test masses.
void urr_test(Bench& bench, const BalancingExperiment& x, const RotorR& r, std::vector<double>& out, std::size_t& o) {
  // ISO 21940-21 style: a known unbalance in both planes (at 0 and 90 deg), one
  // measuring run, one correction; URR = 1 - |after| / |before| per plane (true values).
  const PlaneMass t1 = bench.place(x.mass, x.radius, 0.0, r.z1);
  const PlaneMass t2 = bench.place(x.mass, x.radius, 0.5 * kPi, r.z2);
  const std::vector<PlaneMass> rotor = with(r.masses, {t1, t2});
  const Eigen::Vector2cd est = bench.reading(bench.measure(bench.machine_r, rotor));
  const PlaneMass c1 = bench.correction(est(0), x.radius, r.z1), c2 = bench.correction(est(1), x.radius, r.z2);
  const cd before[2] = {r.residual[0] + unbalance_of(t1), r.residual[1] + unbalance_of(t2)};
  const cd after[2] = {before[0] + unbalance_of(c1), before[1] + unbalance_of(c2)};
  const double urr1 = 1.0 - std::abs(after[0]) / std::abs(before[0]);
  const double urr2 = 1.0 - std::abs(after[1]) / std::abs(before[1]);
  out[o++] = urr1 * 100.0;
  out[o++] = urr2 * 100.0;
  out[o++] = std::min(urr1, urr2) * 100.0;
  out[o++] = std::min(urr1, urr2) >= x.requirement ? 1.0 : 0.0;
  // ISO 21940-21: the indication of known test masses, no correction (balancing_iso_tests.h).
  IsoBench iso = iso_bench(bench, r.z1, r.z2);
  const IsoUrr ir = iso_urr(iso, r.masses, x.mass, x.radius);
  out[o++] = ir.plane[0] * 100.0;
  out[o++] = ir.plane[1] * 100.0;
  out[o++] = std::min(ir.plane[0], ir.plane[1]) * 100.0;
  out[o++] = std::min(ir.plane[0], ir.plane[1]) >= x.requirement ? 1.0 : 0.0;
}

/// umar_iso: the ISO 21940-21 two-plane minimum achievable residual unbalance.
void umar_iso_test(Bench& bench, const BalancingExperiment& x, const RotorR& r, std::vector<double>& out,
                   std::size_t& o) {
  IsoBench iso = iso_bench(bench, r.z1, r.z2);
  const TwoPlaneUmar t = two_plane_umar(iso, r.masses, x.mass, x.radius, x.positions, x.plane_2_offset, x.claim);
  for (double v : {t.umar[0], t.umar[1], t.max_deviation[0] * 1e3, t.max_deviation[1] * 1e3, t.mean[0] * 1e3,
                   t.mean[1] * 1e3, t.pass ? 1.0 : 0.0}) {
    out[o++] = v;
  }
  for (const auto& readings : t.readings) {
    for (double v : readings) out[o++] = v * 1e3;
  }
}

/// accuracy: a test piece with plane unbalances at random angles, by influence coefficients and closed
/// form; couple interference and the plates' motion.
void accuracy_test(Bench& bench, const BalancingExperiment& x, const RotorR& r, std::vector<double>& out,
                   std::size_t& o) {
  // A test piece (mass centre offset from rotor R's) with plane unbalances of the given
  // size at random angles, measured on the machine calibrated with R.
  const double a1 = 2 * kPi * bench.draws.stream().uniform(), a2 = 2 * kPi * bench.draws.stream().uniform();
  const std::vector<PlaneMass> piece{{x.piece_unbalance, 1.0, a1, r.z1}, {x.piece_unbalance, 1.0, a2, r.z2}};
  const cd truth[2] = {unbalance_of(piece[0]), unbalance_of(piece[1])};
  const cd u_true = truth[0] + truth[1], v_true = truth[0] * r.z1 + truth[1] * r.z2;
  const Eigen::Vector2cd a = bench.measure(bench.machine_piece, piece);
  const Eigen::Vector2cd ic = bench.influence(a), cf = bench.closed_form(a);
  for (const Eigen::Vector2cd* e : {&ic, &cf}) {
    const Eigen::Vector2cd& est = *e;
    const cd u_est = est(0) + est(1), v_est = est(0) * r.z1 + est(1) * r.z2;
    out[o++] = std::abs(u_est - u_true) * 1e6;
    out[o++] = std::abs(v_est - v_true) / (r.z2 - r.z1) * 1e6;
    out[o++] = std::max(rel_error(est(0), truth[0]), rel_error(est(1), truth[1])) * 100.0;
  }
  // Couple-unbalance interference: a pure couple (equal masses 180 deg apart on the two
  // planes) added to the piece; the change of the indicated static unbalance per couple.
  const PlaneMass c1 = bench.place(x.mass, x.radius, 0.0, r.z1), c2 = bench.place(x.mass, x.radius, kPi, r.z2);
  const cd couple = unbalance_of(c1) * r.z1 + unbalance_of(c2) * r.z2;
  const Eigen::Vector2cd da = bench.measure(bench.machine_piece, with(piece, {c1, c2})) - a;
  const Eigen::Vector2cd dic = bench.influence(da), dcf = bench.closed_form(da);
  const cd applied_static = unbalance_of(c1) + unbalance_of(c2);  // ~0 (placement errors)
  out[o++] = std::abs(dic(0) + dic(1) - applied_static) / std::abs(couple) * 1e-3;
  out[o++] = std::abs(dcf(0) + dcf(1) - applied_static) / std::abs(couple) * 1e-3;
  // How far the horizontal plates move for a static unbalance of piece_unbalance (a
  // displacement pickup must resolve it): the piece's motion scaled by piece_unbalance / |U|.
  out[o++] = std::abs(a(0)) / (1.0 + bench.draws.value[kGain1]) / bench.machine_piece.sensor_1_plate_stiffness *
             x.piece_unbalance / std::abs(u_true) * 1e6;
}

void calibration_outputs(const Bench& bench, std::vector<double>& out, std::size_t& o) {
  for (Eigen::Index s = 0; s < 2; ++s) {
    for (Eigen::Index p = 0; p < 2; ++p) {
      const cd c = bench.cal.coefficients(s, p);
      out[o++] = std::abs(c);
      out[o++] = std::arg(c) / units::kRadPerDeg;
    }
  }
}

}  // namespace poise::kinds::balancing_machine::detail
