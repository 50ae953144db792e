#include "models/spring_plate_machine.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/units.h"

namespace poise::models {
namespace {

using cd = std::complex<double>;

void require_positive(double value, const char* field, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    std::ostringstream os;
    os << what << ": " << field << " = " << value << ", expected a finite value > 0";
    throw Error(os.str());
  }
}

void require_non_negative(double value, const char* field, const char* what) {
  if (!(value >= 0.0) || !std::isfinite(value)) {
    std::ostringstream os;
    os << what << ": " << field << " = " << value << ", expected a finite value >= 0";
    throw Error(os.str());
  }
}

void check_plate(const SpringPlate& plate) {
  require_positive(plate.length, "length", "spring plate");
  require_positive(plate.width, "width", "spring plate");
  require_positive(plate.thickness, "thickness", "spring plate");
  require_positive(plate.youngs_modulus, "youngs_modulus", "spring plate");
}

double torsional_stiffness(const SpringPlateMachineParams& p) {
  return p.torsion_split.rotation_factor * rotational_stiffness(p.torsional_plate_stiffness, p.lever) -
         p.rotating_mass * p.gravity * p.mass_centre_height;
}

double sensor_1_stiffness(const SpringPlateMachineParams& p) {
  return p.sensor_1_plate_stiffness > 0.0 ? p.sensor_1_plate_stiffness : p.horizontal_plate_stiffness;
}

// End slope phi per unit theta of the clamped ends (the guided end 0; pinned: free).
double end_slope_sign(TorsionPlateEnd end) {
  return end == TorsionPlateEnd::kClampedBaseInboard ? 1.0
                                                     : (end == TorsionPlateEnd::kClampedBaseOutboard ? -1.0 : 0.0);
}

}  // namespace

// ---- spring plates ----------------------------------------------------------------------

double plate_second_moment(const SpringPlate& plate) {
  check_plate(plate);
  return plate.width * plate.thickness * plate.thickness * plate.thickness / 12.0;
}

double guided_plate_stiffness(const SpringPlate& plate) {
  const double l = plate.length;
  return 12.0 * plate.youngs_modulus * plate_second_moment(plate) / (l * l * l);
}

double guided_plate_deflection(const SpringPlate& plate, double end_force) {
  return end_force / guided_plate_stiffness(plate);
}

double guided_plate_max_stress(const SpringPlate& plate, double end_force) {
  check_plate(plate);
  // Moment F L / 2 at each clamp (antisymmetric about mid-length), section modulus w t^2 / 6.
  return 3.0 * std::abs(end_force) * plate.length / (plate.width * plate.thickness * plate.thickness);
}

double guided_column_buckling_load(const SpringPlate& plate) {
  return units::kPi * units::kPi * plate.youngs_modulus * plate_second_moment(plate) / (plate.length * plate.length);
}

double guided_column_lateral_stiffness(const SpringPlate& plate, double axial_load) {
  const double ei = plate.youngs_modulus * plate_second_moment(plate), length = plate.length;
  const double u = length * std::sqrt(std::max(axial_load, 0.0) / ei);
  if (u < 1e-3) {
    // Series about P = 0 (the closed form cancels catastrophically): 12 EI/L^3 (1 - u^2/10).
    return 12.0 * ei / (length * length * length) * (1.0 - u * u / 10.0);
  }
  const double q = u / length;
  return ei * q * q * q * std::sin(u) / (2.0 - 2.0 * std::cos(u) - u * std::sin(u));
}

double rotational_stiffness(double plate_stiffness, double lever) { return plate_stiffness * lever * lever; }

const char* torsion_plate_end_name(TorsionPlateEnd e) {
  switch (e) {
    case TorsionPlateEnd::kClampedBaseInboard: return "clamped_base_inboard";
    case TorsionPlateEnd::kClampedBaseOutboard: return "clamped_base_outboard";
    case TorsionPlateEnd::kPinned: return "pinned";
    default: return "guided";
  }
}

