#include "studies/study_config.h"

#include <filesystem>

#include "studies/toml_reader.h"

namespace poise::studies {

namespace {

void read_gimbal_groups(TomlReader& root, StudyConfig& c) {
  const units::Dimension torque = units::kTorque;
  for (auto& g : root.table_array("group")) {
    GimbalGroup grp;
    grp.name = g.string("name");
    grp.positions = static_cast<std::size_t>(g.integer("positions", 4, 3600));
    grp.placement = g.choice("placement", {"sequential", "interleaved", "back_and_forth"}, "sequential");
    grp.repeats = static_cast<std::size_t>(g.integer("repeats", 1, 10000, 1));
    if (g.has("paper_rmse_torque")) grp.paper_rmse_torque = g.quantity("paper_rmse_torque", torque, non_negative);
    if (g.has("paper_rmse_angle")) grp.paper_rmse_angle = g.quantity("paper_rmse_angle", units::kAngle, non_negative);
    g.string("notes", "");
    for (auto& l : g.table_array("load")) {
      GimbalLoad load;
      load.mass = l.quantity("mass", units::kMass, positive);
      load.radius = l.quantity("radius", units::kLength, positive);
      load.angle = l.quantity("angle", units::kAngle);
      if (l.has("paper_torque")) load.paper_torque = l.quantity("paper_torque", torque);
      if (l.has("paper_angle")) load.paper_angle = l.quantity("paper_angle", units::kAngle);
      grp.loads.push_back(load);
    }
    if (grp.loads.empty()) g.error("load", "", "at least one [[group.load]] (a test mass)");
    c.groups.push_back(grp);
  }
  if (c.groups.empty()) root.error("group", "", "at least one [[group]] of tests");
}

void read_balancing_procedure(TomlReader& root, StudyConfig& c) {
  {
    TomlReader t = root.table("procedure");
    c.plane_1_surface = static_cast<int>(t.integer("plane_1_surface", 1, 1000));
    c.plane_2_surface = static_cast<int>(t.integer("plane_2_surface", 1, 1000));
    if (c.plane_1_surface == c.plane_2_surface) {
      t.error("plane_2_surface", std::to_string(c.plane_2_surface), "a surface other than plane_1_surface");
    }
    c.estimator = t.choice("estimator", {"influence", "closed_form"});
    c.calibration_mass = t.quantity("calibration_mass", units::kMass, positive);
    c.calibration_radius = t.quantity("calibration_radius", units::kLength, positive);
    t.string("notes", "");
  }
  const units::Dimension unbalance{{1, 1, 0, 0, 0, 0}};
  for (auto& e : root.table_array("experiment")) {
    BalancingExperiment x;
    x.name = e.string("name");
    x.type = e.choice("type", {"separation", "umar", "stability", "urr", "accuracy"});
    for (const auto& other : c.experiments) {
      if (other.name == x.name) e.error("name", "\"" + x.name + "\"", "a name no other experiment has");
    }
    x.mass = e.quantity("mass", units::kMass, positive);
    x.radius = e.quantity("radius", units::kLength, positive);
    if (x.type == "separation" || x.type == "umar" || x.type == "stability") {
      x.positions = static_cast<int>(e.integer("positions", 1, 360, 8));
    }
    if (x.type == "stability") {
      x.surface = static_cast<int>(e.integer("surface", 1, 1000));
      x.band = e.number("band", [](double v) { return v > 0 && v < 1 ? "" : "a fraction in (0, 1), e.g. 0.12"; }, 0.12);
      x.balance_first = e.boolean("balance_first", true);
    }
    if (x.type == "accuracy") x.piece_unbalance = e.quantity("piece_unbalance", unbalance, positive);
    if (x.type == "urr") {
      x.requirement = e.number("requirement", [](double v) { return v > 0 && v < 1 ? "" : "a fraction in (0, 1), e.g. 0.9"; });
    }
    e.string("notes", "");
    c.experiments.push_back(x);
  }
  if (c.experiments.empty()) root.error("experiment", "", "at least one [[experiment]]");
}

}  // namespace

sampling::Design make_design(const StudyConfig& cfg, std::uint64_t seed, std::size_t samples, std::size_t dimension) {
  sampling::DesignOptions o;
  o.replicate_size = cfg.replicate_size;
  o.saltelli_base = cfg.saltelli_base;
  o.saltelli_noise_group = cfg.saltelli_noise_group;
  return sampling::Design(cfg.method, seed, samples, dimension, o);
}

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
        t.error("name", quote_value(c.name), "a name of letters, digits, '_' and '-' (it names a folder)");
        break;
      }
    }
    c.kind = t.choice("kind", {"seeker_los", "gimbal_static_unbalance", "balancing_machine", "platform_balancing",
                              "geometry_mass_properties", "los_obstruction"});
    const std::string model = t.string("model");
    c.model_path = (std::filesystem::path(path).parent_path() / model).lexically_normal().string();
    std::error_code ec;  // a name too long for the file system is a missing file, not an exception (exit 1)
    if (model.empty() && t.has("model") && t.raw()["model"].is_string()) {
      t.error("model", "\"\"", "the path of the model file, e.g. \"../models/seeker_two_axis_wang2011.toml\"");
    } else if (!model.empty() && !std::filesystem::is_regular_file(c.model_path, ec)) {
      t.error("model", quote_value(model), "an existing model file (looked for " + c.model_path + ")");
    }
    c.title = t.string("title", "");
    c.notes = t.string("notes", "");
  }
  {
    TomlReader t = root.table("sampling");
    c.method = sampling::parse_sampling_method(t.choice("method", {"sobol", "lhs", "monte_carlo"}));
    c.samples = static_cast<std::size_t>(t.integer("samples", 1, 1'000'000'000));
    c.seed = static_cast<std::uint64_t>(t.integer("seed", 0, INT64_MAX));
    c.replicate_size = static_cast<std::size_t>(t.integer("replicate_size", 0, 1'000'000'000, 0));
    if (c.replicate_size > 0 && c.samples % c.replicate_size != 0) {
      t.error("replicate_size", std::to_string(c.replicate_size),
              "a divisor of samples (" + std::to_string(c.samples) + "): whole replicates only");
    } else if (c.replicate_size > 0 && c.method == sampling::SamplingMethod::kSobol &&
               (c.replicate_size & (c.replicate_size - 1)) != 0) {
      t.error("replicate_size", std::to_string(c.replicate_size),
              "a power of two for sobol (a scrambled Sobol replicate is a 2^m net), e.g. 256 or 1024");
    }
    if (t.has("max_failure_share")) {
      c.max_failure_share = t.number("max_failure_share", [](double v) {
        return v >= 0.0 && v <= 1.0 ? std::string() : std::string("a share between 0 and 1, e.g. 0.05");
      });
    }
  }
  if (c.kind == "seeker_los") {
    read_geometry_study(root, c.kind, c.geometry);  // optional [clearance]
    {
      TomlReader t = root.table("grid");
      c.yaw_points = static_cast<std::size_t>(t.integer("yaw_points", 1, 1001));
      c.pitch_points = static_cast<std::size_t>(t.integer("pitch_points", 1, 1001));
    }
    {
      TomlReader t = root.table("requirement");
      c.requirement_text = t.string("los_error");
      if (t.has("los_error") && t.raw()["los_error"].is_string()) {  // else: t.string reported it
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
          t.error("los_error", quote_value(c.requirement_text),
                  std::string("a positive angle or pixel count, e.g. \"1 px\" or \"18 arcsec\" (") +
                      e.what() + ")");
        }
      }
    }
  } else if (c.kind == "platform_balancing") {
    read_platform_section(root, path, c.platform);
  } else if (c.kind == "geometry_mass_properties" || c.kind == "los_obstruction") {
    read_geometry_study(root, c.kind, c.geometry);
  } else if (c.kind == "balancing_machine") {
    read_balancing_procedure(root, c);
    if (root.has("paper")) {
      TomlReader t = root.table("paper");
      for (const auto& key : t.keys()) c.paper.push_back({key, t.number(key), t.line_of(key)});
    }
  } else {
    read_gimbal_groups(root, c);
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
  c.overrides = apply_study_overrides(c, c.overrides);  // study keys (group.*) apply here
  return c;
}

std::map<std::string, std::string> apply_study_overrides(StudyConfig& cfg,
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
    if (cfg.groups.empty()) {
      errors.emplace_back(where, key, "\"" + value + "\"", "a study with [[group]] tables (a gimbal study)");
      continue;
    }
    bool found = name.empty();
    for (auto& g : cfg.groups) {
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
      } else if (rest == "placement") {
        if (value != "sequential" && value != "interleaved" && value != "back_and_forth") {
          errors.emplace_back(where, key, "\"" + value + "\"", "one of \"sequential\", \"interleaved\", \"back_and_forth\"");
          break;
        }
        g.placement = value;
      } else {
        errors.emplace_back(where, key, "\"" + value + "\"",
                            "a study key group[.<name>].positions, .placement or .repeats");
        break;
      }
    }
    if (!found) {
      std::string names;
      for (const auto& g : cfg.groups) names += (names.empty() ? "" : ", ") + g.name;
      errors.emplace_back(where, key, "\"" + value + "\"", "the name of a [[group]]: " + names);
    }
  }
  if (!errors.empty()) throw ValidationError(errors);
  return model_keys;
}

}  // namespace poise::studies
