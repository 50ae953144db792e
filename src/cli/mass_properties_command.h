#pragma once
/// `poise mass-properties MESH... --unit mm|cm|m|in --density "2700 kg/m^3" [--json]`: volume,
/// mass, centre of mass, inertia tensor about the centre of mass, principal moments and axes
/// of a designer's CAD parts (STL binary or ASCII, OBJ), each checked before use
/// (geometry/mesh_check.h); exact to the mesh by the divergence theorem, with the ray-cast
/// integration as an independent check; several meshes: each part and the assembly.
#include <CLI/CLI.hpp>
#include <functional>
#include <optional>

namespace poise::cli {

/// Runs `poise mass-properties` if it was the subcommand given: returns its exit status
/// (0 success, 2 bad mesh or argument, 1 other failure), or nullopt for another subcommand.
using MassPropertiesHandler = std::function<std::optional<int>()>;

/// Registers the `mass-properties` subcommand on app; call the handler after parsing.
MassPropertiesHandler add_mass_properties_command(CLI::App& app);

}  // namespace poise::cli
