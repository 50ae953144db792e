#include "kinds/gimbal_static_unbalance/gimbal_sections.h"

#include "core/units.h"
#include "engine/study_files/toml_reader.h"

namespace poise::kinds::gimbal_static_unbalance {
using namespace poise::engine;

std::unique_ptr<KindSections> read_gimbal_sections(TomlReader& root, const StudyConfig&) {
  auto c = std::make_unique<GimbalSections>();
  for (auto& g : root.table_array("group")) {
    GimbalGroup grp;
    grp.name = g.string("name");
    grp.positions = static_cast<std::size_t>(g.integer("positions", 4, 3600));
    grp.placement = g.choice("placement", {"sequential", "interleaved", "back_and_forth"}, "sequential");
    grp.repeats = static_cast<std::size_t>(g.integer("repeats", 1, 10000, 1));
    grp.counterweight_placement = g.choice("counterweight_placement", {"model", "disk_frame", "turntable"}, "model");
    g.string("notes", "");
    for (auto& l : g.table_array("load")) {
      GimbalLoad load;
      load.mass = l.quantity("mass", units::kMass, positive);
      load.radius = l.quantity("radius", units::kLength, positive);
      load.angle = l.quantity("angle", units::kAngle);
      grp.loads.push_back(load);
    }
    if (grp.loads.empty()) g.error("load", "", "at least one [[group.load]] (a test mass)");
    c->groups.push_back(grp);
  }
  if (c->groups.empty()) root.error("group", "", "at least one [[group]] of tests");
  return c;
}

std::map<std::string, std::string> apply_gimbal_study_overrides(StudyConfig& cfg,
                                                                const std::map<std::string, std::string>& overrides) {
  std::map<std::string, std::string> model_keys;
  std::vector<InputError> errors;
  const SourceLocation where{cfg.file, 0, 0};
  for (const auto& [key, value] : overrides) {
    if (key.rfind("group.", 0) != 0) {
      model_keys[key] = value;
      continue;
    }
    // "group.<key>" (every group) or "group.<name>.<key>" (one group).
    std::string rest = key.substr(6), name;
    if (const auto dot = rest.find('.'); dot != std::string::npos) {
      name = rest.substr(0, dot);
      rest = rest.substr(dot + 1);
    }
    if (mutable_sections_of<GimbalSections>(cfg).groups.empty()) {
      errors.emplace_back(where, key, "\"" + value + "\"", "a study with [[group]] tables (a gimbal study)");
      continue;
    }
    bool found = name.empty();
    for (auto& g : mutable_sections_of<GimbalSections>(cfg).groups) {
      if (!name.empty() && g.name != name) continue;
      found = true;
      if (rest == "positions" || rest == "repeats") {
        std::size_t used = 0;
        long long n = -1;
        try {
          n = std::stoll(value, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        const long long lo = rest == "positions" ? 4 : 1, hi = rest == "positions" ? 3600 : 10000;
        if (used != value.size() || n < lo || n > hi) {
          errors.emplace_back(where, key, "\"" + value + "\"",
                              "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
          break;
        }
        (rest == "positions" ? g.positions : g.repeats) = static_cast<std::size_t>(n);
      } else if (rest == "counterweight_placement") {
        if (value != "model" && value != "disk_frame" && value != "turntable") {
          errors.emplace_back(where, key, "\"" + value + "\"", "one of \"model\", \"disk_frame\", \"turntable\"");
          break;
        }
        g.counterweight_placement = value;
      } else if (rest == "placement") {
        if (value != "sequential" && value != "interleaved" && value != "back_and_forth") {
          errors.emplace_back(where, key, "\"" + value + "\"",
                              "one of \"sequential\", \"interleaved\", \"back_and_forth\"");
          break;
        }
        g.placement = value;
      } else {
        errors.emplace_back(where, key, "\"" + value + "\"",
                            "a study key group[.<name>].positions, .placement, .repeats or .counterweight_placement");
        break;
      }
    }
    if (!found) {
      std::string names;
      for (const auto& g : mutable_sections_of<GimbalSections>(cfg).groups)
        names += (names.empty() ? "" : ", ") + g.name;
      errors.emplace_back(where, key, "\"" + value + "\"", "the name of a [[group]]: " + names);
    }
  }
  if (!errors.empty()) throw ValidationError(errors);
  return model_keys;
}

}  // namespace poise::kinds::gimbal_static_unbalance
