#include "geometry/embree_scene.h"

#include <memory>

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>

#include <tbb/task_arena.h>

#include "core/error.h"

namespace poise::geometry {
namespace {

void on_error(void*, RTCError code, const char* str) {
  // Reported again as an exception by the calls that check rtcGetDeviceError.
  (void)code;
  (void)str;
}

void check(RTCDevice dev, const char* what) {
  const RTCError e = rtcGetDeviceError(dev);
  if (e != RTC_ERROR_NONE)
    throw Error(std::string("Embree: ") + what + " failed (error code " + std::to_string(static_cast<int>(e)) + ")");
}

// The filter of collect-all-hits scenes: record the hit, reject it so traversal goes on.
struct CollectContext {
  RTCIntersectContext base;
  std::vector<std::pair<unsigned, unsigned>>* hits;
};

void collect_filter(const RTCFilterFunctionNArguments* args) {
  auto* ctx = reinterpret_cast<CollectContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    ctx->hits->emplace_back(RTCHitN_geomID(args->hit, args->N, i), RTCHitN_primID(args->hit, args->N, i));
    args->valid[i] = 0;
  }
}

}  // namespace

RTCDevice embree_device() {
  static RTCDevice device = [] {
    RTCDevice d = rtcNewDevice("verbose=0");
    if (!d)
      throw Error("Embree: rtcNewDevice failed (error code " +
                  std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
    rtcSetDeviceErrorFunction(d, on_error, nullptr);
    return d;
  }();
  return device;
}

EmbreeThreadFlags::EmbreeThreadFlags() : saved_(_mm_getcsr()) {
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

EmbreeThreadFlags::~EmbreeThreadFlags() { _mm_setcsr(saved_); }

EmbreeScene::EmbreeScene(std::vector<Mesh> meshes, bool collect_all_hits)
    : meshes_(std::move(meshes)), collect_(collect_all_hits) {
  RTCDevice dev = embree_device();
  // The scene and each geometry are held by their own releasing handle until the scene is built:
  // a check that throws here (no destructor runs for an unfinished object) leaks neither.
  std::unique_ptr<RTCSceneTy, void (*)(RTCScene)> scene(rtcNewScene(dev), rtcReleaseScene);
  scene_ = scene.get();
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_MEDIUM);
  for (std::size_t k = 0; k < meshes_.size(); ++k) {
    const Mesh& m = meshes_[k];
    const std::unique_ptr<RTCGeometryTy, void (*)(RTCGeometry)> geometry(
        rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE), rtcReleaseGeometry);
    RTCGeometry g = geometry.get();
    auto* v =
        static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                    std::max<std::size_t>(m.vertices.size(), 1)));
    auto* ix = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned),
                                                              std::max<std::size_t>(m.triangles.size(), 1)));
    check(dev, "allocating geometry buffers");
    for (std::size_t i = 0; i < m.vertices.size(); ++i) {
      for (int j = 0; j < 3; ++j) v[3 * i + j] = static_cast<float>(m.vertices[i][j]);
    }
    if (m.vertices.empty()) v[0] = v[1] = v[2] = 0.0f;
    for (std::size_t i = 0; i < m.triangles.size(); ++i) {
      for (int j = 0; j < 3; ++j) ix[3 * i + j] = m.triangles[i][j];
    }
    if (m.triangles.empty()) ix[0] = ix[1] = ix[2] = 0;  // one degenerate triangle: never hit
    if (collect_) rtcSetGeometryIntersectFilterFunction(g, collect_filter);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(scene_, g, static_cast<unsigned>(k));  // the scene holds its own reference
  }
  // Embree builds the BVH with oneTBB tasks; here in an arena of this thread alone, so that no
  // other thread (one of the run's, waiting in its own parallel loop) runs one of them: oneTBB
  // 2021.8 read the build's task_group_context after Embree had freed it (ThreadSanitizer, twice,
  // Sensitivity.GeometryStudyThicknessDrivesTheDiskMass). A run's threads build their scenes side
  // by side; each BVH build is then serial.
  tbb::task_arena own_arena(1);
  own_arena.execute([this] { rtcCommitScene(scene_); });
  check(dev, "building the scene");
  scene.release();  // the object is whole: its destructor releases the scene
}

EmbreeScene::~EmbreeScene() {
  if (scene_) rtcReleaseScene(scene_);
}

void EmbreeScene::trace_all(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double merge_tol,
                            std::vector<Crossing>& out) const {
  POISE_INVARIANT(collect_, "EmbreeScene::trace_all needs a scene built with collect_all_hits");
  thread_local std::vector<std::pair<unsigned, unsigned>> hits;
  hits.clear();
  CollectContext ctx;
  rtcInitIntersectContext(&ctx.base);
  ctx.hits = &hits;
  RTCRayHit rh{};
  rh.ray.org_x = static_cast<float>(o.x());
  rh.ray.org_y = static_cast<float>(o.y());
  rh.ray.org_z = static_cast<float>(o.z());
  rh.ray.dir_x = static_cast<float>(d.x());
  rh.ray.dir_y = static_cast<float>(d.y());
  rh.ray.dir_z = static_cast<float>(d.z());
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &ctx.base, &rh);
  // A primitive can be offered twice (once per BVH leaf that references it).
  std::sort(hits.begin(), hits.end());
  hits.erase(std::unique(hits.begin(), hits.end()), hits.end());
  out.clear();
  for (const auto& [gid, pid] : hits) {
    const Mesh& m = meshes_[gid];
    const Eigen::Vector3d n = m.face_normal(pid);
    const double nd = n.dot(d);
    if (nd == 0.0) continue;  // grazing along the face: no crossing
    const double t = n.dot(m.vertices[m.triangles[pid][0]] - o) / nd;
    out.push_back({t, nd < 0 ? +1 : -1, gid, pid});
  }
  std::sort(out.begin(), out.end(),
            [](const Crossing& a, const Crossing& b) { return a.t < b.t || (a.t == b.t && a.sign < b.sign); });
  // Merge crossings of one ray through a shared edge or vertex: same mesh, same sign, (nearly)
  // the same t, triangles sharing a vertex. Coincident faces of different shells stay apart.
  auto adjacent = [&](const Crossing& a, const Crossing& b) {
    if (a.geom != b.geom) return false;
    const Triangle& ta = meshes_[a.geom].triangles[a.prim];
    const Triangle& tb = meshes_[b.geom].triangles[b.prim];
    for (auto i : ta) {
      for (auto j : tb) {
        if (i == j) return true;
      }
    }
    return false;
  };
  std::size_t w = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    bool dup = false;
    for (std::size_t j = w; j-- > 0;) {
      if (out[i].t - out[j].t > merge_tol) break;
      if (out[j].sign == out[i].sign && adjacent(out[i], out[j])) {
        dup = true;
        break;
      }
    }
    if (!dup) out[w++] = out[i];
  }
  out.resize(w);
}

}  // namespace poise::geometry
