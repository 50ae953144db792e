#include "models/platform_statics.h"

#include <cmath>

namespace poise::models {

void GimbalBody::add_point_mass(double m, const Eigen::Vector3d& p) {
  mass += m;
  first_moment += m * p;
  inertia += m * (p.squaredNorm() * Eigen::Matrix3d::Identity() - p * p.transpose());
}

const char* axis_name(Axis a) {
  switch (a) {
    case Axis::kInner: return "inner";
    case Axis::kMiddle: return "middle";
    case Axis::kOuter: return "outer";
  }
  return "?";
}

int axis_component(Axis a) {
  switch (a) {
    case Axis::kInner: return 1;
    case Axis::kMiddle: return 2;
    case Axis::kOuter: return 0;
  }
  return 0;
}

Eigen::Matrix3d rot_x(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d r;
  r << 1, 0, 0, 0, c, -s, 0, s, c;
  return r;
}

Eigen::Matrix3d rot_y(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d r;
  r << c, 0, s, 0, 1, 0, -s, 0, c;
  return r;
}

Eigen::Matrix3d rot_z(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d r;
  r << c, -s, 0, s, c, 0, 0, 0, 1;
  return r;
}

Eigen::Matrix3d base_from_gimbal(Axis a, const GimbalAngles& q) {
  Eigen::Matrix3d r = rot_x(q.alpha);
  if (a == Axis::kOuter) return r;
  r = r * rot_z(q.beta);
  if (a == Axis::kMiddle) return r;
  return r * rot_y(q.gamma);
}

FrameForces specific_force_in_frames(const GimbalAngles& q, const Eigen::Vector3d& f_base) {
  FrameForces f;
  f.outer = rot_x(q.alpha).transpose() * f_base;    // C_b^o
  f.middle = rot_z(q.beta).transpose() * f.outer;   // C_o^m
  f.inner = rot_y(q.gamma).transpose() * f.middle;  // C_m^p
  return f;
}

namespace {

// Adds body b, whose frame is turned by R relative to the target frame, to the assembly.
void accumulate(GimbalBody& acc, const GimbalBody& b, const Eigen::Matrix3d& r) {
  acc.mass += b.mass;
  acc.first_moment += r * b.first_moment;
  acc.inertia += r * b.inertia * r.transpose();
}

}  // namespace

GimbalBody outboard_assembly(const Platform& p, Axis a, const GimbalAngles& q) {
  GimbalBody acc;
  const Eigen::Matrix3d ry = rot_y(q.gamma);
  switch (a) {
    case Axis::kInner: accumulate(acc, p.inner, Eigen::Matrix3d::Identity()); break;
    case Axis::kMiddle:
      accumulate(acc, p.middle, Eigen::Matrix3d::Identity());
      accumulate(acc, p.inner, ry);
      break;
    case Axis::kOuter: {
      const Eigen::Matrix3d rz = rot_z(q.beta);
      accumulate(acc, p.outer, Eigen::Matrix3d::Identity());
      accumulate(acc, p.middle, rz);
      accumulate(acc, p.inner, rz * ry);
      break;
    }
  }
  return acc;
}

PlatformTorques unbalance_torques(const Platform& p, const GimbalAngles& q, const Eigen::Vector3d& f_base) {
  const FrameForces f = specific_force_in_frames(q, f_base);
  PlatformTorques t;
  t.inner = outboard_assembly(p, Axis::kInner, q).first_moment.cross(f.inner);
  t.middle = outboard_assembly(p, Axis::kMiddle, q).first_moment.cross(f.middle);
  t.outer = outboard_assembly(p, Axis::kOuter, q).first_moment.cross(f.outer);
  t.axis[0] = t.inner.y();
  t.axis[1] = t.middle.z();
  t.axis[2] = t.outer.x();
  return t;
}

std::array<Eigen::Vector3d, 3> torque_sensitivities(const Platform& p, const GimbalAngles& q) {
  std::array<Eigen::Vector3d, 3> c;
  for (Axis a : kAllAxes) {
    const Eigen::Matrix3d r = base_from_gimbal(a, q);
    const Eigen::Vector3d s = r * outboard_assembly(p, a, q).first_moment;
    const Eigen::Vector3d axis = r.col(axis_component(a));
    // tau . axis = (S x f) . axis = f . (axis x S)
    c[static_cast<std::size_t>(a)] = axis.cross(s);
  }
  return c;
}

Eigen::Vector3d printed_eq1(const GimbalAngles& q, double g) {
  return Eigen::Vector3d(0.0, -std::sin(q.alpha), -std::cos(q.alpha)) * g;
}

Eigen::Vector3d printed_eq2(const GimbalAngles& q, double g) {
  const double sa = std::sin(q.alpha), ca = std::cos(q.alpha), sb = std::sin(q.beta), cb = std::cos(q.beta);
  return Eigen::Vector3d(-sa * sb, -sa * cb, -ca) * g;
}

Eigen::Vector3d printed_eq3(const GimbalAngles& q, double g) {
  const double sa = std::sin(q.alpha), ca = std::cos(q.alpha), sb = std::sin(q.beta), cb = std::cos(q.beta);
  const double sc = std::sin(q.gamma), cc = std::cos(q.gamma);
  return Eigen::Vector3d(-sa * sb * cc + ca * sc, -sa * cb, -sa * sb * sc - ca * cc) * g;
}

Eigen::Vector3d printed_eq4(const GimbalAngles& q, const PrintedInputs& in) {
  const double sa = std::sin(q.alpha), ca = std::cos(q.alpha), sb = std::sin(q.beta), cb = std::cos(q.beta);
  const double sc = std::sin(q.gamma), cc = std::cos(q.gamma);
  const double k = in.m_p * in.g, x = in.r_p.x(), y = in.r_p.y(), z = in.r_p.z();
  return {k * y * sa * sb * sc + k * y * ca * cc - k * z * sa * cb,
          -k * x * sa * sb * sc - k * x * ca * cc + k * z * sa * sb * cc - k * z * ca * sc,
          k * x * sa * cb - k * y * sa * sb * cc + k * y * ca * sc};
}

Eigen::Vector3d printed_eq7(const GimbalAngles& q, const PrintedInputs& in) {
  const double sa = std::sin(q.alpha), ca = std::cos(q.alpha), sb = std::sin(q.beta), cb = std::cos(q.beta);
  const double sc = std::sin(q.gamma), cc = std::cos(q.gamma);
  const double km = in.m_m * in.g, kp = in.m_p * in.g;
  const double xm = in.r_m.x(), ym = in.r_m.y(), zm = in.r_m.z();
  const double xp = in.r_p.x(), yp = in.r_p.y(), zp = in.r_p.z();
  return {km * ym * ca - km * zm * sa * cb + kp * xp * sa * cb * sc + kp * yp * ca - kp * zp * sa * cb * cc,
          // OCR 001 prints y_p in the fourth term (the derivation gives x_p): kept as printed.
          -km * xm * ca + km * zm * sa * sb - kp * xp * ca * cc - kp * yp * sa * sb * sc - kp * zp * ca * sc +
              kp * zp * sa * sb * cc,
          km * xm * sa * cb - km * ym * sa * sb + kp * xp * sa * cb * cc - kp * yp * sa * sb + kp * zp * sa * cb * sc};
}

Eigen::Vector3d printed_eq10(const GimbalAngles& q, const PrintedInputs& in) {
  const double sa = std::sin(q.alpha), ca = std::cos(q.alpha), sb = std::sin(q.beta), cb = std::cos(q.beta);
  const double sc = std::sin(q.gamma), cc = std::cos(q.gamma);
  const double ko = in.m_o * in.g, km = in.m_m * in.g, kp = in.m_p * in.g;
  const double xo = in.r_o.x(), yo = in.r_o.y(), zo = in.r_o.z();
  const double xm = in.r_m.x(), ym = in.r_m.y(), zm = in.r_m.z();
  const double xp = in.r_p.x(), yp = in.r_p.y(), zp = in.r_p.z();
  return {ko * yo * ca - ko * zo * sa + km * xm * ca * sb + km * ym * ca * cb - km * zm * sa + kp * xp * ca * sb * cc +
              kp * xp * sa * sc + kp * yp * ca * cb + kp * zp * ca * sb * sc - kp * zp * sa * cc,
          // The sign before m_p g y_p cos a sin b is lost in both OCRs; "+" taken.
          -ko * xo * ca - km * xm * ca * cb + km * ym * ca * sb - kp * xp * ca * cb * cc + kp * yp * ca * sb -
              kp * zp * ca * cb * sc,
          ko * xo * sa + km * xm * sa * cb - km * ym * sa * sb + kp * xp * sa * cb * cc - kp * yp * sa * sb +
              kp * zp * sa * cb * sc};
}

Eigen::Vector3d line_of_sight(const GimbalAngles& q) { return base_from_gimbal(Axis::kInner, q).col(0); }

double los_error_from_axis_errors(const GimbalAngles& q, double d_alpha, double d_beta, double d_gamma) {
  const Eigen::Matrix3d ro = rot_x(q.alpha);
  const Eigen::Matrix3d rm = ro * rot_z(q.beta);
  const Eigen::Vector3d d = rm * rot_y(q.gamma).col(0);
  const Eigen::Vector3d dw = d_alpha * Eigen::Vector3d::UnitX() + d_beta * ro.col(2) + d_gamma * rm.col(1);
  return dw.cross(d).norm();
}

}  // namespace poise::models
