#pragma once
// Private to geometry/: merges a mesh's equal vertex coordinates as they are read
// (mesh_io.cc's STL readers).
#include <array>
#include <cstdint>
#include <cstring>
#include <unordered_map>

#include <Eigen/Core>

#include "geometry/mesh.h"

namespace poise::geometry {

// Merges equal coordinates (STL stores every triangle's three vertices).
class VertexWelder {
 public:
  explicit VertexWelder(Mesh& mesh) : mesh_(mesh) {}
  /// A closed mesh of n triangles has about n/2 vertices.
  void reserve(std::size_t triangles) {
    index_.reserve(triangles / 2 + 16);
    mesh_.vertices.reserve(triangles / 2 + 16);
  }
  std::uint32_t add(const Eigen::Vector3d& v) {
    // + 0.0 turns -0.0 into 0.0, so equal coordinates have equal bits for the hash.
    const auto [it, inserted] =
        index_.try_emplace({v.x() + 0.0, v.y() + 0.0, v.z() + 0.0}, static_cast<std::uint32_t>(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.push_back(v);
    return it->second;
  }

 private:
  Mesh& mesh_;
  struct Hash {
    std::size_t operator()(const std::array<double, 3>& p) const {
      std::uint64_t h = 0x9e3779b97f4a7c15ull;
      for (double c : p) {
        std::uint64_t b;
        std::memcpy(&b, &c, 8);
        h = (h ^ b) * 0xff51afd7ed558ccdull;
        h ^= h >> 32;
      }
      return static_cast<std::size_t>(h);
    }
  };
  std::unordered_map<std::array<double, 3>, std::uint32_t, Hash> index_;
};

}  // namespace poise::geometry