TorsionPlateSplit torsion_plate_split(TorsionPlateEnd end, double plate_length, double lever) {
  require_positive(plate_length, "length", "torsional plate");
  require_positive(lever, "lever", "torsional plate");
  TorsionPlateSplit s;
  if (end == TorsionPlateEnd::kGuided) return s;
  if (end == TorsionPlateEnd::kPinned) {
    s.rotation_factor = s.force_factor = 0.25;  // F = 3 E I / L^3 v, no end moment
    return s;
  }
  // In units of E I / L^3 times l theta: v = l theta, phi = sgn theta; F = 12 - 6 sgn rho,
  // and the end moment's work per dtheta, sgn M / l = 4 rho^2 - 6 sgn rho.
  const double rho = plate_length / lever, sgn = end_slope_sign(end);
  const double f = 12.0 - 6.0 * sgn * rho, m = 4.0 * rho * rho - 6.0 * sgn * rho;
  s.force_factor = f / 12.0;
  s.rotation_factor = (f + m) / 12.0;
  s.moment_share = m / f;
  return s;
}

double torsion_plate_max_moment(const SpringPlate& plate, TorsionPlateEnd end, double lever, double theta) {
  // Deflection w = a x^2 + b x^3 from the base clamp (w(0) = w'(0) = 0), w(L) = l theta and
  // w'(L) = phi; M = E I w'' is linear in x, largest at an end.
  const double ei = plate.youngs_modulus * plate_second_moment(plate), len = plate.length;
  const double v = lever * theta;
  const double phi = end == TorsionPlateEnd::kPinned   ? 1.5 * v / len
                     : end == TorsionPlateEnd::kGuided ? 0.0
                                                       : end_slope_sign(end) * theta;
  const double a = (3.0 * v - phi * len) / (len * len), b = (phi * len - 2.0 * v) / (len * len * len);
  return ei * std::max(std::abs(2.0 * a), std::abs(2.0 * a + 6.0 * b * len));
}

// ---- machine -----------------------------------------------------------------------------

void validate(const SpringPlateMachineParams& p) {
  constexpr const char* kWhat = "spring-plate machine";
  require_positive(p.total_mass, "total_mass", kWhat);
  require_positive(p.rotating_mass, "rotating_mass", kWhat);
  require_positive(p.inertia, "inertia", kWhat);
  require_positive(p.lever, "lever", kWhat);
  require_positive(p.horizontal_plate_stiffness, "horizontal_plate_stiffness", kWhat);
  require_positive(p.torsional_plate_stiffness, "torsional_plate_stiffness", kWhat);
  require_non_negative(p.sensor_1_plate_stiffness, "sensor_1_plate_stiffness", kWhat);
  require_positive(p.torsion_split.rotation_factor, "torsion_split.rotation_factor", kWhat);
  require_positive(p.torsion_split.force_factor, "torsion_split.force_factor", kWhat);
  require_non_negative(p.damping_x, "damping_x", kWhat);
  require_non_negative(p.damping_theta, "damping_theta", kWhat);
  require_non_negative(p.gravity, "gravity", kWhat);
  if (!std::isfinite(p.mass_centre_height)) throw Error("spring-plate machine: mass_centre_height is not finite");
  if (p.rotating_mass > p.total_mass) {
    std::ostringstream os;
    os << kWhat << ": rotating_mass = " << p.rotating_mass << " kg exceeds total_mass = " << p.total_mass
       << " kg; expected m <= M (M is everything that translates, the swinging part included)";
    throw Error(os.str());
  }
  if (!(torsional_stiffness(p) > 0.0)) {
    std::ostringstream os;
    os << kWhat << ": K_rot - m g H = " << torsional_stiffness(p)
       << " N m/rad, expected > 0 (the torsional plate cannot hold the swinging part upright)";
    throw Error(os.str());
  }
}

