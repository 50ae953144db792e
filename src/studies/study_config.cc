#include "studies/study_config.h"

#include <filesystem>

#include "studies/toml_reader.h"

namespace poise::studies {

StudyConfig load_study(const std::string& path) {
  toml::table doc = parse_toml_file(path);
  auto ctx = std::make_shared<ReadContext>();
  ctx->file = path;
  TomlReader root(doc, ctx);
  StudyConfig c;
  c.file = path;
  {
    TomlReader t = root.table("study");
    c.name = t.string("name");
    for (char ch : c.name) {
      if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-')) {
        t.error("name", "\"" + c.name + "\"", "a name of letters, digits, '_' and '-' (it names a folder)");
        break;
      }
    }
    c.kind = t.choice("kind", {"seeker_los"});
    const std::string model = t.string("model");
    c.model_path = (std::filesystem::path(path).parent_path() / model).lexically_normal().string();
    if (!model.empty() && !std::filesystem::exists(c.model_path)) {
      t.error("model", "\"" + model + "\"", "an existing model file (looked for " + c.model_path + ")");
    }
    c.title = t.string("title", "");
    c.notes = t.string("notes", "");
  }
  {
    TomlReader t = root.table("sampling");
    c.method = sampling::parse_sampling_method(t.choice("method", {"sobol", "lhs", "monte_carlo"}));
    c.samples = static_cast<std::size_t>(t.integer("samples", 1, 1'000'000'000));
    c.seed = static_cast<std::uint64_t>(t.integer("seed", 0, INT64_MAX));
  }
  {
    TomlReader t = root.table("grid");
    c.yaw_points = static_cast<std::size_t>(t.integer("yaw_points", 1, 1001));
    c.pitch_points = static_cast<std::size_t>(t.integer("pitch_points", 1, 1001));
  }
  {
    TomlReader t = root.table("requirement");
    c.requirement_text = t.string("los_error");
    try {
      const units::Quantity q = units::parse_quantity(c.requirement_text);
      if (q.dim == units::kPixel) {
        c.requirement_in_pixels = true;
      } else if (q.dim == units::kAngle) {
        c.requirement_in_pixels = false;
      } else {
        throw Error("got " + units::dimension_name(q.dim));
      }
      if (!(q.value > 0)) throw Error("not positive");
      c.requirement = q.value;
    } catch (const Error& e) {
      t.error("los_error", "\"" + c.requirement_text + "\"",
              std::string("a positive angle or pixel count, e.g. \"1 px\" or \"18 arcsec\" (") +
                  e.what() + ")");
    }
  }
  if (root.has("overrides")) {
    TomlReader t = root.table("overrides");
    for (const auto& key : t.keys()) c.overrides[key] = t.string(key);
  }
  for (auto& s : root.table_array("sweep")) {
    SweepSpec sw;
    sw.parameter = s.string("parameter");
    sw.values = s.string_array("values");
    if (sw.values.empty()) s.error("values", "[]", "at least one value");
    sw.samples = static_cast<std::size_t>(
        s.integer("samples", 1, 1'000'000'000, static_cast<std::int64_t>(c.samples)));
    c.sweeps.push_back(sw);
  }
  if (root.has("output")) {
    TomlReader t = root.table("output");
    c.plots = t.boolean("plots", true);
    c.block = static_cast<std::size_t>(t.integer("block", 1, 1'000'000, 1024));
    c.contribution_samples =
        static_cast<std::size_t>(t.integer("contribution_samples", 0, 1'000'000'000, 4096));
  }
  finish(doc, *ctx);
  return c;
}

}  // namespace poise::studies
