#pragma once
// Meshes with closed-form mass properties, built here triangle by triangle (independently of
// src/geometry/generators), and their closed forms: prisms of regular polygons.
#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <string>

#include "geometry/mass_properties.h"
#include "geometry/mesh.h"

namespace poise::test {

/// Area and polar second moment of area (about its centre) of the regular n-gon of
/// circumradius r: A = n r^2 sin(2 pi/n) / 2, J = n r^4 sin(2 pi/n) (2 + cos(2 pi/n)) / 12.
inline double ngon_area(double r, int n) { return 0.5 * n * r * r * std::sin(2.0 * std::numbers::pi / n); }
inline double ngon_polar_moment(double r, int n) {
  const double a = 2.0 * std::numbers::pi / n;
  return n * std::pow(r, 4) * std::sin(a) * (2.0 + std::cos(a)) / 12.0;
}

/// A plate of thickness t (z from 0 to t): the regular n-gon of circumradius R about the z
/// axis with a through hole, the n-gon of circumradius rh centred at (cx, 0). One closed
/// genus-1 shell, outward normals; vertex i of the hole faces vertex i of the rim.
inline geometry::Mesh disk_with_offset_hole(double R, double rh, double cx, double t, int n) {
  geometry::Mesh m;
  m.name = "disk_with_hole";
  auto add = [&](double x, double y, double z) {
    m.vertices.emplace_back(x, y, z);
    return static_cast<std::uint32_t>(m.vertices.size() - 1);
  };
  std::vector<std::uint32_t> ob(n), ot(n), hb(n), ht(n);
  for (int i = 0; i < n; ++i) {
    const double th = 2.0 * std::numbers::pi * i / n;
    ob[i] = add(R * std::cos(th), R * std::sin(th), 0.0);
    ot[i] = add(R * std::cos(th), R * std::sin(th), t);
    hb[i] = add(cx + rh * std::cos(th), rh * std::sin(th), 0.0);
    ht[i] = add(cx + rh * std::cos(th), rh * std::sin(th), t);
  }
  auto quad = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    m.triangles.push_back({a, b, c});
    m.triangles.push_back({a, c, d});
  };
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    quad(ob[i], ob[j], ot[j], ot[i]);  // rim, normal outwards
    quad(hb[i], ht[i], ht[j], hb[j]);  // hole wall, normal towards the hole's axis
    quad(ot[i], ot[j], ht[j], ht[i]);  // top, +z
    quad(ob[i], hb[i], hb[j], ob[j]);  // bottom, -z
  }
  return m;
}

/// Closed form of disk_with_offset_hole (density rho): the rim prism minus the hole prism.
inline geometry::MassProperties disk_with_offset_hole_closed_form(double R, double rh, double cx, double t, int n,
                                                                  double rho) {
  const double mo = rho * t * ngon_area(R, n), mh = rho * t * ngon_area(rh, n);
  const double jo = rho * t * ngon_polar_moment(R, n), jh = rho * t * ngon_polar_moment(rh, n);
  geometry::MassProperties p;
  p.mass = mo - mh;
  const double x = -mh * cx / p.mass;  // centre of mass on the x axis, away from the hole
  p.com = Eigen::Vector3d(x, 0.0, t / 2.0);
  const double ixx = jo / 2.0 + mo * t * t / 12.0 - (jh / 2.0 + mh * t * t / 12.0);
  p.inertia.setZero();
  p.inertia(0, 0) = ixx;
  p.inertia(1, 1) = ixx + mo * x * x - mh * (cx - x) * (cx - x);
  p.inertia(2, 2) = jo + mo * x * x - (jh + mh * (cx - x) * (cx - x));
  return p;
}

/// Closed form of a prism of the regular n-gon of circumradius r about z, z in [z0, z1].
inline geometry::MassProperties ngon_prism_closed_form(double r, int n, double z0, double z1, double rho) {
  const double len = z1 - z0, m = rho * len * ngon_area(r, n), j = rho * len * ngon_polar_moment(r, n);
  geometry::MassProperties p;
  p.mass = m;
  p.com = Eigen::Vector3d(0.0, 0.0, 0.5 * (z0 + z1));
  p.inertia.setZero();
  p.inertia(0, 0) = p.inertia(1, 1) = j / 2.0 + m * len * len / 12.0;
  p.inertia(2, 2) = j;
  return p;
}

/// Writes the mesh as ASCII STL (lengths divided by unit_m), every facet with its normal.
inline std::string ascii_stl(const geometry::Mesh& mesh, double unit_m) {
  std::string s = "solid " + mesh.name + "\n";
  char buf[160];
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    const Eigen::Vector3d nrm = mesh.face_normal(k).normalized();
    std::snprintf(buf, sizeof buf, "  facet normal %.9e %.9e %.9e\n    outer loop\n", nrm.x(), nrm.y(), nrm.z());
    s += buf;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d v = mesh.vertices[mesh.triangles[k][i]] / unit_m;
      std::snprintf(buf, sizeof buf, "      vertex %.17g %.17g %.17g\n", v.x(), v.y(), v.z());
      s += buf;
    }
    s += "    endloop\n  endfacet\n";
  }
  return s + "endsolid " + mesh.name + "\n";
}

}  // namespace poise::test
