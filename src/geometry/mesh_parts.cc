#include "geometry/mesh_parts.h"

#include <charconv>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/format.h"
#include "core/units.h"
#include "geometry/mesh_text.h"
#include "geometry/rigid_body_inertia.h"

namespace poise::geometry {
namespace {

[[noreturn]] void refuse(const std::string& what) { throw MeshCheckError(what); }

std::string count(std::size_t n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

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

// --rays as a number from 8 to 4096, or -1.
int rays_per_side(const MeshPartsRequest& opt) {
  int n = 0;
  const char* end = opt.rays.data() + opt.rays.size();
  const auto [p, ec] = std::from_chars(opt.rays.data(), end, n);
  return ec == std::errc() && p == end && n >= 8 && n <= 4096 ? n : -1;
}

// --weld in metres: -1 for the default, relative to the part.
double weld_length(const MeshPartsRequest& opt) {
  if (opt.weld.empty()) return -1.0;
  double weld_m = 0.0;
  try {
    weld_m = opt.weld == "0" ? 0.0 : units::parse_as(opt.weld, units::kLength);
  } catch (const Error& e) {
    refuse("--weld \"" + opt.weld + "\": " + e.what());
  }
  if (!(weld_m >= 0.0) || !std::isfinite(weld_m)) {
    refuse("--weld \"" + opt.weld + "\": expected a length >= 0, e.g. \"0.0001 mm\"");
  }
  return weld_m;
}

// --max-overlap: a share of the part's volume from 0 (none accepted) to below 1.
double overlap_share(const MeshPartsRequest& opt) {
  if (opt.max_overlap.empty()) return kMaxOverlapShare;
  double share = -1.0;
  const char* begin = opt.max_overlap.data();
  const char* end = begin + opt.max_overlap.size();
  const auto [p, ec] = std::from_chars(begin, end, share);
  if (ec != std::errc() || p != end || !(share >= 0.0 && share < 1.0)) {
    refuse("--max-overlap " + opt.max_overlap +
           ": expected a share of the part's volume from 0 to below 1, e.g. 1e-6 (overlapping shells are "
           "accepted up to it)");
  }
  return share;
}

// The arguments, checked before any mesh is read; each part's file, unit and density.
std::vector<MeshPart> parts_of(const MeshPartsRequest& opt) {
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
  if (rays_per_side(opt) < 0) {
    refuse("--rays " + opt.rays + ": expected a whole number from 8 to 4096 (rays across the part)");
  }
  std::vector<MeshPart> parts(opt.meshes.size());
  for (std::size_t i = 0; i < parts.size(); ++i) {
    MeshPart& p = parts[i];
    p.file = opt.meshes[i];
    p.unit = opt.units.empty() ? std::string() : opt.units.size() == 1 ? opt.units[0] : opt.units[i];
    p.unit_m = unit_size(p.unit);
    const std::string& dtext = opt.densities.size() == 1 ? opt.densities[0] : opt.densities[i];
    try {
      p.density = units::parse_as(dtext, units::kDensity);
    } catch (const Error& e) {
      refuse("--density \"" + dtext + "\": " + e.what());
    }
    if (!(p.density > 0.0) || !std::isfinite(p.density)) {
      refuse("--density \"" + dtext + "\": expected a positive density, e.g. \"2700 kg/m^3\"");
    }
  }
  return parts;
}

// What reading the part repaired or found doubtful, one note each.
void repair_notes(const MeshPart& p, std::vector<std::string>& notes) {
  if (const std::string w = unit_warning(p.mesh, p.unit, p.unit_m); !w.empty()) notes.push_back(w);
  const WeldReport& weld = p.repairs.weld;
  if (weld.merged_vertices > 0 || weld.dropped_triangles > 0) {
    notes.push_back(p.file + ": welded " + std::to_string(weld.merged_vertices) + " vertices onto others within " +
                    describe_length(p.mesh, weld.tolerance_m) +
                    (weld.dropped_triangles > 0 ? " and dropped the " + std::to_string(weld.dropped_triangles) +
                                                      " triangles this left without area"
                                                : std::string()) +
                    " (--weld sets the tolerance, \"0\" none)");
  }
  if (p.repairs.needles.dropped > 0) {
    notes.push_back(p.file + ": dropped " +
                    count(p.repairs.needles.dropped, "zero-area triangle", "zero-area triangles") +
                    " the closed surface does not need (needles whose edges pair up among themselves; they enclose "
                    "nothing), the first was " +
                    p.repairs.needles.first);
  }
  if (p.dropped > 0) {
    notes.push_back(p.file + ": dropped " + std::to_string(p.dropped) +
                    " duplicate triangles (--drop-duplicates); the figures are those of the mesh without them");
  }
}

// Overlapping shells: an error above the accepted share of the part's volume, else a note.
void judge_overlap(const MeshPart& p, const RayCastStats& stats, double max_share, MeshParts& c) {
  if (stats.overlap_rays == 0) return;
  const double share = stats.overlap_volume_m3 / std::abs(p.check.volume_m3);
  const std::string what = "about " + describe_volume(p.mesh, stats.overlap_volume_m3) + " counted twice (" +
                           significant(share, 3) + " of the part's volume; accepted up to " +
                           significant(max_share, 3) + ", --max-overlap), " + describe_box(p.mesh, stats.overlap_box);
  if (share > max_share) {
    c.errors.push_back(p.file + ": shells overlap: " + std::to_string(stats.overlap_rays) + " of " +
                       std::to_string(stats.rays) +
                       " check rays pass through material enclosed by two shells (solids exported into one "
                       "another), " +
                       what + "; unite them in CAD, or export them as separate files");
  } else {
    c.notes.push_back(p.file + ": shells overlap by " + what +
                      " (a trace, as touching curved faces leave where their facets cross); the figures include it");
  }
}

// One part read, checked and integrated; its defects go to c.errors.
void examine(MeshPart& p, const MeshPartsRequest& opt, double weld_m, double max_share, MeshParts& c) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(p.file, ec)) {
    c.errors.push_back(p.file + ": no such mesh file (or not a regular file)");
    return;
  }
  try {
    p.mesh = load_mesh(p.file, p.unit_m, &p.repairs, weld_m);
  } catch (const Error& e) {
    c.errors.emplace_back(e.what());  // MeshFormatError (names file and line), unreadable file, unknown extension
    return;
  }
  if (opt.drop_duplicates) p.dropped = drop_duplicate_triangles(p.mesh);
  repair_notes(p, c.notes);
  p.check = check_mesh(p.mesh);
  if (!p.check.ok()) {
    c.errors.insert(c.errors.end(), p.check.errors.begin(), p.check.errors.end());
    return;
  }
  if (const Defect& z = p.check.zero_area_triangles; z.count > 0) {
    c.notes.push_back(p.file + ": kept " + count(z.count, "zero-area triangle", "zero-area triangles") +
                      " that close the surface (a vertex on another triangle's edge), the first is " +
                      describe_triangle(p.mesh, z.first_triangle) + "; they add no volume");
  }
  p.exact = to_mass_properties(exact_moments(p.mesh, p.density));
  // Rays along the part's thinnest side: a plate is crossed through its thickness, where
  // each segment is integrated exactly, and sampled across its face.
  RayGridOptions grid;
  grid.rays_per_side = c.rays;
  p.mesh.bounds().sizes().minCoeff(&grid.axis);
  RayCastStats stats;
  p.raycast = to_mass_properties(raycast_moments({{p.mesh, p.density}}, grid, &stats));
  judge_overlap(p, stats, max_share, c);
  // The ray cast is an independent integration: past its tolerance the mesh, not the rays,
  // is the likely cause (a region counted twice, a surface that does not enclose what it
  // seems to), unless the walls are thinner than the rays' spacing.
  if (const double dm = raycast_difference(p.exact, p.raycast).mass; dm > kRaycastTolerance) {
    c.errors.push_back(p.file + ": the ray-cast check differs from the exact mass by " + significant(100.0 * dm, 3) +
                       " % (tolerance " + significant(100.0 * kRaycastTolerance, 2) +
                       " %): the mesh may count a region twice (faces or shells exported twice) or not enclose what "
                       "it seems to; if its walls are thin, raise --rays (now " +
                       std::to_string(c.rays) + ") to tell");
  }
}

}  // namespace

RaycastDifference raycast_difference(const MassProperties& exact, const MassProperties& ray) {
  RaycastDifference d;
  d.mass = std::abs(ray.mass - exact.mass) / exact.mass;
  d.com_m = (ray.com - exact.com).norm();
  d.inertia = (ray.inertia - exact.inertia).norm() / exact.inertia.norm();
  return d;
}

MeshParts compute_mesh_parts(const MeshPartsRequest& opt) {
  MeshParts c;
  c.parts = parts_of(opt);
  c.rays = rays_per_side(opt);
  const double weld_m = weld_length(opt), max_share = overlap_share(opt);
  c.unit = c.parts.front().unit;
  c.unit_m = c.parts.front().unit_m;
  for (MeshPart& p : c.parts) examine(p, opt, weld_m, max_share, c);
  if (!c.errors.empty()) return c;
  std::vector<MassProperties> exact, ray;
  for (const MeshPart& p : c.parts) {
    exact.push_back(p.exact);
    ray.push_back(p.raycast);
    c.volume += p.check.volume_m3;
  }
  c.total = assemble(exact);
  c.total_diff = raycast_difference(c.total, assemble(ray));
  return c;
}

}  // namespace poise::geometry
