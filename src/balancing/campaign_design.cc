#include "balancing/campaign_design.h"

#include <cstdlib>
#include <filesystem>

#include "core/error.h"
#include "core/units.h"
#include "engine/kind_interface/output_spec.h"

namespace poise::balancing {
namespace {

// "4.5 mm" -> 4.5 and "mm" ("" for a plain number), checked by the units module.
std::pair<double, std::string> split_quantity(const std::string& text) {
  units::parse_quantity(text);  // throws with what is wrong
  const char* begin = text.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  std::string unit(end);
  unit.erase(0, unit.find_first_not_of(" \t"));
  unit.erase(unit.find_last_not_of(" \t") + 1);
  return {v, unit};
}

DesignCalibrate read_calibrate(engine::TomlReader& t) {
  DesignCalibrate k;
  k.line = t.line_of("key");
  k.key = t.string("key");
  const std::vector<std::string> range = t.string_array("range");
  const char* expected = "two values of the key with one unit, low first, e.g. [\"3 mm\", \"5 mm\"]";
  if (range.size() != 2) {
    t.error("range", std::to_string(range.size()) + " value(s)", expected);
    return k;
  }
  try {
    const auto [low, unit] = split_quantity(range[0]);
    const auto [high, unit_high] = split_quantity(range[1]);
    if (unit != unit_high || !(low < high)) t.error("range", "[\"" + range[0] + "\", \"" + range[1] + "\"]", expected);
    k.low = low;
    k.high = high;
    k.unit = unit;
  } catch (const Error& e) {
    t.error("range", "[\"" + range[0] + "\", \"" + range[1] + "\"]", std::string(expected) + " (" + e.what() + ")");
  }
  return k;
}

}  // namespace

DesignLink read_design_link(engine::TomlReader& d, const BalancingCampaign& c, const std::string& campaign_path) {
  DesignLink link;
  link.study = (std::filesystem::path(campaign_path).parent_path() / d.string("study")).string();
  link.samples = static_cast<std::size_t>(d.integer("samples", 2, 1000000, 64));
  for (engine::TomlReader& k : d.table_array("compare")) {
    DesignCompare cmp;
    cmp.figure = k.choice("figure", {"urr", "umar", "influence"});
    cmp.plane = k.choice("plane", c.planes);
    cmp.output = k.string("output");
    if (cmp.figure == "influence" || k.schema_only()) cmp.sensor = k.choice("sensor", c.sensors);
    link.compare.push_back(cmp);
  }
  if (link.compare.empty()) d.error("compare", "", "at least one [[design.compare]] with figure, plane and output");
  if (d.has_or_schema("calibrate")) {
    engine::TomlReader t = d.table("calibrate");
    link.calibrate = read_calibrate(t);
    bool influence = false;
    for (const auto& k : link.compare) influence = influence || k.figure == "influence";
    if (!influence) {
      d.error("calibrate", "a key to fit",
              "[[design.compare]] tables with figure = \"influence\": the real coefficients it is fitted to");
    }
  }
  return link;
}

}  // namespace poise::balancing
