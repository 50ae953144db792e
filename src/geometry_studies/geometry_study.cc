#include "geometry_studies/geometry_study.h"

#include "core/units.h"
#include "engine/study_files/toml_reader.h"

namespace poise::geometry_studies {
using namespace poise::engine;

void read_geometry_study(TomlReader& root, const std::string& kind, GeometryStudySpec& s) {
  if (kind == "geometry_mass_properties") {
    TomlReader t = root.table("mass_properties");
    s.rays_per_side = static_cast<int>(t.integer("rays_per_side", 4, 20000, 200));
    s.per_part = t.choice("grid", {"per_part", "one_scene"}, "per_part") == "per_part";
    s.export_mesh = t.boolean("export_mesh", true);
    t.ask("convergence", "an array of ray counts per side, each 4..4000", "[25, 50, 100, 200, 400]", false);
    if (t.has("convergence")) {
      s.convergence.clear();
      const toml::array* a = t.raw()["convergence"].as_array();
      bool ok = a != nullptr && !a->empty();
      if (a) {
        for (const auto& v : *a) {
          const auto n = v.value<std::int64_t>();
          if (!n || *n < 4 || *n > 4000) {
            ok = false;
            break;
          }
          s.convergence.push_back(static_cast<int>(*n));
        }
      }
      t.context().used.insert(t.path("convergence"));
      if (!ok) t.error("convergence", "", "an array of ray counts per side, each 4..4000, e.g. [25, 50, 100, 200]");
    }
  } else if (kind == "seeker_los") {
    if (root.has_or_schema("clearance")) {
      TomlReader t = root.table("clearance");
      s.clearance_output = t.boolean("output");
      s.clearance_yaw_points = static_cast<std::size_t>(t.integer("yaw_points", 1, 101, 3));
      s.clearance_pitch_points = static_cast<std::size_t>(t.integer("pitch_points", 1, 101, 3));
    }
  } else if (kind == "los_obstruction") {
    {
      TomlReader t = root.table("grid");
      s.yaw_points = static_cast<std::size_t>(t.integer("yaw_points", 1, 201));
      s.pitch_points = static_cast<std::size_t>(t.integer("pitch_points", 1, 201));
    }
    {
      TomlReader t = root.table("beam");
      s.beam_rays = static_cast<int>(t.integer("rays", 16, 1'000'000, 1024));
    }
    if (root.has_or_schema("clearance")) {
      TomlReader t = root.table("clearance");
      s.clearance_per_sample = t.boolean("per_sample", true);
      s.clearance_warn = t.quantity("warn_below", units::kLength, non_negative, 0.5e-3);
    }
  }
}

}  // namespace poise::geometry_studies
