#include "kinds/seeker_los/seeker_los_sections.h"

#include "core/units.h"
#include "engine/study_files/toml_reader.h"

namespace poise::kinds::seeker_los {
using namespace poise::engine;

std::unique_ptr<KindSections> read_seeker_los_sections(TomlReader& root, const StudyConfig& cfg) {
  auto c = std::make_unique<SeekerLosSections>();
  if (root.has_or_schema("clearance")) {  // optional
    TomlReader t = root.table("clearance");
    c->clearance.clearance_output = t.boolean("output");
    c->clearance.clearance_yaw_points = static_cast<std::size_t>(t.integer("yaw_points", 1, 101, 3));
    c->clearance.clearance_pitch_points = static_cast<std::size_t>(t.integer("pitch_points", 1, 101, 3));
  }
  {
    TomlReader t = root.table("grid");
    c->yaw_points = static_cast<std::size_t>(t.integer("yaw_points", 1, 1001));
    c->pitch_points = static_cast<std::size_t>(t.integer("pitch_points", 1, 1001));
  }
  // The LOS limit of the field figures: the [requirement] shorthand, or else the first
  // [[requirement]] on los_max_arcsec or los_max_px.
  const Requirement* stated = nullptr;
  for (const auto& r : cfg.requirements) {
    if (!stated && (r.output == "los_max_arcsec" || r.output == "los_max_px")) stated = &r;
  }
  const bool shorthand = root.has("requirement") && root.raw()["requirement"].is_table();
  if (!stated && !shorthand && !root.has("requirement") && !root.schema_only()) {
    // No LOS limit stated: a study may have no requirement, as every kind may. The field
    // figures (the share of the field within the limit) are then taken against 1 px.
    c->requirement = 1.0;
    c->requirement_in_pixels = true;
    c->requirement_shorthand = false;
  } else if (stated && !shorthand) {
    c->requirement_text = stated->limit_text;
    c->requirement_shorthand = false;
    try {
      const units::Quantity q = units::parse_quantity(c->requirement_text);
      c->requirement_in_pixels = q.dim == units::kPixel;
      c->requirement = q.value;
    } catch (const Error&) {
      // reported with the [[requirement]]
    }
  } else if (!root.has("requirement") || root.raw()["requirement"].is_table() || root.schema_only()) {
    TomlReader t = root.table("requirement");
    t.ask("los_error", "a positive angle or pixel count, e.g. \"1 px\" or \"18 arcsec\"",
          "none: then [[requirement]] tables on los_max_arcsec or los_max_px", true);
    c->requirement_text = t.string("los_error");
    if (t.has("los_error") && t.raw()["los_error"].is_string()) {  // else: t.string reported it
      try {
        const units::Quantity q = units::parse_quantity(c->requirement_text);
        if (q.dim == units::kPixel) {
          c->requirement_in_pixels = true;
        } else if (q.dim == units::kAngle) {
          c->requirement_in_pixels = false;
        } else {
          throw Error("got " + units::dimension_name(q.dim));
        }
        if (!(q.value > 0)) throw Error("not positive");
        c->requirement = q.value;
      } catch (const Error& e) {
        t.error("los_error", quote_value(c->requirement_text),
                std::string("a positive angle or pixel count, e.g. \"1 px\" or \"18 arcsec\" (") + e.what() + ")");
      }
    }
  } else {
    root.error(
        "requirement", "[[requirement]] tables",
        "an LOS limit: [requirement] los_error = \"1 px\", or a [[requirement]] on los_max_arcsec or los_max_px");
  }
  if (root.has_or_schema("output")) {
    TomlReader t = root.table("output");
    c->contribution_samples = static_cast<std::size_t>(t.integer("contribution_samples", 0, 1'000'000'000, 4096));
    c->grid_values = t.boolean("grid_values", true);
    c->maps = t.boolean("maps", true);
    c->grid_values_in_memory_mb = static_cast<std::size_t>(
        t.integer("grid_values_in_memory_mb", 0, 1'000'000, static_cast<std::int64_t>(kKeepColumnsBytes >> 20)));
  }
  return c;
}

}  // namespace poise::kinds::seeker_los
