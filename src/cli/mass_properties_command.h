#pragma once
/// `poise mass-properties MESH... --unit mm|cm|m|in --density "2700 kg/m^3" [--json]`: volume,
/// mass, centre of mass, inertia tensor about the centre of mass, principal moments and axes
/// of a designer's CAD parts (STL binary or ASCII, OBJ), each checked before use
/// (geometry/mesh_check.h); exact to the mesh by the divergence theorem, with the ray-cast
/// integration as an independent check; several meshes: each part and the assembly.
#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace poise::cli {

/// Runs `poise mass-properties` if it was the subcommand given: returns its exit status
/// (0 success, 2 bad mesh or argument, 1 other failure), or nullopt for another subcommand.
using MassPropertiesHandler = std::function<std::optional<int>()>;

/// What `poise mass-properties` is given: meshes, their length unit (mm, cm, m, in) and their
/// density ("2700 kg/m^3"), each once for all or one per mesh, rays per side of the check grid.
struct MassPropertiesRequest {
  std::vector<std::string> meshes;
  std::vector<std::string> units;
  std::vector<std::string> densities;
  int rays = 256;
  bool drop_duplicates = false;  ///< remove repeated triangles (and say so) instead of refusing
  std::string weld;              ///< weld tolerance, a length ("0.0001 mm"); "0" none; "" the default
  std::string max_overlap;       ///< overlap accepted, a share of the part's volume ("1e-6"); "" the default
};

/// The `--json` object of those meshes, with "warnings" (a unit that looks wrong, what was
/// welded or dropped, an overlap accepted). Throws geometry::MeshCheckError (a poise::Error)
/// for a bad argument, or for bad meshes with every defect of each, one per line.
nlohmann::json mass_properties_json(const MassPropertiesRequest& request);

/// Registers the `mass-properties` subcommand on app; call the handler after parsing.
MassPropertiesHandler add_mass_properties_command(CLI::App& app);

}  // namespace poise::cli