Eigen::Matrix2d mass_matrix(const SpringPlateMachineParams& p) {
  const double mh = p.rotating_mass * p.mass_centre_height;
  Eigen::Matrix2d m;
  m << p.total_mass, mh, mh, p.inertia + mh * p.mass_centre_height;
  return m;
}

Eigen::Matrix2d stiffness_matrix(const SpringPlateMachineParams& p) {
  Eigen::Matrix2d k;
  k << 2.0 * p.horizontal_plate_stiffness, 0.0, 0.0, torsional_stiffness(p);
  return k;
}

Eigen::Matrix2d damping_matrix(const SpringPlateMachineParams& p) {
  Eigen::Matrix2d c;
  c << p.damping_x, 0.0, 0.0, p.damping_theta;
  return c;
}

NaturalFrequencies natural_frequencies(const SpringPlateMachineParams& p) {
  validate(p);
  const Eigen::Matrix2d m = mass_matrix(p), k = stiffness_matrix(p);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> es(k, m);
  if (es.info() != Eigen::Success) throw Error("spring-plate machine: eigenproblem K phi = w^2 M phi failed");
  NaturalFrequencies f;
  f.omega_1 = std::sqrt(es.eigenvalues()(0));  // ascending
  f.omega_2 = std::sqrt(es.eigenvalues()(1));
  f.omega_x = std::sqrt(k(0, 0) / m(0, 0));
  f.omega_theta = std::sqrt(k(1, 1) / m(1, 1));
  f.modes = es.eigenvectors();
  return f;
}

Eigen::Vector2cd unbalance_forcing(const SpringPlateUnbalance& u, double omega) {
  const double w2 = omega * omega;
  const cd f = u.static_unbalance * w2 * std::polar(1.0, u.static_phase);
  const cd t = u.couple_unbalance * w2 * std::polar(1.0, u.couple_phase);
  return {f, f * u.height + t};
}

Eigen::Vector2cd steady_state_response(const SpringPlateMachineParams& p, const SpringPlateUnbalance& u, double omega) {
  validate(p);
  const Eigen::Matrix2cd a =
      (stiffness_matrix(p) - omega * omega * mass_matrix(p)).cast<cd>() + cd(0.0, omega) * damping_matrix(p).cast<cd>();
  // 2x2: Cramer's rule is exact and keeps the error small near a singular (undamped resonant) A.
  const cd det = a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0);
  const Eigen::Vector2cd f = unbalance_forcing(u, omega);
  return {(a(1, 1) * f(0) - a(0, 1) * f(1)) / det, (a(0, 0) * f(1) - a(1, 0) * f(0)) / det};
}

Eigen::Vector2cd hard_bearing_response(const SpringPlateMachineParams& p, const SpringPlateUnbalance& u, double omega) {
  validate(p);
  const Eigen::Matrix2d k = stiffness_matrix(p);
  const Eigen::Vector2cd f = unbalance_forcing(u, omega);
  return {f(0) / k(0, 0), f(1) / k(1, 1)};
}

Eigen::Vector2cd sensor_forces(const SpringPlateMachineParams& p, const Eigen::Vector2cd& response) {
  return {sensor_1_stiffness(p) * response(0),
          p.torsion_split.force_factor * p.torsional_plate_stiffness * p.lever * response(1)};
}

SpringPlateUnbalance unbalance_from_sensor_forces(const SpringPlateMachineParams& p, const Eigen::Vector2cd& sensor,
                                                  double omega, double height) {
  require_positive(omega, "omega", "unbalance from sensor forces");
  const double w2 = omega * omega;
  const cd u = 2.0 * sensor(0) / w2;
  const cd v = (sensor(1) * p.lever * (1.0 + p.torsion_split.moment_share) - 2.0 * sensor(0) * height) / w2;
  SpringPlateUnbalance out;
  out.static_unbalance = std::abs(u);
  out.static_phase = std::arg(u);
  out.height = height;
  out.couple_unbalance = std::abs(v);
  out.couple_phase = std::arg(v);
  return out;
}

