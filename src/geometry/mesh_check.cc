#include "geometry/mesh_check.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "core/format.h"
#include "geometry/mesh_gaps.h"
#include "geometry/mesh_needles.h"

namespace poise::geometry {
namespace {

// An edge of a triangle: key = lo << 32 | hi (vertex indices, lo < hi); sorted by key, then
// triangle, so equal edges are adjacent and listed from their lowest triangle.
struct HalfEdge {
  std::uint64_t key;
  std::uint32_t tri;
  bool forward;  // the triangle runs lo -> hi
};

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), std::size_t{0}); }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);  // the root is the lowest triangle
  }

 private:
  std::vector<std::size_t> parent_;
};

void note(Defect& d, std::size_t tri) {
  d.first_triangle = d.count == 0 ? tri : std::min(d.first_triangle, tri);
  ++d.count;
}

std::string plural(std::size_t n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// Solid angle of triangle (a, b, c) seen from the origin (Van Oosterom and Strackee 1983).
double solid_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double num = a.dot(b.cross(c));
  const double den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
  return 2.0 * std::atan2(num, den);
}

}  // namespace

namespace {

// A triangle's vertices from its smallest index on, keeping its winding: equal for the same
// face in the same winding, different for the face turned over.
std::array<std::uint32_t, 3> winding_key(const Triangle& t) {
  const int m = t[0] < t[1] ? (t[0] < t[2] ? 0 : 2) : (t[1] < t[2] ? 1 : 2);
  return {t[m], t[(m + 1) % 3], t[(m + 2) % 3]};
}

// Indices of the triangles that repeat an earlier one (same vertices, same winding), ascending.
std::vector<std::size_t> repeated_triangles(const Mesh& mesh) {
  std::vector<std::pair<std::array<std::uint32_t, 3>, std::size_t>> keys(mesh.triangles.size());
  for (std::size_t k = 0; k < keys.size(); ++k) keys[k] = {winding_key(mesh.triangles[k]), k};
  std::sort(keys.begin(), keys.end());
  std::vector<std::size_t> repeats;
  for (std::size_t k = 1; k < keys.size(); ++k) {
    if (keys[k].first == keys[k - 1].first) repeats.push_back(keys[k].second);
  }
  std::sort(repeats.begin(), repeats.end());
  return repeats;
}

}  // namespace

std::size_t drop_duplicate_triangles(Mesh& mesh) {
  const std::vector<std::size_t> repeats = repeated_triangles(mesh);
  remove_triangles(mesh, repeats);
  return repeats.size();
}

namespace {

// The duplicates as an error (their count and the first).
void note_repeats(const Mesh& mesh, MeshCheck& r) {
  const std::vector<std::size_t> repeats = repeated_triangles(mesh);
  if (repeats.empty()) return;
  r.duplicate_triangles = {repeats.size(), repeats.front()};
  r.errors.push_back(mesh.name + ": " + plural(repeats.size(), "triangle repeats", "triangles repeat") +
                     " another with the same vertices and winding, the first is " +
                     describe_triangle(mesh, repeats.front()) +
                     ": a face or shell exported twice would count its volume twice; remove the copies in CAD, or "
                     "pass --drop-duplicates to drop them");
}

}  // namespace

namespace {

// What the edge pass finds besides the counts in MeshCheck: which triangles take part, the
// two-triangle links for the orientation walk, the shells, the open edges.
struct Surface {
  explicit Surface(std::size_t n) : usable(n, 1), links(n), link_count(n, 0), shells(n) {}
  struct Link {
    std::uint32_t other;
    bool same_way;  // both triangles run the shared edge the same way: one of them is flipped
  };
  std::vector<char> usable;  // not a repeated vertex
  // At most three two-triangle edges per triangle: fixed slots, no allocation per triangle.
  std::vector<std::array<Link, 3>> links;
  std::vector<std::uint8_t> link_count;
  UnionFind shells;
  std::vector<Edge> open;
  std::vector<std::size_t> shell_of;
};

// Every triangle's three edges, sorted (see HalfEdge); degenerate and zero-area ones noted.
std::vector<HalfEdge> half_edges(const Mesh& mesh, MeshCheck& r, Surface& s) {
  std::vector<HalfEdge> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    const Triangle& t = mesh.triangles[k];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      note(r.degenerate_triangles, k);
      s.usable[k] = 0;
      continue;
    }
    if (zero_area(mesh, k)) note(r.zero_area_triangles, k);
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t p = t[e], q = t[(e + 1) % 3];
      const std::uint64_t key = static_cast<std::uint64_t>(std::min(p, q)) << 32 | std::max(p, q);
      edges.push_back({key, static_cast<std::uint32_t>(k), p < q});
    }
  }
  std::sort(edges.begin(), edges.end(),
            [](const HalfEdge& x, const HalfEdge& y) { return x.key != y.key ? x.key < y.key : x.tri < y.tri; });
  return edges;
}

