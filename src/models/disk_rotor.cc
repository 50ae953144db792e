#include "models/disk_rotor.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace poise::models {

GimbalGravity gravity_in_gimbal(double g, double theta, double tilt, double tilt_azimuth) {
  // Turntable frame: gravity (0, g cos theta, -g sin theta). The gimbal axis is the
  // turntable x axis turned by `tilt` towards (0, cos az, sin az), i.e. about
  // n = (0, -sin az, cos az); gravity in the gimbal frame is R^T g.
  const Eigen::Vector3d g_tt(0.0, g * std::cos(theta), -g * std::sin(theta));
  if (tilt == 0.0) return {g_tt.y(), g_tt.z()};
  const Eigen::Vector3d n(0.0, -std::sin(tilt_azimuth), std::cos(tilt_azimuth));
  const Eigen::Vector3d g_gimbal = Eigen::AngleAxisd(tilt, n).toRotationMatrix().transpose() * g_tt;
  return {g_gimbal.y(), g_gimbal.z()};
}

double cogging_torque_at(const DiskRotorParams& p, double phi) {
  double torque = p.cogging_order > 0 ? -p.cogging_torque * std::sin(p.cogging_order * phi + p.cogging_phase) : 0.0;
  for (const auto& h : p.cogging_map) torque -= h.torque * std::sin(h.order * phi + h.phase);
  return torque;
}

int highest_cogging_order(const DiskRotorParams& p) {
  int highest = p.cogging_order > 0 ? p.cogging_order : 0;
  for (const auto& h : p.cogging_map) highest = std::max(highest, h.order);
  return highest;
}

namespace {
// Generalized force on phi: motor, cogging, friction, cable and gravity (no y, z in it).
inline double phi_force(const DiskRotorParams& p, const GimbalGravity& g, double phi, double w, double sp, double cp,
                        double motor_torque) {
  const double cogging = cogging_torque_at(p, phi);
  return motor_torque + cogging - p.viscous_friction * w - p.coulomb_friction * std::tanh(w / p.coulomb_smoothing) -
         p.torsion_stiffness * (phi - p.torsion_zero) + p.mass * p.eccentricity * (-g.gy * sp + g.gz * cp);
}
}  // namespace

double rigid_axis_acceleration(const DiskRotorParams& p, const GimbalGravity& g, double phi, double phidot,
                               double motor_torque) {
  const double pa = phi + p.eccentricity_angle;
  const double q_phi = phi_force(p, g, phi, phidot, std::sin(pa), std::cos(pa), motor_torque);
  return q_phi / (p.inertia + p.mass * p.eccentricity * p.eccentricity);
}

std::array<double, 3> disk_accelerations(const DiskRotorParams& p, const GimbalGravity& g, const DiskState& s,
                                         double motor_torque) {
  const double phi = s[0], w = s[1], y = s[2], yd = s[3], z = s[4], zd = s[5];
  const double m = p.mass, e = p.eccentricity;
  const double pa = phi + p.eccentricity_angle;
  const double sp = std::sin(pa), cp = std::cos(pa);
  const double q_phi = phi_force(p, g, phi, w, sp, cp, motor_torque);
  const double f_y = m * e * cp * w * w - p.support_stiffness * y - p.support_damping * yd + m * g.gy;
  const double f_z = m * e * sp * w * w - p.support_stiffness * z - p.support_damping * zd + m * g.gz;
  const double phi_dd = (q_phi + e * (sp * f_y - cp * f_z)) / p.inertia;
  return {phi_dd, (f_y + m * e * sp * phi_dd) / m, (f_z - m * e * cp * phi_dd) / m};
}

double disk_energy(const DiskRotorParams& p, const GimbalGravity& g, const DiskState& s) {
  const double phi = s[0], w = s[1], y = s[2], yd = s[3], z = s[4], zd = s[5];
  const double m = p.mass, e = p.eccentricity;
  const double pa = phi + p.eccentricity_angle;
  const double vcy = yd - e * w * std::sin(pa), vcz = zd + e * w * std::cos(pa);
  const double kinetic = 0.5 * m * (vcy * vcy + vcz * vcz) + 0.5 * p.inertia * w * w;
  const double potential = 0.5 * p.support_stiffness * (y * y + z * z) +
                           0.5 * p.torsion_stiffness * (phi - p.torsion_zero) * (phi - p.torsion_zero) -
                           m * (g.gy * (y + e * std::cos(pa)) + g.gz * (z + e * std::sin(pa)));
  return kinetic + potential;
}

double holding_torque(const DiskRotorParams& p, const GimbalGravity& g, double phi) {
  const double pa = phi + p.eccentricity_angle;
  return p.mass * p.eccentricity * (g.gy * std::sin(pa) - g.gz * std::cos(pa)) +
         p.torsion_stiffness * (phi - p.torsion_zero);
}

std::array<double, 2> static_deflection(const DiskRotorParams& p, const GimbalGravity& g) {
  return {p.mass * g.gy / p.support_stiffness, p.mass * g.gz / p.support_stiffness};
}

}  // namespace poise::models
