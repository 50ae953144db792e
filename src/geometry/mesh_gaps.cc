#include "geometry/mesh_gaps.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace poise::geometry {
namespace {

constexpr std::size_t kMaxTests = 20'000'000;

double point_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double s = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + s * ab - p).norm();
}

struct Segment {
  Eigen::Vector3d a, b, mid;
  double half = 0.0;  // half its length
};

}  // namespace

Gap widest_gap(const Mesh& mesh, const std::vector<Edge>& open_edges) {
  Gap gap;
  gap.width_m = -1.0;  // none found
  std::vector<Segment> segs;
  segs.reserve(open_edges.size());
  double longest_half = 0.0;
  for (const Edge& e : open_edges) {
    const Eigen::Vector3d& a = mesh.vertices[e[0]];
    const Eigen::Vector3d& b = mesh.vertices[e[1]];
    segs.push_back({a, b, (a + b) / 2.0, (b - a).norm() / 2.0});
    longest_half = std::max(longest_half, segs.back().half);
  }
  // Sorted by the x of their middles: an edge farther in x than the best so far (plus both
  // half-lengths) cannot be nearer.
  std::sort(segs.begin(), segs.end(), [](const Segment& x, const Segment& y) {
    return x.mid.x() != y.mid.x()   ? x.mid.x() < y.mid.x()
           : x.mid.y() != y.mid.y() ? x.mid.y() < y.mid.y()
                                    : x.mid.z() < y.mid.z();
  });
  std::size_t tests = 0;
  for (std::size_t i = 0; i < segs.size() && tests < kMaxTests; ++i) {
    const Segment& e = segs[i];
    double best = std::numeric_limits<double>::infinity();
    auto look = [&](std::size_t j) {
      ++tests;
      const Segment& f = segs[j];
      best = std::min(best, std::max(point_to_segment(e.a, f.a, f.b), point_to_segment(e.b, f.a, f.b)));
    };
    auto reach = [&](std::size_t j) { return std::abs(segs[j].mid.x() - e.mid.x()) <= best + e.half + longest_half; };
    for (std::size_t j = i + 1; j < segs.size() && reach(j); ++j) look(j);
    for (std::size_t j = i; j-- > 0 && reach(j);) look(j);
    if (std::isfinite(best) && best >= gap.width_m) gap = {best, e.mid};
  }
  return gap;
}

}  // namespace poise::geometry