// Open, shared and non-manifold edges; links across two-triangle edges; shells joined.
void pair_edges(const std::vector<HalfEdge>& edges, MeshCheck& r, Surface& s) {
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    const std::size_t uses = j - i;
    const std::size_t first = edges[i].tri;  // sorted by triangle within the edge
    if (uses == 1) {
      note(r.open_edges, first);
      s.open.push_back({static_cast<std::uint32_t>(edges[i].key >> 32), static_cast<std::uint32_t>(edges[i].key)});
    } else if (uses > 2) {
      // Closed solids meeting along an edge (touching bodies in one export) use it as often
      // in each direction: the surface still bounds a region. Otherwise it is not manifold.
      std::size_t forward = 0;
      for (std::size_t k = i; k < j; ++k) forward += edges[k].forward;
      note(2 * forward == uses ? r.shared_edges : r.non_manifold_edges, first);
    } else {
      const bool same = edges[i].forward == edges[i + 1].forward;
      s.links[edges[i].tri][s.link_count[edges[i].tri]++] = {edges[i + 1].tri, same};
      s.links[edges[i + 1].tri][s.link_count[edges[i + 1].tri]++] = {edges[i].tri, same};
    }
    for (std::size_t k = i + 1; k < j; ++k) s.shells.unite(edges[i].tri, edges[k].tri);
    i = j;
  }
}

// Shells in order of their lowest triangle (the union-find root), with their signed volumes.
void collect_shells(const Mesh& mesh, MeshCheck& r, Surface& s) {
  const std::size_t n = mesh.triangles.size();
  s.shell_of.assign(n, 0);
  std::vector<std::size_t> index_of_root(n, std::numeric_limits<std::size_t>::max());
  for (std::size_t k = 0; k < n; ++k) {
    if (!s.usable[k]) continue;
    const std::size_t root = s.shells.find(k);
    if (index_of_root[root] == std::numeric_limits<std::size_t>::max()) {
      index_of_root[root] = r.shells.size();
      r.shells.push_back({root, 0, 0.0, false});
    }
    Shell& shell = r.shells[index_of_root[root]];
    s.shell_of[k] = index_of_root[root];
    const Triangle& t = mesh.triangles[k];
    shell.volume_m3 += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]])) / 6.0;
    ++shell.triangles;
  }
  for (const Shell& shell : r.shells) r.volume_m3 += shell.volume_m3;
}

// Orientation: walk each patch (triangles joined by two-triangle edges) from its first
// triangle, flipping the parity across every edge run the same way; the triangles of the
// smaller parity class are the flipped ones.
void walk_orientation(std::size_t n, MeshCheck& r, const Surface& s) {
  std::vector<signed char> parity(n, -1);
  for (std::size_t start = 0; start < n; ++start) {
    if (!s.usable[start] || parity[start] >= 0) continue;
    std::vector<std::uint32_t> stack{static_cast<std::uint32_t>(start)}, members;
    parity[start] = 0;
    bool orientable = true;
    while (!stack.empty()) {
      const std::uint32_t k = stack.back();
      stack.pop_back();
      members.push_back(k);
      for (std::uint8_t j = 0; j < s.link_count[k]; ++j) {
        const Surface::Link& l = s.links[k][j];
        const signed char want = static_cast<signed char>(parity[k] ^ (l.same_way ? 1 : 0));
        if (parity[l.other] < 0) {
          parity[l.other] = want;
          stack.push_back(l.other);
        } else if (parity[l.other] != want) {
          orientable = false;
        }
      }
    }
    std::size_t ones = 0;
    for (const auto k : members) ones += parity[k];
    const int minority = 2 * ones <= members.size() ? 1 : 0;
    for (const auto k : members) {
      if (orientable && parity[k] == minority) note(r.flipped_triangles, k);
    }
    if (!orientable) note(r.non_orientable_shells, start);
  }
}

