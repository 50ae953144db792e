#include "cli/mass_properties_command.h"

#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli/mass_properties_output.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_parts.h"

namespace poise::cli {
namespace {

// The command line, as given: the request, --json, and arguments CLI11 did not recognise.
struct Options {
  geometry::MeshPartsRequest request;
  bool json = false;
  std::vector<std::string> extras;
};

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

Repairs (each said in a note):
  vertices closer than the weld tolerance are welded (default 1e-6 of the part's
  bounding-box diagonal, --weld to set it, 0 for none): an export's cracks close and an
  OBJ's unshared vertices join; zero-area triangles the closed surface does not need
  (needles whose edges pair up among themselves) are dropped; OBJ polygons are cut into
  triangles by ear clipping (no slivers at collinear vertices); with --drop-duplicates,
  triangles that repeat another are removed.

Checks (a bad mesh is refused with exit status 2; every mesh is checked and every defect
of each is named at once, with the file, the triangle and its line, where it is in the
file's unit, and its size):
  open edges (not closed; with the width of the widest gap), edges of three or more
  triangles that do not pair up (not manifold; solids touching along an edge or a face
  pass), triangles flipped against their neighbours, degenerate triangles (a zero-area
  triangle that closes the surface at a T-junction is kept, with a note), a shell of
  negative volume that is inside no other shell (inside out), triangles that repeat
  another (a face or shell exported twice: --drop-duplicates removes them), shells that
  overlap by more than --max-overlap of the part's volume (default 1e-6; found by the
  check's rays, with the volume counted twice and where; a smaller overlap, such as
  touching curved faces whose facets cross, is a note), and a ray-cast mass more than
  2 % from the exact one.
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

int run(const Options& opt) {
  try {
    if (!opt.extras.empty()) {
      throw geometry::MeshCheckError("unknown argument '" + opt.extras.front() +
                                     "' (see poise mass-properties --help)");
    }
    const geometry::MeshParts c = geometry::compute_mesh_parts(opt.request);
    if (!c.errors.empty()) {
      for (const auto& e : c.errors) std::cerr << "poise mass-properties: " << e << '\n';
      for (const auto& w : c.notes) std::cerr << "poise mass-properties: note: " << w << '\n';
      std::cerr << "Nothing was computed.\n";
      return 2;
    }
    for (const auto& w : c.notes) std::cerr << "poise mass-properties: warning: " << w << '\n';
    if (opt.json) {
      std::cout << mass_properties::to_json(c).dump(2) << '\n';
    } else {
      mass_properties::print_text(c, std::cout);
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
  geometry::MeshPartsRequest parts;
  parts.meshes = request.meshes;
  parts.units = request.units;
  parts.densities = request.densities;
  parts.rays = std::to_string(request.rays);
  parts.drop_duplicates = request.drop_duplicates;
  parts.weld = request.weld;
  parts.max_overlap = request.max_overlap;
  const geometry::MeshParts c = geometry::compute_mesh_parts(parts);
  if (!c.errors.empty()) {
    std::string msg;
    for (const auto& e : c.errors) msg += (msg.empty() ? "" : "\n") + e;
    throw geometry::MeshCheckError(msg);
  }
  nlohmann::json out = mass_properties::to_json(c);
  out["warnings"] = c.notes;
  return out;
}

MassPropertiesHandler add_mass_properties_command(CLI::App& app) {
  auto opt = std::make_shared<Options>();  // outlives this call: CLI11 writes into it
  CLI::App* sub = app.add_subcommand(
      "mass-properties",
      "volume, mass, centre of mass, inertia and principal axes of CAD meshes (STL, OBJ), each checked; "
      "several meshes: each part and the assembly");
  // Not required through CLI11, so that a missing argument is refused here with exit status 2.
  sub->add_option("MESH", opt->request.meshes, "mesh files: .stl (binary or ASCII) or .obj, e.g. rotor_disk.stl");
  sub->add_option("--unit,-u", opt->request.units,
                  "length unit the files were exported in: mm, cm, m or in (required: STL has no unit); once for "
                  "all meshes, or once per mesh in their order (the assembly is printed in the first's)");
  sub->add_option("--density,-d", opt->request.densities,
                  "density with its unit, e.g. \"2700 kg/m^3\" or \"7.85 g/cm^3\"; once for all meshes, or once per "
                  "mesh in their order (required)");
  sub->add_option("--rays", opt->request.rays, "rays per side of the ray-cast check grid (default 256)");
  sub->add_flag("--json", opt->json, "print one JSON object");
  sub->add_option("--weld", opt->request.weld,
                  "weld vertices closer than this length, e.g. \"0.0001 mm\" (\"0\": none; default 1e-6 of the "
                  "part's bounding-box diagonal): closes the cracks of an export and joins an OBJ's unshared "
                  "vertices; what was welded is said");
  sub->add_option("--max-overlap", opt->request.max_overlap,
                  "largest overlap of shells accepted, as a share of the part's volume (default 1e-6; 0: none): "
                  "touching curved faces whose facets cross by their chord error pass with a note");
  sub->add_flag("--drop-duplicates", opt->request.drop_duplicates,
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
