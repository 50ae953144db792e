#include "kinds/platform_balancing/platform_study_config.h"

#include <filesystem>
#include <sstream>

#include "engine/study_files/toml_reader.h"

namespace poise::kinds::platform_balancing {
using namespace poise::engine;

namespace {

// "inner,middle,outer" -> {0, 1, 2}; empty on a malformed order.
std::array<int, 3> parse_order(const std::string& text, bool* ok) {
  std::array<int, 3> out{-1, -1, -1};
  std::stringstream ss(text);
  std::string part;
  int n = 0;
  *ok = true;
  while (std::getline(ss, part, ',')) {
    part.erase(0, part.find_first_not_of(' '));
    part.erase(part.find_last_not_of(' ') + 1);
    const int axis = part == "inner" ? 0 : (part == "middle" ? 1 : (part == "outer" ? 2 : -1));
    if (axis < 0 || n >= 3) {
      *ok = false;
      return out;
    }
    for (int k = 0; k < n; ++k) {
      if (out[static_cast<std::size_t>(k)] == axis) *ok = false;
    }
    out[static_cast<std::size_t>(n++)] = axis;
  }
  *ok = *ok && n == 3;
  return out;
}

}  // namespace

void read_platform_section(TomlReader& root, const std::string& study_path, PlatformStudySection& c) {
  TomlReader t = root.table("platform");
  c.order_texts = t.string_array("orders");
  if (c.order_texts.empty()) t.error("orders", "[]", "at least one test order, e.g. \"inner,middle,outer\"");
  for (const auto& text : c.order_texts) {
    bool ok = false;
    const auto order = parse_order(text, &ok);
    if (!ok) {
      t.error("orders", quote_value(text),
              "each of inner, middle, outer once, comma-separated, e.g. \"inner,middle,outer\"");
      continue;
    }
    std::string label;
    for (int a : order) label += a == 0 ? 'i' : (a == 1 ? 'm' : 'o');
    for (const auto& l : c.order_labels) {
      if (l == label) t.error("orders", quote_value(text), "an order not listed twice");
    }
    c.orders.push_back(order);
    c.order_labels.push_back(label);
  }
  c.positions = static_cast<std::size_t>(t.integer("positions", 4, 3600));
  auto range = [&](const std::string& name, double& lo, double& hi, std::size_t& n) {
    lo = t.quantity(name + "_min", units::kAngle);
    hi = t.quantity(name + "_max", units::kAngle);
    n = static_cast<std::size_t>(t.integer(name + "_points", 1, 721));
    if (hi < lo) t.error(name + "_max", "", name + "_max >= " + name + "_min");
  };
  range("outer", c.outer_min, c.outer_max, c.outer_points);
  range("middle", c.middle_min, c.middle_max, c.middle_points);
  range("inner", c.inner_min, c.inner_max, c.inner_points);
  c.acceleration = {t.quantity("acceleration_x", units::kAcceleration),
                    t.quantity("acceleration_y", units::kAcceleration),
                    t.quantity("acceleration_z", units::kAcceleration)};
  t.string("notes", "");
  {
    TomlReader p = t.table("profile");
    c.duration = p.quantity("duration", units::kTime, positive);
    c.time_step = p.quantity("time_step", units::kTime, positive);
    if (c.time_step > 0 && c.duration / c.time_step > 2e6)
      p.error("time_step", "", "at most 2e6 steps over the duration");
    c.manoeuvre = {p.quantity("manoeuvre_x", units::kAcceleration), p.quantity("manoeuvre_y", units::kAcceleration),
                   p.quantity("manoeuvre_z", units::kAcceleration)};
    c.onset = p.quantity("onset", units::kTime, non_negative);
    c.rise_time = p.quantity("rise_time", units::kTime, non_negative);
    p.string("notes", "");
    for (auto& v : p.table_array("vibration")) {
      PlatformVibration line;
      line.amplitude = {v.quantity("amplitude_x", units::kAcceleration),
                        v.quantity("amplitude_y", units::kAcceleration),
                        v.quantity("amplitude_z", units::kAcceleration)};
      line.frequency = v.quantity("frequency", units::kFrequency, positive);
      if (c.time_step > 0 && line.frequency * c.time_step > 0.1) {
        v.error("frequency", "", "a frequency of at most 0.1 / time_step (10 profile samples per period)");
      }
      c.vibration.push_back(line);
    }
  }
  if (t.has_or_schema("shafting")) {
    TomlReader s = t.table("shafting");
    const std::string rel = s.string("study");
    c.shafting_study = (std::filesystem::path(study_path).parent_path() / rel).lexically_normal().string();
    std::error_code ec;  // a name too long for the file system is a missing file, not an exception
    if (!std::filesystem::is_regular_file(c.shafting_study, ec)) {
      s.error("study", quote_value(rel), "an existing study file (looked for " + c.shafting_study + ")");
    }
    c.shafting_samples = static_cast<std::size_t>(s.integer("samples", 16, 10'000'000, 4096));
    c.shafting_output = s.string("output", "los_max_arcsec");
    c.shafting_pixel_output = s.string("pixel_output", "los_max_px");
  }
}

std::unique_ptr<KindSections> read_platform_sections(TomlReader& root, const StudyConfig& cfg) {
  auto c = std::make_unique<PlatformSections>();
  read_platform_section(root, cfg.file, c->platform);
  return c;
}

}  // namespace poise::kinds::platform_balancing
