#include "geometry/obstruction.h"

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "core/error.h"

namespace poise::geometry {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Nearest hits of up to 16 rays (origins o, common direction d) in one scene: t, or +inf.
void nearest16(const EmbreeScene& scene, const Eigen::Vector3d* o, int n, const Eigen::Vector3d& d,
               std::array<float, 16>& t, std::array<unsigned, 16>& geom) {
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  for (int i = 0; i < 16; ++i) {
    valid[i] = i < n ? -1 : 0;
    const Eigen::Vector3d& p = o[i < n ? i : 0];
    rh.ray.org_x[i] = static_cast<float>(p.x());
    rh.ray.org_y[i] = static_cast<float>(p.y());
    rh.ray.org_z[i] = static_cast<float>(p.z());
    rh.ray.dir_x[i] = static_cast<float>(d.x());
    rh.ray.dir_y[i] = static_cast<float>(d.y());
    rh.ray.dir_z[i] = static_cast<float>(d.z());
    rh.ray.tnear[i] = 0.0f;
    rh.ray.tfar[i] = kInf;
    rh.ray.mask[i] = 0xFFFFFFFFu;
    rh.ray.flags[i] = 0;
    rh.ray.time[i] = 0.0f;
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
  }
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcIntersect16(valid, scene.handle(), &ctx, &rh);
  for (int i = 0; i < 16; ++i) {
    const bool hit = i < n && rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
    // float to float: clang-tidy 14 takes the float infinity for a constant out of float's range.
    t[i] = hit ? rh.ray.tfar[i] : kInf;  // NOLINT(bugprone-narrowing-conversions)
    geom[i] = hit ? rh.hit.geomID[i] : RTC_INVALID_GEOMETRY_ID;
  }
}

struct ClosestQuery {
  const Mesh* mesh;
  Eigen::Vector3d p;
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector3d q = Eigen::Vector3d::Zero();
  unsigned prim = 0;
  bool on_face = false;
};

bool closest_callback(RTCPointQueryFunctionArguments* args) {
  auto* cq = static_cast<ClosestQuery*>(args->userPtr);
  const Mesh& m = *cq->mesh;
  const Triangle& tri = m.triangles[args->primID];
  bool on_face = false;
  const Eigen::Vector3d q =
      closest_point_on_triangle(cq->p, m.vertices[tri[0]], m.vertices[tri[1]], m.vertices[tri[2]], &on_face);
  const double d = (q - cq->p).norm();
  if (d < cq->best) {
    cq->best = d;
    cq->q = q;
    cq->prim = args->primID;
    cq->on_face = on_face;
    args->query->radius = static_cast<float>(d) * 1.0001f + 1e-9f;  // a hair larger: float rounding
    return true;
  }
  return false;
}

// Winding number of the closed mesh about p: minus the sum of crossing signs from p outward.
int winding(const EmbreeScene& scene, const Eigen::Vector3d& p) {
  static const Eigen::Vector3d dir = Eigen::Vector3d(0.5773, 0.5774, 0.5772).normalized();  // off every axis
  thread_local std::vector<EmbreeScene::Crossing> xs;
  scene.trace_all(p, dir, 1e-12, xs);
  int s = 0;
  for (const auto& x : xs) {
    if (x.t > 0) s += x.sign;
  }
  return -s;
}

}  // namespace

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c, bool* on_face) {
  if (on_face) *on_face = false;
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  if (on_face) *on_face = true;
  return a + ab * (vb * denom) + ac * (vc * denom);
}

double min_signed_distance(const Mesh& a, const Eigen::Isometry3d& a_to_b, const EmbreeScene& b) {
  POISE_INVARIANT(b.meshes().size() == 1, "min_signed_distance: the target scene holds one mesh");
  const Mesh& target = b.mesh(0);
  double best = std::numeric_limits<double>::infinity();
  for (const auto& v : a.vertices) {
    ClosestQuery cq{&target, a_to_b * v};
    RTCPointQuery q;
    q.x = static_cast<float>(cq.p.x());
    q.y = static_cast<float>(cq.p.y());
    q.z = static_cast<float>(cq.p.z());
    q.time = 0.0f;
    q.radius = kInf;
    RTCPointQueryContext ctx;
    rtcInitPointQueryContext(&ctx);
    rtcPointQuery(b.handle(), &q, &ctx, closest_callback, &cq);
    double d = cq.best;
    // The face normal decides the side unless the closest point is on an edge or vertex
    // (where the faces may disagree) or says "inside": then count windings.
    const bool outside_by_normal = cq.on_face && (cq.p - cq.q).dot(target.face_normal(cq.prim)) > 0;
    if (!outside_by_normal && winding(b, cq.p) > 0) d = -d;
    best = std::min(best, d);
  }
  return best;
}

