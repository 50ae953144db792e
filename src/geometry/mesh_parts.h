#pragma once
/// A designer's parts from their CAD meshes, as `poise mass-properties` and Python's
/// poise.mass_properties compute them (the command only parses and prints): each
/// mesh read, repaired as far as it is safe (welded, unneeded zero-area triangles and, with
/// --drop-duplicates, repeated ones dropped), checked, integrated exactly and by the ray cast.
/// Every mesh is examined and every defect of every mesh collected before anything is
/// refused, so one run names all that is wrong; what was repaired or tolerated is a note.
#include <cstddef>
#include <string>
#include <vector>

#include "geometry/mass_properties.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_io.h"

namespace poise::geometry {

/// The meshes and how to read them, as the command and Python give them (the messages name
/// each field as the command's option: --unit, --density, --rays, --weld, --max-overlap).
struct MeshPartsRequest {
  std::vector<std::string> meshes;
  std::vector<std::string> units;  // once for all meshes, or once per mesh
  std::vector<std::string> densities;
  std::string rays = "256";
  bool drop_duplicates = false;
  std::string weld;         // a length with its unit, "0" for none; "" = the default
  std::string max_overlap;  // a share of the part's volume; "" = kMaxOverlapShare
};

/// Ray cast against exact mass, relative: thin members at 256 rays agree to about 1 %.
inline constexpr double kRaycastTolerance = 0.02;

struct MeshPart {
  std::string file;
  double density = 0.0;  // kg/m^3
  Mesh mesh;
  MeshCheck check;
  MassProperties exact, raycast;
  std::size_t dropped = 0;  // duplicate triangles removed (--drop-duplicates)
  LoadReport repairs;
  std::string unit;     // the length unit the file was exported in
  double unit_m = 1.0;  // its size
};

struct RaycastDifference {
  double mass = 0.0;     // relative
  double com_m = 0.0;    // distance between the centres of mass
  double inertia = 0.0;  // |I_ray - I| / |I| (Frobenius)
};
RaycastDifference raycast_difference(const MassProperties& exact, const MassProperties& ray);

/// Every part integrated and the assembly, or the errors that refuse them.
struct MeshParts {
  std::vector<MeshPart> parts;
  std::string unit;  // the assembly's: the first mesh's
  double unit_m = 1.0, volume = 0.0;
  int rays = 0;
  MassProperties total;
  RaycastDifference total_diff;
  std::vector<std::string> notes;   // what was repaired or tolerated, a unit that looks wrong
  std::vector<std::string> errors;  // every defect of every mesh; none computed if any
};

/// Throws MeshCheckError for a bad argument (before any mesh is read); a bad mesh goes to
/// MeshParts::errors, and the other meshes are still examined.
MeshParts compute_mesh_parts(const MeshPartsRequest& request);

}  // namespace poise::geometry