// "not closed: ..." with where the first open edge is and how wide the widest gap.
std::string open_edges_error(const Mesh& mesh, const MeshCheck& r, const std::vector<Edge>& open) {
  std::string msg = mesh.name + ": not closed: " + plural(r.open_edges.count, "open edge", "open edges") +
                    ", the first at " + describe_triangle(mesh, r.open_edges.first_triangle);
  const Gap gap = widest_gap(mesh, open);
  if (gap.width_m < 0.0) return msg;
  msg +=
      "; the widest gap is " + describe_length(mesh, gap.width_m) + " across, near " + describe_point(mesh, gap.where);
  // A crack far narrower than the part: welding its sides would close it.
  if (gap.width_m == 0.0) {
    msg += " (vertices that coincide but are not shared: a weld joins them, --weld 0 keeps them apart)";
  } else if (gap.width_m <= 1e-3 * mesh.bounds().diagonal().norm()) {
    msg += " (a crack: --weld \"" + describe_length(mesh, 2.0 * gap.width_m) + "\" would join its sides)";
  }
  return msg;
}

// One sentence per topological defect; zero-area triangles count as degenerate only where
// the surface is not closed (in a closed one they fill T-junctions and add no volume).
void topology_errors(const Mesh& mesh, MeshCheck& r, const Surface& s) {
  const std::string& name = mesh.name;
  if (r.open_edges.count) r.errors.push_back(open_edges_error(mesh, r, s.open));
  if (r.non_manifold_edges.count) {
    r.errors.push_back(name + ": not manifold: " + plural(r.non_manifold_edges.count, "edge shared", "edges shared") +
                       " by three or more triangles that do not pair up (as many running each way), the first at " +
                       describe_triangle(mesh, r.non_manifold_edges.first_triangle));
  }
  if (r.flipped_triangles.count) {
    r.errors.push_back(
        name + ": inconsistent orientation: " + plural(r.flipped_triangles.count, "triangle is", "triangles are") +
        " flipped against their neighbours (their normals point the other way), the first is " +
        describe_triangle(mesh, r.flipped_triangles.first_triangle));
  }
  if (r.non_orientable_shells.count) {
    r.errors.push_back(name + ": not orientable: " + plural(r.non_orientable_shells.count, "shell has", "shells have") +
                       " no consistent inside (a one-sided surface), the first from " +
                       describe_triangle(mesh, r.non_orientable_shells.first_triangle));
  }
  const bool closed = !r.open_edges.count && !r.non_manifold_edges.count && !r.flipped_triangles.count &&
                      !r.non_orientable_shells.count;
  Defect degenerate = r.degenerate_triangles;
  if (!closed && r.zero_area_triangles.count) {
    degenerate.first_triangle = degenerate.count
                                    ? std::min(degenerate.first_triangle, r.zero_area_triangles.first_triangle)
                                    : r.zero_area_triangles.first_triangle;
    degenerate.count += r.zero_area_triangles.count;
  }
  if (degenerate.count) {
    r.errors.push_back(name + ": " + plural(degenerate.count, "degenerate triangle", "degenerate triangles") +
                       " (a repeated vertex or zero area), the first is " +
                       describe_triangle(mesh, degenerate.first_triangle));
  }
  r.degenerate_triangles = degenerate;
}

