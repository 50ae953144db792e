#include "geometry/mass_properties.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace poise::geometry {

Moments& Moments::operator+=(const Moments& o) {
  mass += o.mass;
  first += o.first;
  second += o.second;
  return *this;
}

MassProperties to_mass_properties(const Moments& m) {
  MassProperties p;
  p.mass = m.mass;
  if (m.mass == 0.0) return p;
  p.com = m.first / m.mass;
  const Eigen::Matrix3d c = m.second - m.mass * p.com * p.com.transpose();
  p.inertia = c.trace() * Eigen::Matrix3d::Identity() - c;
  return p;
}

Moments exact_moments(const Mesh& mesh, double density) {
  Moments m;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    const Eigen::Vector3d& b = mesh.vertices[t[1]];
    const Eigen::Vector3d& c = mesh.vertices[t[2]];
    const double v = a.dot(b.cross(c)) / 6.0;
    const Eigen::Vector3d s = a + b + c;
    m.mass += v;
    m.first += v * s / 4.0;
    m.second += v / 20.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  m.mass *= density;
  m.first *= density;
  m.second *= density;
  return m;
}

Moments exact_moments(const Assembly& parts) {
  Moments m;
  for (const auto& b : parts) m += exact_moments(b.mesh, b.density);
  return m;
}

RayCastStats& RayCastStats::operator+=(const RayCastStats& o) {
  rays += o.rays;
  crossings += o.crossings;
  open_rays += o.open_rays;
  overlap_rays += o.overlap_rays;
  overlap_volume_m3 += o.overlap_volume_m3;
  overlap_box.extend(o.overlap_box);
  return *this;
}

namespace {

// One ray of the grid: origin o, direction d (a unit axis), its cell of area h^2 across the
// axes u and v.
struct GridRay {
  Eigen::Vector3d o, d;
  double h = 0.0, merge_tol = 0.0;
  int u = 0, v = 1;
};

// The moments along one ray from its sorted crossings; its overlap (winding >= 2) noted.
void integrate_ray(const std::vector<EmbreeScene::Crossing>& xs, const std::vector<double>& densities,
                   const GridRay& ray, Moments& acc, RayCastStats& st) {
  const Eigen::Vector3d& o = ray.o;
  const Eigen::Vector3d& d = ray.d;
  const double dA = ray.h * ray.h;
  ++st.rays;
  st.crossings += xs.size();
  // Winding per geometry: each mesh's own shells define its inside.
  double w_rho = 0.0;  // sum over meshes of density * winding
  int w_total = 0;
  bool overlap = false;
  for (std::size_t k = 0; k + 1 < xs.size(); ++k) {
    w_rho += xs[k].sign * densities[xs[k].geom];
    w_total += xs[k].sign;
    const double t0 = xs[k].t, t1 = xs[k + 1].t;
    if (w_total >= 2 && t1 - t0 > ray.merge_tol) {
      overlap = true;
      st.overlap_volume_m3 += (w_total - 1) * (t1 - t0) * dA;
      Eigen::Vector3d half = Eigen::Vector3d::Zero();
      half[ray.u] = half[ray.v] = ray.h / 2.0;
      st.overlap_box.extend(o + t0 * d - half);
      st.overlap_box.extend(o + t1 * d + half);
    }
    if (w_rho == 0.0 || t1 <= t0) continue;
    const double len = t1 - t0, q2 = (t1 * t1 - t0 * t0) / 2.0, q3 = (t1 * t1 * t1 - t0 * t0 * t0) / 3.0;
    const double wgt = w_rho * dA;
    acc.mass += wgt * len;
    acc.first += wgt * (o * len + d * q2);
    acc.second +=
        wgt * (o * o.transpose() * len + (o * d.transpose() + d * o.transpose()) * q2 + d * d.transpose() * q3);
  }
  if (!xs.empty()) w_total += xs.back().sign;
  if (w_total != 0) ++st.open_rays;
  if (overlap) ++st.overlap_rays;
}

}  // namespace

Moments raycast_moments(const EmbreeScene& scene, const std::vector<double>& densities, const RayGridOptions& opt,
                        RayCastStats* stats) {
  POISE_INVARIANT(opt.axis >= 0 && opt.axis <= 2, "raycast_moments: axis must be 0, 1 or 2");
  require(opt.rays_per_side >= 1, "raycast_moments: at least one ray per side");
  POISE_INVARIANT(densities.size() == scene.meshes().size(), "raycast_moments: one density per mesh");
  Eigen::AlignedBox3d box;
  for (const auto& m : scene.meshes()) box.extend(m.bounds());
  Moments total;
  if (box.isEmpty()) return total;
  const int a = opt.axis, u = (a + 1) % 3, v = (a + 2) % 3;
  const Eigen::Vector3d ext = box.sizes();
  const double h = std::max(ext[u], ext[v]) / opt.rays_per_side;
  if (!(h > 0)) return total;
  const int nu = std::max(1, static_cast<int>(std::ceil(ext[u] / h - 1e-9)));
  const int nv = std::max(1, static_cast<int>(std::ceil(ext[v] / h - 1e-9)));
  // Centre the grid on the box so a symmetric body meets a symmetric grid.
  const double u0 = box.center()[u] - 0.5 * nu * h, v0 = box.center()[v] - 0.5 * nv * h;
  const double start = box.min()[a] - 0.01 * ext[a] - 1e-6;
  GridRay proto;
  proto.d = Eigen::Vector3d::Zero();
  proto.d[a] = 1.0;
  proto.h = h;
  proto.merge_tol = 1e-9 * (ext.norm() + 1e-3);
  proto.u = u;
  proto.v = v;

  std::vector<Moments> rows(nu);
  std::vector<RayCastStats> row_stats(nu);
  tbb::parallel_for(0, nu, [&](int i) {
    const EmbreeThreadFlags flags;
    std::vector<EmbreeScene::Crossing> xs;
    GridRay ray = proto;
    for (int j = 0; j < nv; ++j) {
      ray.o[a] = start;
      ray.o[u] = u0 + (i + 0.5) * h;
      ray.o[v] = v0 + (j + 0.5) * h;
      scene.trace_all(ray.o, ray.d, ray.merge_tol, xs);
      integrate_ray(xs, densities, ray, rows[i], row_stats[i]);
    }
  });
  RayCastStats s;
  for (int i = 0; i < nu; ++i) {
    total += rows[i];
    s += row_stats[i];
  }
  if (stats) *stats += s;
  return total;
}

Moments raycast_moments(const Assembly& parts, const RayGridOptions& opt, RayCastStats* stats) {
  Moments m;
  for (const auto& b : parts) {
    const EmbreeScene scene({b.mesh}, true);
    m += raycast_moments(scene, {b.density}, opt, stats);
  }
  return m;
}

MassProperties solid_cylinder_z(double mass, double radius, double length) {
  MassProperties p;
  p.mass = mass;
  const double ixx = mass * (3 * radius * radius + length * length) / 12.0;
  p.inertia.diagonal() << ixx, ixx, mass * radius * radius / 2.0;
  return p;
}

MassProperties solid_box(double mass, const Eigen::Vector3d& s) {
  MassProperties p;
  p.mass = mass;
  p.inertia.diagonal() << mass * (s.y() * s.y() + s.z() * s.z()) / 12.0, mass * (s.x() * s.x() + s.z() * s.z()) / 12.0,
      mass * (s.x() * s.x() + s.y() * s.y()) / 12.0;
  return p;
}

}  // namespace poise::geometry