HardBearingCheck check_hard_bearing(const SpringPlateMachineParams& p, double omega, double factor) {
  require_positive(omega, "omega", "hard-bearing check");
  require_positive(factor, "factor", "hard-bearing check");
  const NaturalFrequencies f = natural_frequencies(p);
  HardBearingCheck c;
  c.ratio = f.omega_1 / omega;
  c.ok = c.ratio >= factor;
  SpringPlateUnbalance s;
  s.static_unbalance = 1.0;
  SpringPlateUnbalance v;
  v.couple_unbalance = 1.0;
  const double dev_x = std::abs(steady_state_response(p, s, omega)(0) / hard_bearing_response(p, s, omega)(0) - 1.0);
  const double dev_t = std::abs(steady_state_response(p, v, omega)(1) / hard_bearing_response(p, v, omega)(1) - 1.0);
  c.deviation = std::max(dev_x, dev_t);
  std::ostringstream os;
  os << "lowest natural frequency " << f.omega_1 << " rad/s is " << c.ratio << " times the speed " << omega
     << " rad/s (" << (c.ok ? "meets" : "below") << " the required factor " << factor
     << "); exact response deviates from the hard-bearing limit by " << c.deviation;
  if (!c.ok) os << "; stiffen the spring plates or lower the speed";
  c.message = os.str();
  return c;
}

// ---- Eqs. 1-2 ----------------------------------------------------------------------------

ResultantUnbalance resultant_unbalance(std::span<const PlaneMass> masses, double height) {
  ResultantUnbalance r;
  r.height = height;
  for (const PlaneMass& pm : masses) {
    const cd ui = pm.mass * pm.radius * std::polar(1.0, pm.angle);
    r.static_unbalance += ui;
    r.couple_unbalance += ui * (pm.height - height);
  }
  return r;
}

SpringPlateUnbalance to_machine_unbalance(const ResultantUnbalance& r) {
  SpringPlateUnbalance u;
  u.static_unbalance = std::abs(r.static_unbalance);
  u.static_phase = std::arg(r.static_unbalance);
  u.height = r.height;
  u.couple_unbalance = std::abs(r.couple_unbalance);
  u.couple_phase = std::arg(r.couple_unbalance);
  return u;
}

// ---- time domain -------------------------------------------------------------------------

double mechanical_energy(const SpringPlateMachineParams& p, const double* y) {
  const Eigen::Vector2d q(y[0], y[2]), qd(y[1], y[3]);
  return 0.5 * qd.dot(mass_matrix(p) * qd) + 0.5 * q.dot(stiffness_matrix(p) * q);
}

int spring_plate_rhs(double t, const double* y, double* ydot, void* user_data) {
  if (user_data == nullptr) return -1;
  const auto* d = static_cast<const SpringPlateRhsData*>(user_data);
  const SpringPlateMachineParams& p = d->params;
  const SpringPlateUnbalance& u = d->unbalance;
  const double w2 = d->omega * d->omega;
  const double f = u.static_unbalance * w2 * std::cos(d->omega * t + u.static_phase);
  const double torque = u.couple_unbalance * w2 * std::cos(d->omega * t + u.couple_phase);
  const double mh = p.rotating_mass * p.mass_centre_height;
  const double m11 = p.total_mass, m12 = mh, m22 = p.inertia + mh * p.mass_centre_height;
  const double r1 = f - p.damping_x * y[1] - 2.0 * p.horizontal_plate_stiffness * y[0];
  const double r2 = f * u.height + torque - p.damping_theta * y[3] - torsional_stiffness(p) * y[2];
  const double det = m11 * m22 - m12 * m12;
  ydot[0] = y[1];
  ydot[1] = (m22 * r1 - m12 * r2) / det;
  ydot[2] = y[3];
  ydot[3] = (m11 * r2 - m12 * r1) / det;
  return 0;
}

}  // namespace poise::models
