#include "kinds/geometry_mass_properties/mass_properties_sections.h"

#include "engine/study_files/toml_reader.h"

namespace poise::kinds::geometry_mass_properties {

std::unique_ptr<engine::KindSections> read_mass_properties_sections(engine::TomlReader& root) {
  auto s = std::make_unique<MassPropertiesSections>();
  engine::TomlReader t = root.table("mass_properties");
  s->rays_per_side = static_cast<int>(t.integer("rays_per_side", 4, 20000, 200));
  s->per_part = t.choice("grid", {"per_part", "one_scene"}, "per_part") == "per_part";
  s->export_mesh = t.boolean("export_mesh", true);
  t.ask("convergence", "an array of ray counts per side, each 4..4000", "[25, 50, 100, 200, 400]", false);
  if (t.has("convergence")) {
    s->convergence.clear();
    const toml::array* a = t.raw()["convergence"].as_array();
    bool ok = a != nullptr && !a->empty();
    if (a) {
      for (const auto& v : *a) {
        const auto n = v.value<std::int64_t>();
        if (!n || *n < 4 || *n > 4000) {
          ok = false;
          break;
        }
        s->convergence.push_back(static_cast<int>(*n));
      }
    }
    t.context().used.insert(t.path("convergence"));
    if (!ok) t.error("convergence", "", "an array of ray counts per side, each 4..4000, e.g. [25, 50, 100, 200]");
  }
  return s;
}

}  // namespace poise::kinds::geometry_mass_properties
