#include "engine/study_files/study_config.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "engine/kind_interface/study_kind.h"
#include "engine/results/references.h"
#include "engine/results/requirements.h"
#include "engine/study_files/toml_reader.h"

namespace poise::engine {

void throw_wrong_sections(const StudyConfig& cfg) {
  throw Error(cfg.file + ": the sections of a '" + cfg.kind + "' study were asked for as another kind's");
}

sampling::Design make_design(const StudyConfig& cfg, std::uint64_t seed, std::size_t samples, std::size_t dimension) {
  sampling::DesignOptions o;
  o.replicate_size = cfg.replicate_size;
  o.saltelli_base = cfg.saltelli_base;
  o.saltelli_noise_group = cfg.saltelli_noise_group;
  o.saltelli_noise_sources = cfg.saltelli_noise_sources;
  if (cfg.saltelli_base > 0) o.saltelli_extra_groups = cfg.saltelli_groups;
  return sampling::Design(cfg.method, seed, samples, dimension, o);
}

namespace {

// One error naming what the file is when it has no [study] table, not one per missing key.
void require_study_table(const toml::table& doc, const std::string& path) {
  if (doc.contains("study")) return;
  const std::string what =
      doc.contains("budget")  ? "a study file; this is an error budget: check it with `poise budget " + path + "`"
      : doc.contains("model") ? "a study file; this is a model file, which a study names in [study] model"
                              : "a study file: a [study] table with name, kind and model";
  throw ValidationError({InputError(SourceLocation{path, 1, 1}, "study", "(no [study] table)", what)});
}

// [study]: name, kind, model, title, notes. Returns the kind if the file names a known one.
const StudyKind* read_study_table(TomlReader& root, const std::string& path, StudyConfig& c) {
  TomlReader t = root.table("study");
  c.name = t.string("name");
  if (t.has("name") && t.raw()["name"].is_string()) {
    bool ok = !c.name.empty() && c.name.size() <= 100;
    for (char ch : c.name) ok = ok && (std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-');
    if (!ok)
      t.error("name", quote_value(c.name),
              "a name of 1 to 100 letters, digits, '_' and '-' (it names the results folder)");
  }
  const std::vector<std::string> kinds = study_kind_names();
  c.kind = t.choice("kind", kinds);
  // An unknown kind is the error to report: no kind's sections are read in its place.
  const std::string written = t.has("kind") ? t.raw()["kind"].value_or(std::string()) : std::string();
  const StudyKind* kind = std::find(kinds.begin(), kinds.end(), written) != kinds.end() ? &study_kind(c.kind) : nullptr;
  const std::string model = t.string("model");
  c.model_path = (std::filesystem::path(path).parent_path() / model).lexically_normal().string();
  std::error_code ec;  // a name too long for the file system is a missing file, not an exception (exit 1)
  if (model.empty() && t.has("model") && t.raw()["model"].is_string()) {
    t.error("model", "\"\"", "the path of the model file, e.g. \"../models/seeker_two_axis_wang2011.toml\"");
  } else if (!model.empty() && !std::filesystem::is_regular_file(c.model_path, ec)) {
    const std::string looked = std::filesystem::absolute(c.model_path, ec).lexically_normal().string();
    t.error("model", quote_value(model),
            "an existing model file, its path taken from the study file's folder (looked for " +
                (looked.empty() ? c.model_path : looked) + ")");
  }
  c.title = t.string("title", "");
  c.notes = t.string("notes", "");
  return kind;
}

// [sampling]: method, samples, seed, replicate_size, max_failure_share.
void read_sampling_table(TomlReader& root, StudyConfig& c) {
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
  if (t.has_or_schema("max_failure_share")) {
    c.max_failure_share = t.number(
        "max_failure_share",
        [](double v) {
          return v >= 0.0 && v <= 1.0 ? std::string() : std::string("a share between 0 and 1, e.g. 0.05");
        },
        0.05);
  }
}

// [output]: plots, block, contribution_samples, samples_csv (a kind reads its own keys there too).
void read_output_table(TomlReader& root, StudyConfig& c) {
  if (!root.has_or_schema("output")) return;
  TomlReader t = root.table("output");
  c.plots = t.boolean("plots", true);
  c.block = static_cast<std::size_t>(t.integer("block", 1, 1'000'000, 1024));
  t.ask("contribution_samples", "an integer from 0 to 1000000000 (0: no contributions)", "0 (the seeker: 4096)", false);
  c.contribution_samples = static_cast<std::size_t>(t.integer("contribution_samples", 0, 1'000'000'000, 0));
  c.samples_csv = t.boolean("samples_csv", true);
}

// [[sweep]] tables: parameter, values, samples.
void read_sweeps(TomlReader& root, StudyConfig& c) {
  for (auto& t : root.table_array("sweep")) {
    SweepSpec sw;
    sw.line = t.line_of("parameter");
    sw.parameter = t.string("parameter");
    sw.values = t.string_array("values");
    if (sw.values.empty() && t.has("values")) t.error("values", "[]", "at least one value, with its unit");
    t.ask("samples", "an integer from 1 to 1000000000", "the run's sample count", false);  // its schema's default
    sw.samples = static_cast<std::size_t>(t.integer("samples", 1, 1'000'000'000, 0));      // 0: the run's
    c.sweeps.push_back(sw);
  }
}

}  // namespace

StudyConfig load_study(const std::string& path) {
  toml::table doc = parse_toml_file(path);
  auto ctx = std::make_shared<ReadContext>();
  ctx->file = path;
  TomlReader root(doc, ctx);
  StudyConfig c;
  c.file = path;
  require_study_table(doc, path);
  const StudyKind* kind = read_study_table(root, path, c);
  read_sampling_table(root, c);
  c.requirements = read_requirements(root);  // before the kind's: a shorthand may add one
  if (kind) {
    c.sections = kind->read_sections(root, c);
  } else if (!root.schema_only()) {
    root.accept_all();  // the kind's sections are not known: they are not errors of their own
  }
  if (root.has_or_schema("overrides")) {
    TomlReader t = root.table("overrides");
    for (const auto& key : t.keys()) c.overrides[key] = t.string(key);
  }
  read_output_table(root, c);
  c.references = read_references(root);
  read_sweeps(root, c);
  finish(doc, *ctx);
  c.overrides = apply_study_overrides(c, c.overrides);  // the kind's study keys apply here
  return c;
}

std::map<std::string, std::string> apply_study_overrides(StudyConfig& cfg,
                                                         const std::map<std::string, std::string>& overrides) {
  return study_kind(cfg.kind).apply_study_overrides(cfg, overrides);
}

}  // namespace poise::engine
