#pragma once
/// RAII wrappers of Embree 3: one device per process (thread-safe, created on first use),
/// a committed scene of triangle meshes that keeps, beside Embree's single-precision copy,
/// the double-precision meshes so hits can be refined exactly.
///
/// A committed scene is immutable and safe to trace from any number of threads.
#include <embree3/rtcore.h>

#include <memory>
#include <vector>

#include "geometry/mesh.h"

namespace poise::geometry {

/// The process's Embree device (created once; errors become poise::Error).
RTCDevice embree_device();

/// Flush-to-zero and denormals-are-zero on the calling thread while it traces, as Embree
/// recommends; the thread's previous floating-point mode comes back at the end of the scope,
/// so other work on a pooled thread is unaffected.
class EmbreeThreadFlags {
 public:
  EmbreeThreadFlags();
  ~EmbreeThreadFlags();
  EmbreeThreadFlags(const EmbreeThreadFlags&) = delete;
  EmbreeThreadFlags& operator=(const EmbreeThreadFlags&) = delete;

 private:
  unsigned int saved_;
};

class EmbreeScene {
 public:
  /// Builds the BVH over the meshes (geomID k = meshes[k]). `collect_all_hits` installs an
  /// intersection filter that records every hit instead of the nearest (see trace_all()).
  explicit EmbreeScene(std::vector<Mesh> meshes, bool collect_all_hits = false);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  RTCScene handle() const { return scene_; }
  const std::vector<Mesh>& meshes() const { return meshes_; }
  const Mesh& mesh(unsigned geom_id) const { return meshes_[geom_id]; }

  /// One surface crossing along a ray.
  struct Crossing {
    double t = 0.0;  ///< distance along the (unit) direction, refined in double precision
    int sign = 0;    ///< +1 entering material (normal against the ray), -1 leaving
    unsigned geom = 0, prim = 0;
  };
  /// Every crossing of the ray o + t d (t > 0), sorted by t, duplicates at shared edges and
  /// vertices merged (same mesh and sign, within `merge_tol`, triangles sharing a vertex);
  /// coincident faces of different shells are kept apart. Needs collect_all_hits.
  void trace_all(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double merge_tol,
                 std::vector<Crossing>& out) const;

 private:
  std::vector<Mesh> meshes_;
  RTCScene scene_ = nullptr;
  bool collect_ = false;
};

}  // namespace poise::geometry