// A shell of negative volume is a cavity if a point just inside it lies inside the other
// shells (winding number >= 1 from their solid angles), else it is inside out.
void judge_shell_signs(const Mesh& mesh, MeshCheck& r, const Surface& s) {
  const std::size_t n = mesh.triangles.size();
  for (std::size_t i = 0; i < r.shells.size(); ++i) {
    Shell& shell = r.shells[i];
    if (shell.volume_m3 >= 0.0) continue;
    std::size_t best = shell.first_triangle;
    Eigen::AlignedBox3d box;
    for (std::size_t k = 0; k < n; ++k) {
      if (!s.usable[k] || s.shell_of[k] != i) continue;
      if (mesh.face_normal(k).squaredNorm() > mesh.face_normal(best).squaredNorm()) best = k;
      for (int e = 0; e < 3; ++e) box.extend(mesh.vertices[mesh.triangles[k][e]]);
    }
    const Triangle& t = mesh.triangles[best];
    const Eigen::Vector3d centroid = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0;
    // The normals of a negative shell point into the region it encloses.
    const Eigen::Vector3d p = centroid + 1e-6 * box.diagonal().norm() * mesh.face_normal(best).normalized();
    double omega = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      if (!s.usable[k] || s.shell_of[k] == i) continue;
      const Triangle& q = mesh.triangles[k];
      omega += solid_angle(mesh.vertices[q[0]] - p, mesh.vertices[q[1]] - p, mesh.vertices[q[2]] - p);
    }
    if (omega / (4.0 * std::numbers::pi) > 0.5) {
      shell.cavity = true;
      continue;
    }
    r.errors.push_back(mesh.name + ": shell " + std::to_string(i + 1) + " of " + std::to_string(r.shells.size()) +
                       " (" + plural(shell.triangles, "triangle", "triangles") + " from " +
                       describe_triangle(mesh, shell.first_triangle) + ") has negative volume (" +
                       describe_volume(mesh, shell.volume_m3) +
                       ") and lies inside no other shell: it is inside out (its normals point inwards)");
  }
}

}  // namespace

MeshCheck check_mesh(const Mesh& mesh) {
  MeshCheck r;
  note_repeats(mesh, r);
  Surface s(mesh.triangles.size());
  pair_edges(half_edges(mesh, r, s), r, s);
  collect_shells(mesh, r, s);
  walk_orientation(mesh.triangles.size(), r, s);
  topology_errors(mesh, r, s);
  // Signs mean something only on a closed, consistently oriented surface.
  if (!r.errors.empty()) return r;
  judge_shell_signs(mesh, r, s);
  if (r.errors.empty() && !(r.volume_m3 > 0.0)) {
    r.errors.push_back(mesh.name + ": total volume " + describe_volume(mesh, r.volume_m3) + " is not positive");
  }
  return r;
}

MeshCheck require_valid_mesh(const Mesh& mesh) {
  MeshCheck r = check_mesh(mesh);
  if (!r.ok()) {
    std::string msg;
    for (const auto& e : r.errors) msg += (msg.empty() ? "" : "\n") + e;
    throw MeshCheckError(msg);
  }
  return r;
}

std::string unit_warning(const Mesh& mesh, const std::string& unit, double unit_m) {
  if (mesh.vertices.empty()) return "";
  const double side = mesh.bounds().sizes().maxCoeff();  // m
  constexpr double kLargest = 5.0, kSmallest = 0.5e-3;
  if (side <= kLargest && side >= kSmallest) return "";
  const double in_file = side / unit_m;  // the number written in the file
  std::string msg = mesh.name + ": " + significant(in_file) + " " + unit +
                    " across (the largest side of its bounding box), " + (side > kLargest ? "large" : "small") +
                    " for a part: is --unit " + unit + " right?";
  static const std::pair<const char*, double> kUnits[] = {{"mm", 1e-3}, {"m", 1.0}, {"in", 0.0254}, {"cm", 1e-2}};
  for (const auto& [name, size] : kUnits) {
    const double other = in_file * size;
    if (name != unit && other <= kLargest && other >= kSmallest) {
      msg += std::string(" In ") + name + " it would be " + significant(in_file) + " " + name + " across.";
      break;
    }
  }
  return msg;
}

}  // namespace poise::geometry
