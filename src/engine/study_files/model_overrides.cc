#include "engine/study_files/model_overrides.h"

#include "core/nearest_name.h"

#include "engine/results/references.h"

namespace poise::engine {
namespace {

// Replaces root[a][b]...[key] by the override text, keeping numbers numbers.
void apply_one(toml::table& root, const std::string& dotted, const std::string& text, ReadContext& ctx) {
  toml::table* t = &root;
  std::size_t pos = 0;
  while (true) {
    const std::size_t dot = dotted.find('.', pos);
    const std::string part = dotted.substr(pos, dot == std::string::npos ? std::string::npos : dot - pos);
    toml::node* n = t->get(part);
    if (!n) {
      std::vector<std::string> here;  // the keys at this level, for "did you mean"
      for (const auto& [k, v] : *t) here.emplace_back(k.str());
      const std::string near = nearest_name(part, here);
      ctx.errors.emplace_back(
          SourceLocation{ctx.file, 0, 0}, dotted, quote_value(text),
          std::string(kUnknownModelKey) +
              (near.empty() ? std::string() : "; did you mean '" + dotted.substr(0, pos) + near + "'?"));
      return;
    }
    if (dot == std::string::npos) {
      if (n->is_integer()) {
        try {
          std::size_t used = 0;
          const long long v = std::stoll(text, &used);
          if (used != text.size()) throw std::invalid_argument(text);
          t->insert_or_assign(part, static_cast<std::int64_t>(v));
        } catch (...) {
          ctx.errors.emplace_back(SourceLocation{ctx.file, 0, 0}, dotted, quote_value(text),
                                  "an integer (the model's value is an integer)");
        }
      } else if (n->is_number()) {
        try {
          t->insert_or_assign(part, std::stod(text));
        } catch (...) {
          ctx.errors.emplace_back(SourceLocation{ctx.file, 0, 0}, dotted, quote_value(text),
                                  "a plain number (the model's value is a number)");
        }
      } else {
        t->insert_or_assign(part, text);
      }
      return;
    }
    t = n->as_table();
    if (!t) {
      ctx.errors.emplace_back(SourceLocation{ctx.file, 0, 0}, dotted, quote_value(text),
                              "a dotted key through tables of the model file");
      return;
    }
    pos = dot + 1;
  }
}

}  // namespace

void apply_overrides(toml::table& root, const std::map<std::string, std::string>& overrides, ReadContext& ctx) {
  for (const auto& [k, v] : overrides) apply_one(root, k, v, ctx);
}

ModelDocument open_model_file(const std::string& path, const std::map<std::string, std::string>& overrides) {
  ModelDocument m{parse_toml_file(path), std::make_shared<ReadContext>()};
  m.ctx->file = path;
  apply_overrides(m.doc, overrides, *m.ctx);
  return m;
}

ModelHeader read_model_header(TomlReader& root, const std::string& kind) {
  const std::size_t errors_before = root.context().errors.size();
  TomlReader t = root.table("model");
  t.choice("kind", {kind});
  // Not a model of this kind (or no model file at all, e.g. a study): say so alone, rather
  // than listing every key such a model would have.
  if (root.context().errors.size() != errors_before) throw ValidationError(root.context().errors);
  ModelHeader h;
  h.file = root.context().file;
  h.name = t.string("name");
  h.title = t.string("title", "");
  h.source = t.string("source", "");
  // [[reference]] tables: figures to compare with, read by the engine (engine/results/references.h).
  read_references(root);
  return h;
}

}  // namespace poise::engine
