#include "geometry/polygon_triangulation.h"

#include <algorithm>
#include <cstddef>

namespace poise::geometry {
namespace {

// Corner tests on the polygon projected along its normal's largest component.
class Projected {
 public:
  Projected(const std::vector<Eigen::Vector3d>& vertices, const std::vector<std::uint32_t>& polygon) {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();  // Newell's normal
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const Eigen::Vector3d& a = vertices[polygon[i]];
      const Eigen::Vector3d& b = vertices[polygon[(i + 1) % polygon.size()]];
      n += Eigen::Vector3d((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()),
                           (a.x() - b.x()) * (a.y() + b.y()));
    }
    int axis = 0;
    n.cwiseAbs().maxCoeff(&axis);
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    sign_ = n[axis] >= 0.0 ? 1.0 : -1.0;
    points_.reserve(polygon.size());
    for (const std::uint32_t i : polygon) points_.emplace_back(vertices[i][u], vertices[i][v]);
  }
  // Twice the signed area of (a, b, c), positive when it turns the polygon's way.
  double turn(std::size_t a, std::size_t b, std::size_t c) const {
    const Eigen::Vector2d ab = points_[b] - points_[a], ac = points_[c] - points_[a];
    return sign_ * (ab.x() * ac.y() - ab.y() * ac.x());
  }
  // A corner with area: not collinear to rounding (as mesh_needles.h's zero_area).
  bool convex(std::size_t a, std::size_t b, std::size_t c) const {
    const double l2 = std::max({(points_[b] - points_[a]).squaredNorm(), (points_[c] - points_[a]).squaredNorm(),
                                (points_[c] - points_[b]).squaredNorm()});
    return turn(a, b, c) > 1e-12 * l2;
  }
  // p in the closed triangle (a, b, c) and not at one of its corners.
  bool inside(std::size_t p, std::size_t a, std::size_t b, std::size_t c) const {
    const Eigen::Vector2d& q = points_[p];
    if (q == points_[a] || q == points_[b] || q == points_[c]) return false;
    return turn(a, b, p) >= 0.0 && turn(b, c, p) >= 0.0 && turn(c, a, p) >= 0.0;
  }

 private:
  std::vector<Eigen::Vector2d> points_;
  double sign_ = 1.0;
};

}  // namespace

std::vector<Triangle> triangulate_polygon(const std::vector<Eigen::Vector3d>& vertices,
                                          const std::vector<std::uint32_t>& polygon) {
  const std::size_t n = polygon.size();
  std::vector<Triangle> out;
  if (n < 3) return out;
  out.reserve(n - 2);
  if (n == 3) {
    out.push_back({polygon[0], polygon[1], polygon[2]});
    return out;
  }
  const Projected plane(vertices, polygon);
  std::vector<std::size_t> ring(n);  // positions in `polygon` still in the polygon
  for (std::size_t i = 0; i < n; ++i) ring[i] = i;
  // Bounded work: a polygon of thousands of corners that are hard to cut is fanned after
  // this many corner-in-triangle tests (a few milliseconds).
  constexpr std::size_t kMaxTests = 4'000'000;
  std::size_t i = 0, since_cut = 0, tests = 0;
  while (ring.size() > 3 && since_cut < ring.size()) {
    const std::size_t m = ring.size();
    const std::size_t a = ring[(i + m - 1) % m], b = ring[i], c = ring[(i + 1) % m];
    bool ear = plane.convex(a, b, c);
    for (std::size_t j = 0; ear && j < m; ++j) {
      const std::size_t p = ring[j];
      if (p != a && p != b && p != c && plane.inside(p, a, b, c)) ear = false;
    }
    tests += m;
    if (tests > kMaxTests) break;  // the rest is fanned
    if (ear) {
      out.push_back({polygon[a], polygon[b], polygon[c]});
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
      since_cut = 0;
      i = (i + ring.size() - 1) % ring.size();  // the corner before the one cut: it changed
    } else {
      i = (i + 1) % m;
      ++since_cut;
    }
  }
  // The rest (a triangle, or what no ear could be cut from), fanned from its current corner.
  const std::size_t m = ring.size(), s = i;
  for (std::size_t k = 1; k + 1 < m; ++k) {
    out.push_back({polygon[ring[s]], polygon[ring[(s + k) % m]], polygon[ring[(s + k + 1) % m]]});
  }
  return out;
}

}  // namespace poise::geometry
