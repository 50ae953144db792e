#include "kinds/balancing_machine/balancing_sections.h"

#include "core/units.h"
#include "engine/study_files/toml_reader.h"

namespace poise::kinds::balancing_machine {
using namespace poise::engine;

std::unique_ptr<KindSections> read_balancing_sections(TomlReader& root, const StudyConfig&) {
  auto c = std::make_unique<BalancingSections>();
  {
    TomlReader t = root.table("procedure");
    c->plane_1_surface = static_cast<int>(t.integer("plane_1_surface", 1, 1000));
    c->plane_2_surface = static_cast<int>(t.integer("plane_2_surface", 1, 1000));
    if (c->plane_1_surface == c->plane_2_surface) {
      t.error("plane_2_surface", std::to_string(c->plane_2_surface), "a surface other than plane_1_surface");
    }
    c->estimator = t.choice("estimator", {"influence", "closed_form"});
    c->calibration_mass = t.quantity("calibration_mass", units::kMass, positive);
    c->calibration_radius = t.quantity("calibration_radius", units::kLength, positive);
    t.string("notes", "");
  }
  const units::Dimension unbalance{{1, 1, 0, 0, 0, 0}};
  for (auto& e : root.table_array("experiment")) {
    BalancingExperiment x;
    x.name = e.string("name");
    x.type = e.choice("type", {"separation", "umar", "umar_iso", "stability", "urr", "accuracy", "calibration"});
    for (const auto& other : c->experiments) {
      if (other.name == x.name) e.error("name", "\"" + x.name + "\"", "a name no other experiment has");
    }
    const bool schema = e.schema_only();  // `poise keys`: every type's keys
    // calibration reports the machine's own calibration ([procedure]'s mass): no test mass.
    if (schema || x.type != "calibration") {
      x.mass = e.quantity("mass", units::kMass, positive);
      x.radius = e.quantity("radius", units::kLength, positive);
    }
    if (schema || x.type == "separation" || x.type == "umar" || x.type == "umar_iso" || x.type == "stability") {
      x.positions = static_cast<int>(e.integer("positions", 1, 360, 8));
    }
    if (schema || x.type == "stability") {
      x.surface = static_cast<int>(e.integer("surface", 1, 1000));
      x.band = e.number(
          "band", [](double v) { return v > 0 && v < 1 ? "" : "a fraction in (0, 1), e.g. 0.12"; }, 0.12);
      x.balance_first = e.boolean("balance_first", true);
      x.variant = e.choice("variant", {"wang2014", "poise"}, "poise");
    }
    if (schema || x.type == "umar_iso") {
      x.plane_2_offset = e.quantity("plane_2_offset", units::kAngle, {}, 0.0);
      x.claim = e.quantity("claim", unbalance, positive);
    }
    if (schema || x.type == "accuracy") x.piece_unbalance = e.quantity("piece_unbalance", unbalance, positive);
    if (schema || x.type == "urr") {
      x.requirement =
          e.number("requirement", [](double v) { return v > 0 && v < 1 ? "" : "a fraction in (0, 1), e.g. 0.9"; });
    }
    e.string("notes", "");
    c->experiments.push_back(x);
  }
  if (c->experiments.empty()) root.error("experiment", "", "at least one [[experiment]]");
  return c;
}

}  // namespace poise::kinds::balancing_machine
