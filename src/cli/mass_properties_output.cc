#include "cli/mass_properties_output.h"

#include <cmath>
#include <string>

#include "core/format.h"
#include "geometry/rigid_body_inertia.h"

namespace poise::cli::mass_properties {
using geometry::MeshPart;
using geometry::MeshParts;
using geometry::RaycastDifference;
namespace {

nlohmann::json vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json properties_json(const geometry::MassProperties& p, double volume, const RaycastDifference& d, int rays) {
  const geometry::PrincipalAxes pa = geometry::principal_axes(p.inertia);
  nlohmann::json inertia = nlohmann::json::array(), axes = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) {
    inertia.push_back(vec(p.inertia.row(i).transpose()));
    axes.push_back(vec(pa.axes.col(i)));
  }
  return {{"volume_m3", volume},
          {"mass_kg", p.mass},
          {"centre_of_mass_m", vec(p.com)},
          {"inertia_kg_m2", inertia},
          {"principal_moments_kg_m2", vec(pa.moments)},
          {"principal_axes", axes},
          {"raycast_check",
           {{"rays_per_side", rays},
            {"mass_relative_difference", d.mass},
            {"centre_of_mass_difference_m", d.com_m},
            {"inertia_relative_difference", d.inertia}}}};
}

void print_properties(const geometry::MassProperties& p, double volume, const RaycastDifference& d,
                      const std::string& unit, double unit_m, std::ostream& out) {
  // Rounding residue (1e-17 mm where symmetry puts a zero) is shown as 0.
  auto clean = [](double v, double scale) { return std::abs(v) <= 1e-12 * scale ? 0.0 : v; };
  const double size = std::sqrt(std::abs(p.inertia.trace()) / std::max(std::abs(p.mass), 1e-300));
  const Eigen::Vector3d c = (p.com / unit_m).unaryExpr([&](double v) { return clean(v, size / unit_m); });
  const Eigen::Matrix3d inertia = p.inertia.unaryExpr([&](double v) { return clean(v, p.inertia.norm()); });
  geometry::PrincipalAxes pa = geometry::principal_axes(p.inertia);
  pa.axes = pa.axes.unaryExpr([&](double v) { return clean(v, 1e3); });
  out << "  volume          " << significant(volume, 6) << " m^3 ("
      << significant(volume / (unit_m * unit_m * unit_m), 6) << " " << unit << "^3)\n";
  out << "  mass            " << significant(p.mass, 6) << " kg\n";
  out << fmt::format("  centre of mass  ({:.6g}, {:.6g}, {:.6g}) {}\n", c.x(), c.y(), c.z(), unit);
  out << "  inertia about the centre of mass, kg m^2 (Ixx Ixy Ixz / Iyx Iyy Iyz / Izx Izy Izz):\n";
  for (int i = 0; i < 3; ++i) {
    out << fmt::format("    {:>14.6e} {:>14.6e} {:>14.6e}\n", inertia(i, 0), inertia(i, 1), inertia(i, 2));
  }
  out << "  principal moments and axes (in the mesh's frame):\n";
  for (int k = 0; k < 3; ++k) {
    out << fmt::format("    I{} = {:.6e} kg m^2 about ({:+.6f}, {:+.6f}, {:+.6f})\n", k + 1, pa.moments[k],
                       pa.axes(0, k), pa.axes(1, k), pa.axes(2, k));
  }
  out << "  ray-cast check: mass " << significant(100.0 * d.mass, 3) << " %, centre of mass "
      << significant(d.com_m / unit_m, 3) << " " << unit << ", inertia " << significant(100.0 * d.inertia, 3)
      << " % from the exact figures\n";
}

std::size_t cavities_of(const MeshPart& p) {
  std::size_t cavities = 0;
  for (const auto& s : p.check.shells) cavities += s.cavity;
  return cavities;
}

}  // namespace

nlohmann::json to_json(const MeshParts& c) {
  nlohmann::json out = properties_json(c.total, c.volume, c.total_diff, c.rays);
  if (c.parts.size() > 1) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& p : c.parts) {
      nlohmann::json j =
          properties_json(p.exact, p.check.volume_m3, geometry::raycast_difference(p.exact, p.raycast), c.rays);
      j["file"] = p.file;
      j["unit"] = p.unit;
      j["density_kg_m3"] = p.density;
      j["triangles"] = p.mesh.triangles.size();
      j["shells"] = p.check.shells.size();
      j["cavities"] = cavities_of(p);
      list.push_back(std::move(j));
    }
    out["parts"] = std::move(list);
  }
  return out;
}

void print_text(const MeshParts& c, std::ostream& out) {
  for (const auto& p : c.parts) {
    const std::size_t cavities = cavities_of(p);
    out << p.file << " (" << p.unit << ", " << significant(p.density, 6) << " kg/m^3): " << p.mesh.triangles.size()
        << " triangles, " << p.check.shells.size() << (p.check.shells.size() == 1 ? " shell" : " shells");
    if (cavities) out << " (" << cavities << (cavities == 1 ? " cavity" : " cavities") << ")";
    out << ", closed and consistently oriented\n";
    print_properties(p.exact, p.check.volume_m3, geometry::raycast_difference(p.exact, p.raycast), p.unit, p.unit_m,
                     out);
    out << '\n';
  }
  if (c.parts.size() > 1) {
    out << "assembly of " << c.parts.size() << " parts (parallel-axis sum):\n";
    print_properties(c.total, c.volume, c.total_diff, c.unit, c.unit_m, out);
  }
}

}  // namespace poise::cli::mass_properties
