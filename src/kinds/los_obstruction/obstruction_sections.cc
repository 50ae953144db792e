#include "kinds/los_obstruction/obstruction_sections.h"

#include "core/units.h"
#include "engine/study_files/toml_reader.h"

namespace poise::kinds::los_obstruction {

std::unique_ptr<engine::KindSections> read_obstruction_sections(engine::TomlReader& root) {
  auto s = std::make_unique<ObstructionSections>();
  {
    engine::TomlReader t = root.table("grid");
    s->yaw_points = static_cast<std::size_t>(t.integer("yaw_points", 1, 201));
    s->pitch_points = static_cast<std::size_t>(t.integer("pitch_points", 1, 201));
  }
  {
    engine::TomlReader t = root.table("beam");
    s->beam_rays = static_cast<int>(t.integer("rays", 16, 1'000'000, 1024));
  }
  if (root.has_or_schema("clearance")) {
    engine::TomlReader t = root.table("clearance");
    s->clearance_per_sample = t.boolean("per_sample", true);
    s->clearance_warn = t.quantity("warn_below", units::kLength, engine::non_negative, 0.5e-3);
  }
  return s;
}

}  // namespace poise::kinds::los_obstruction
