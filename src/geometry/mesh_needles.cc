#include "geometry/mesh_needles.h"

#include <algorithm>
#include <cstdint>
#include <unordered_map>

#include "geometry/mesh_text.h"

namespace poise::geometry {
namespace {

// The needles on one undirected edge and their balance (+1 for each running lo -> hi, -1 for
// each running hi -> lo).
struct EdgeUse {
  int balance = 0;
  std::vector<std::uint32_t> needles;
};

std::uint64_t edge_key(std::uint32_t p, std::uint32_t q) {
  return static_cast<std::uint64_t>(std::min(p, q)) << 32 | std::max(p, q);
}

}  // namespace

bool zero_area(const Mesh& mesh, std::size_t k) {
  const Triangle& t = mesh.triangles[k];
  if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return true;
  const Eigen::Vector3d& a = mesh.vertices[t[0]];
  const Eigen::Vector3d& b = mesh.vertices[t[1]];
  const Eigen::Vector3d& c = mesh.vertices[t[2]];
  const double lmax2 = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
  return mesh.face_normal(k).norm() <= 1e-12 * lmax2;
}

std::vector<std::size_t> unneeded_needles(const Mesh& mesh) {
  std::vector<std::uint32_t> needles;
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    if (zero_area(mesh, k)) needles.push_back(static_cast<std::uint32_t>(k));
  }
  if (needles.empty()) return {};
  std::unordered_map<std::uint64_t, EdgeUse> edges;
  for (const std::uint32_t k : needles) {
    const Triangle& t = mesh.triangles[k];
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t p = t[e], q = t[(e + 1) % 3];
      if (p == q) continue;  // no edge
      EdgeUse& use = edges[edge_key(p, q)];
      use.balance += p < q ? 1 : -1;
      use.needles.push_back(k);
    }
  }
  // Keep every needle on an edge that does not pair up among the candidates; keeping one
  // changes its edges' balance, so its neighbours are judged again.
  std::unordered_map<std::uint32_t, char> candidate;
  for (const std::uint32_t k : needles) candidate[k] = 1;
  std::vector<std::uint32_t> work(needles.rbegin(), needles.rend());
  while (!work.empty()) {
    const std::uint32_t k = work.back();
    work.pop_back();
    if (!candidate[k]) continue;
    const Triangle& t = mesh.triangles[k];
    bool paired = true;
    for (int e = 0; e < 3 && paired; ++e) {
      if (t[e] != t[(e + 1) % 3]) paired = edges[edge_key(t[e], t[(e + 1) % 3])].balance == 0;
    }
    if (paired) continue;
    candidate[k] = 0;
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t p = t[e], q = t[(e + 1) % 3];
      if (p == q) continue;
      EdgeUse& use = edges[edge_key(p, q)];
      use.balance -= p < q ? 1 : -1;
      // An edge that pairs up again had its other needles kept already, or still to judge.
      if (use.balance != 0) work.insert(work.end(), use.needles.begin(), use.needles.end());
    }
  }
  std::vector<std::size_t> out;
  for (const std::uint32_t k : needles) {
    if (candidate[k]) out.push_back(k);
  }
  return out;
}

NeedleReport drop_needles(Mesh& mesh) {
  NeedleReport r;
  const std::vector<std::size_t> drop = unneeded_needles(mesh);
  if (drop.empty()) return r;
  r.dropped = drop.size();
  r.first = describe_triangle(mesh, drop.front());
  remove_triangles(mesh, drop);
  return r;
}

}  // namespace poise::geometry