GimbalPose seeker_pose(const models::SeekerErrorState& errors, double alpha, double beta) {
  return {models::yaw_orientation(errors.yaw, alpha), models::pitch_orientation(errors.pitch, beta),
          models::optical_axis(errors.collimation)};
}

GimbalPose nominal_pose(double alpha, double beta) { return seeker_pose(models::SeekerErrorState{}, alpha, beta); }

SeekerScenes::SeekerScenes(const SeekerGeometry& g, int beam_rays) : SeekerScenes(g, seeker_meshes(g), beam_rays) {}

SeekerScenes::SeekerScenes(const SeekerGeometry& g, SeekerMeshes parts, int beam_rays)
    : geometry_(g), meshes_(std::move(parts)) {
  require(beam_rays >= 1, "SeekerScenes: at least one beam ray");
  base_ = std::make_unique<EmbreeScene>(std::vector<Mesh>{meshes_.housing, meshes_.posts, meshes_.window});
  yaw_ = std::make_unique<EmbreeScene>(std::vector<Mesh>{meshes_.ring});
  pitch_ = std::make_unique<EmbreeScene>(std::vector<Mesh>{meshes_.barrel, meshes_.pitch_shafts});
  housing_q_ = std::make_unique<EmbreeScene>(std::vector<Mesh>{meshes_.housing}, true);
  ring_q_ = std::make_unique<EmbreeScene>(std::vector<Mesh>{meshes_.ring}, true);
  barrel_q_ = std::make_unique<EmbreeScene>(std::vector<Mesh>{meshes_.barrel}, true);
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < beam_rays; ++i) {
    const double r = g.aperture_radius * std::sqrt((i + 0.5) / beam_rays), th = i * golden;
    origins_.emplace_back(g.detector_x, r * std::cos(th), r * std::sin(th));
  }
}

SeekerScenes::Beam SeekerScenes::trace_beam(const GimbalPose& pose) const {
  const EmbreeThreadFlags flags;
  const Eigen::Matrix3d base_from_pitch = pose.yaw * pose.pitch;
  const Eigen::Vector3d d_p = pose.optical_axis.normalized();
  const Eigen::Vector3d d_y = pose.pitch * d_p, d_b = base_from_pitch * d_p;
  Beam beam;
  std::array<Eigen::Vector3d, 16> ob, oy;
  std::array<float, 16> tb, ty, tp;
  std::array<unsigned, 16> gb, gy, gp;
  for (std::size_t s = 0; s < origins_.size(); s += 16) {
    const int n = static_cast<int>(std::min<std::size_t>(16, origins_.size() - s));
    for (int i = 0; i < n; ++i) {
      ob[i] = base_from_pitch * origins_[s + i];
      oy[i] = pose.pitch * origins_[s + i];
    }
    nearest16(*base_, ob.data(), n, d_b, tb, gb);
    nearest16(*yaw_, oy.data(), n, d_y, ty, gy);
    nearest16(*pitch_, &origins_[s], n, d_p, tp, gp);
    for (int i = 0; i < n; ++i) {
      ++beam.rays;
      if (gb[i] == 2 && tb[i] < ty[i] && tb[i] < tp[i]) ++beam.unobstructed;  // geomID 2: window
    }
  }
  return beam;
}

SeekerScenes::Clearance SeekerScenes::clearance(const GimbalPose& pose) const {
  const EmbreeThreadFlags flags;
  Eigen::Isometry3d yaw = Eigen::Isometry3d::Identity(), pitch_in_yaw = Eigen::Isometry3d::Identity();
  yaw.linear() = pose.yaw;
  pitch_in_yaw.linear() = pose.pitch;
  const Eigen::Isometry3d pitch = yaw * pitch_in_yaw;
  auto both = [](const Mesh& a, const Eigen::Isometry3d& a_to_b, const EmbreeScene& sa, const Mesh& b,
                 const EmbreeScene& sb) {
    return std::min(min_signed_distance(a, a_to_b, sb), min_signed_distance(b, a_to_b.inverse(), sa));
  };
  Clearance c;
  c.ring_housing = both(meshes_.ring, yaw, *ring_q_, meshes_.housing, *housing_q_);
  c.barrel_housing = both(meshes_.barrel, pitch, *barrel_q_, meshes_.housing, *housing_q_);
  c.barrel_ring = both(meshes_.barrel, pitch_in_yaw, *barrel_q_, meshes_.ring, *ring_q_);
  return c;
}

}  // namespace poise::geometry
