#include "cli/mass_properties_command.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/units.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_io.h"
#include "geometry/rigid_body_inertia.h"

namespace poise::cli {
namespace {

const char* kMassPropertiesHelp = R"(What it does:
  Reads each mesh (STL binary or ASCII, OBJ; the lengths in --unit), checks it, and gives
  its volume, mass, centre of mass, inertia tensor about the centre of mass, and principal
  moments and axes. With several meshes: each part, then the assembly (parallel-axis sum).
  Several closed shells in one file are one part; a shell wound inwards inside another is
  an internal cavity and removes material.

  Exact to the mesh: each triangle (a, b, c) and the origin span a signed tetrahedron,
  V = a.(b x c)/6, int x dV = V (a+b+c)/4, int x x^T dV = V/20 (aa^T + bb^T + cc^T + ss^T)
  with s = a+b+c (divergence theorem). Checked by an independent integration: parallel
  rays (Embree) through a grid of --rays cells per side, each segment inside the part
  integrated exactly, the rays along the part's thinnest side; the relative differences
  are printed. A faceted export of a round part is a polygon: its figures are the
  polygon's, not the drawing's circle's.

Checks (a bad mesh is refused with exit status 2, naming the file, what is wrong, where):
  open edges (not closed), edges of three or more triangles that do not pair up (not
  manifold; solids touching along an edge or a face pass), triangles flipped against
  their neighbours, degenerate triangles, a shell of negative volume that is inside no
  other shell (inside out), shells that overlap (found by the check's rays), triangles
  that repeat another (a face or shell exported twice: --drop-duplicates removes them and
  says how many), and a ray-cast mass more than 2 % from the exact one.
  A part larger than 5 m or smaller than 0.5 mm is a warning: --unit is probably wrong.

Examples:
  poise mass-properties rotor_disk.stl --unit mm --density "2700 kg/m^3"
  poise mass-properties disk.stl hub.obj screw.stl --unit mm \
      --density "2700 kg/m^3" --density "2700 kg/m^3" --density "7850 kg/m^3" --json

--json prints one object: volume_m3, mass_kg, centre_of_mass_m [x, y, z], inertia_kg_m2
(3 x 3, about the centre of mass), principal_moments_kg_m2 (ascending),
principal_axes (one unit vector per moment, right-handed), raycast_check (relative
differences of the independent integration) and, with several meshes, parts (one such
object per mesh, with file, unit, density_kg_m3, triangles, shells and cavities).
Exit status: 0 success, 2 bad mesh or argument (nothing computed), 1 other failure.
)";

using units::kDensity;
// Ray cast against exact mass, relative: thin members at 256 rays agree to about 1 %.
constexpr double kRaycastTolerance = 0.02;

struct Part {
  std::string file;
  double density = 0.0;  // kg/m^3
  geometry::Mesh mesh;
  geometry::MeshCheck check;
  geometry::MassProperties exact, raycast;
  std::size_t dropped = 0;  // duplicate triangles removed (--drop-duplicates)
  geometry::WeldReport weld;
  std::string unit;     // the length unit the file was exported in
  double unit_m = 1.0;  // its size
};

struct RaycastDifference {
  double mass = 0.0;     // relative
  double com_m = 0.0;    // distance between the centres of mass
  double inertia = 0.0;  // |I_ray - I| / |I| (Frobenius)
};

RaycastDifference difference(const geometry::MassProperties& exact, const geometry::MassProperties& ray) {
  RaycastDifference d;
  d.mass = std::abs(ray.mass - exact.mass) / exact.mass;
  d.com_m = (ray.com - exact.com).norm();
  d.inertia = (ray.inertia - exact.inertia).norm() / exact.inertia.norm();
  return d;
}

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

std::string g(double v, int digits = 6) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
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
  char line[200];
  out << "  volume          " << g(volume) << " m^3 (" << g(volume / (unit_m * unit_m * unit_m)) << " " << unit
      << "^3)\n";
  out << "  mass            " << g(p.mass) << " kg\n";
  std::snprintf(line, sizeof line, "  centre of mass  (%.6g, %.6g, %.6g) %s\n", c.x(), c.y(), c.z(), unit.c_str());
  out << line;
  out << "  inertia about the centre of mass, kg m^2 (Ixx Ixy Ixz / Iyx Iyy Iyz / Izx Izy Izz):\n";
  for (int i = 0; i < 3; ++i) {
    std::snprintf(line, sizeof line, "    %14.6e %14.6e %14.6e\n", inertia(i, 0), inertia(i, 1), inertia(i, 2));
    out << line;
  }
  out << "  principal moments and axes (in the mesh's frame):\n";
  for (int k = 0; k < 3; ++k) {
    std::snprintf(line, sizeof line, "    I%d = %.6e kg m^2 about (%+.6f, %+.6f, %+.6f)\n", k + 1, pa.moments[k],
                  pa.axes(0, k), pa.axes(1, k), pa.axes(2, k));
    out << line;
  }
  out << "  ray-cast check: mass " << g(100.0 * d.mass, 3) << " %, centre of mass " << g(d.com_m / unit_m, 3) << " "
      << unit << ", inertia " << g(100.0 * d.inertia, 3) << " % from the exact figures\n";
}

[[noreturn]] void refuse(const std::string& what) { throw geometry::MeshCheckError(what); }

double unit_size(const std::string& unit) {
  if (unit == "mm") return 1e-3;
  if (unit == "cm") return 1e-2;
  if (unit == "m") return 1.0;
  if (unit == "in") return 0.0254;
  if (unit.empty()) {
    refuse(
        "--unit is required: the length unit the mesh was exported in (mm, cm, m or in); STL and OBJ files do "
        "not say");
  }
  refuse("--unit '" + unit + "': expected mm, cm, m or in (the length unit the mesh was exported in)");
}

struct Options {
  std::vector<std::string> meshes;
  std::vector<std::string> units;  // once for all meshes, or once per mesh
  std::vector<std::string> densities;
  std::string rays = "256";
  bool json = false;
  bool drop_duplicates = false;
  std::string weld;  // a length with its unit, "0" for none; "" = the default, relative to the part
  std::vector<std::string> extras;  // arguments CLI11 did not recognise
};

// --rays as a number from 8 to 4096, or -1.
int rays_per_side(const Options& opt) {
  int n = 0;
  const char* end = opt.rays.data() + opt.rays.size();
  const auto [p, ec] = std::from_chars(opt.rays.data(), end, n);
  return ec == std::errc() && p == end && n >= 8 && n <= 4096 ? n : -1;
}

std::vector<Part> read_parts(const Options& opt) {
  if (opt.meshes.empty()) refuse("no mesh given: poise mass-properties MESH... --unit mm --density \"2700 kg/m^3\"");
  if (opt.units.size() > 1 && opt.units.size() != opt.meshes.size()) {
    refuse("--unit given " + std::to_string(opt.units.size()) + " times for " + std::to_string(opt.meshes.size()) +
           " meshes: give one for all, or one per mesh in their order");
  }
  if (opt.densities.empty()) refuse("--density is required, e.g. --density \"2700 kg/m^3\" (aluminium)");
  if (opt.densities.size() != 1 && opt.densities.size() != opt.meshes.size()) {
    refuse("--density given " + std::to_string(opt.densities.size()) + " times for " +
           std::to_string(opt.meshes.size()) + " meshes: give one for all, or one per mesh in their order");
  }
  if (!opt.extras.empty()) {
    refuse("unknown argument '" + opt.extras.front() + "' (see poise mass-properties --help)");
  }
  if (rays_per_side(opt) < 0)
    refuse("--rays " + opt.rays + ": expected a whole number from 8 to 4096 (rays across the part)");
  double weld_m = -1.0;  // the default
  if (!opt.weld.empty()) {
    try {
      weld_m = opt.weld == "0" ? 0.0 : units::parse_as(opt.weld, units::kLength);
    } catch (const Error& e) {
      refuse("--weld \"" + opt.weld + "\": " + e.what());
    }
    if (!(weld_m >= 0.0) || !std::isfinite(weld_m)) refuse("--weld \"" + opt.weld + "\": expected a length >= 0, e.g. \"0.0001 mm\"");
  }
  std::vector<Part> parts;
  for (std::size_t i = 0; i < opt.meshes.size(); ++i) {
    Part p;
    p.file = opt.meshes[i];
    p.unit = opt.units.empty() ? std::string() : opt.units.size() == 1 ? opt.units[0] : opt.units[i];
    p.unit_m = unit_size(p.unit);
    const std::string& dtext = opt.densities.size() == 1 ? opt.densities[0] : opt.densities[i];
    try {
      p.density = units::parse_as(dtext, kDensity);
    } catch (const Error& e) {
      refuse("--density \"" + dtext + "\": " + e.what());
    }
    if (!(p.density > 0.0) || !std::isfinite(p.density)) {
      refuse("--density \"" + dtext + "\": expected a positive density, e.g. \"2700 kg/m^3\"");
    }
    std::error_code ec;
    if (!std::filesystem::is_regular_file(p.file, ec)) refuse(p.file + ": no such mesh file (or not a regular file)");
    try {
      p.mesh = geometry::load_mesh(p.file, p.unit_m, &p.weld, weld_m);
    } catch (const Error& e) {
      refuse(e.what());  // MeshFormatError (names file and line), unreadable file, unknown extension
    }
    if (opt.drop_duplicates) p.dropped = geometry::drop_duplicate_triangles(p.mesh);
    p.check = geometry::require_valid_mesh(p.mesh);
    parts.push_back(std::move(p));
  }
  return parts;
}

// Every part checked and integrated, and the assembly; the warnings a person should see.
struct Computed {
  std::vector<Part> parts;
  std::string unit;  // the assembly's: the first mesh's
  double unit_m = 1.0, volume = 0.0;
  int rays = 0;
  geometry::MassProperties total;
  RaycastDifference total_diff;
  std::vector<std::string> warnings;
};

Computed compute(const Options& opt) {
  Computed c;
  c.parts = read_parts(opt);
  c.unit = c.parts.front().unit;
  c.unit_m = c.parts.front().unit_m;
  geometry::RayGridOptions grid;
  grid.rays_per_side = c.rays = rays_per_side(opt);
  std::vector<geometry::MassProperties> exact, ray;
  for (auto& p : c.parts) {
    const std::string warning = geometry::unit_warning(p.mesh, p.unit, p.unit_m);
    if (!warning.empty()) c.warnings.push_back(warning);
    if (p.weld.merged_vertices > 0 || p.weld.dropped_triangles > 0) {
      c.warnings.push_back(p.file + ": welded " + std::to_string(p.weld.merged_vertices) +
                           " vertices onto others within " + g(p.weld.tolerance_m / p.unit_m, 3) + " " + p.unit +
                           (p.weld.dropped_triangles > 0
                                ? " and dropped the " + std::to_string(p.weld.dropped_triangles) +
                                      " triangles this left without area"
                                : std::string()) +
                           " (--weld sets the tolerance, \"0\" none)");
    }
    if (p.dropped > 0) {
      c.warnings.push_back(p.file + ": dropped " + std::to_string(p.dropped) +
                           " duplicate triangles (--drop-duplicates); the figures are those of the mesh without them");
    }
    p.exact = geometry::to_mass_properties(geometry::exact_moments(p.mesh, p.density));
    // Rays along the part's thinnest side: a plate is crossed through its thickness, where
    // each segment is integrated exactly, and sampled across its face.
    p.mesh.bounds().sizes().minCoeff(&grid.axis);
    geometry::RayCastStats stats;
    p.raycast = geometry::to_mass_properties(geometry::raycast_moments({{p.mesh, p.density}}, grid, &stats));
    if (stats.overlap_rays > 0) {
      // Each shell is closed, but two of them enclose common material: the divergence
      // theorem (and the rays) would count it twice.
      refuse(p.file + ": shells overlap: " + std::to_string(stats.overlap_rays) + " of " + std::to_string(stats.rays) +
             " check rays pass through material enclosed by two shells (solids exported into one another); unite "
             "them in CAD, or export them as separate files");
    }
    // The ray cast is an independent integration: past its tolerance the mesh, not the rays,
    // is the likely cause (a region counted twice, a surface that does not enclose what it
    // seems to), unless the walls are thinner than the rays' spacing.
    if (const double dm = difference(p.exact, p.raycast).mass; dm > kRaycastTolerance) {
      refuse(p.file + ": the ray-cast check differs from the exact mass by " + g(100.0 * dm, 3) + " % (tolerance " +
             g(100.0 * kRaycastTolerance, 2) + " %): the mesh may count a region twice (faces or shells exported "
             "twice) or not enclose what it seems to; if its walls are thin, raise --rays (now " +
             std::to_string(c.rays) + ") to tell");
    }
    exact.push_back(p.exact);
    ray.push_back(p.raycast);
    c.volume += p.check.volume_m3;
  }
  c.total = geometry::assemble(exact);
  c.total_diff = difference(c.total, geometry::assemble(ray));
  return c;
}

std::size_t cavities_of(const Part& p) {
  std::size_t cavities = 0;
  for (const auto& s : p.check.shells) cavities += s.cavity;
  return cavities;
}

nlohmann::json to_json(const Computed& c) {
  nlohmann::json out = properties_json(c.total, c.volume, c.total_diff, c.rays);
  if (c.parts.size() > 1) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& p : c.parts) {
      nlohmann::json j = properties_json(p.exact, p.check.volume_m3, difference(p.exact, p.raycast), c.rays);
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

void print_text(const Computed& c) {
  for (const auto& p : c.parts) {
    const std::size_t cavities = cavities_of(p);
    std::cout << p.file << " (" << p.unit << ", " << g(p.density) << " kg/m^3): " << p.mesh.triangles.size()
              << " triangles, " << p.check.shells.size() << (p.check.shells.size() == 1 ? " shell" : " shells");
    if (cavities) std::cout << " (" << cavities << (cavities == 1 ? " cavity" : " cavities") << ")";
    std::cout << ", closed and consistently oriented\n";
    print_properties(p.exact, p.check.volume_m3, difference(p.exact, p.raycast), p.unit, p.unit_m, std::cout);
    std::cout << '\n';
  }
  if (c.parts.size() > 1) {
    std::cout << "assembly of " << c.parts.size() << " parts (parallel-axis sum):\n";
    print_properties(c.total, c.volume, c.total_diff, c.unit, c.unit_m, std::cout);
  }
}

int run(const Options& opt) {
  try {
    const Computed c = compute(opt);
    for (const auto& w : c.warnings) std::cerr << "poise mass-properties: warning: " << w << '\n';
    if (opt.json) {
      std::cout << to_json(c).dump(2) << '\n';
    } else {
      print_text(c);
    }
  } catch (const geometry::MeshCheckError& e) {
    std::cerr << "poise mass-properties: " << e.what() << "\nNothing was computed.\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "poise mass-properties: error: " << e.what() << '\n';
    return 1;
  }
  return 0;
}

}  // namespace

nlohmann::json mass_properties_json(const MassPropertiesRequest& request) {
  Options opt;
  opt.meshes = request.meshes;
  opt.units = request.units;
  opt.densities = request.densities;
  opt.rays = std::to_string(request.rays);
  opt.drop_duplicates = request.drop_duplicates;
  opt.weld = request.weld;
  const Computed c = compute(opt);
  nlohmann::json out = to_json(c);
  out["warnings"] = c.warnings;
  return out;
}

MassPropertiesHandler add_mass_properties_command(CLI::App& app) {
  auto opt = std::make_shared<Options>();  // outlives this call: CLI11 writes into it
  CLI::App* sub = app.add_subcommand(
      "mass-properties",
      "volume, mass, centre of mass, inertia and principal axes of CAD meshes (STL, OBJ), each checked; "
      "several meshes: each part and the assembly");
  // Not required through CLI11, so that a missing argument is refused here with exit status 2.
  sub->add_option("MESH", opt->meshes, "mesh files: .stl (binary or ASCII) or .obj, e.g. rotor_disk.stl");
  sub->add_option("--unit,-u", opt->units,
                  "length unit the files were exported in: mm, cm, m or in (required: STL has no unit); once for "
                  "all meshes, or once per mesh in their order (the assembly is printed in the first's)");
  sub->add_option("--density,-d", opt->densities,
                  "density with its unit, e.g. \"2700 kg/m^3\" or \"7.85 g/cm^3\"; once for all meshes, or once per "
                  "mesh in their order (required)");
  sub->add_option("--rays", opt->rays, "rays per side of the ray-cast check grid (default 256)");
  sub->add_flag("--json", opt->json, "print one JSON object");
  sub->add_option("--weld", opt->weld,
                  "weld vertices closer than this length, e.g. \"0.0001 mm\" (\"0\": none; default 1e-6 of the "
                  "part's bounding-box diagonal): closes the cracks of an export and joins an OBJ's unshared "
                  "vertices; what was welded is said");
  sub->add_flag("--drop-duplicates", opt->drop_duplicates,
                "remove triangles that repeat another (same vertices, same winding: a face or shell exported "
                "twice) and say how many; without it such a mesh is refused");
  sub->allow_extras();  // an unknown option is refused by the handler, with exit status 2
  sub->footer(kMassPropertiesHelp);
  return [sub, opt]() -> std::optional<int> {
    if (!*sub) return std::nullopt;
    opt->extras = sub->remaining();
    return run(*opt);
  };
}

}  // namespace poise::cli
