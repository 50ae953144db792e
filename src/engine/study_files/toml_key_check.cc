// Unknown keys and the key schema: finish() refuses every key nobody read, with the nearest
// key asked for at that place ("did you mean", by edit distance); KeySchemaRecorder records
// the keys asked for (`poise keys`).
#include "engine/study_files/toml_reader.h"

#include "core/nearest_name.h"

#include "engine/study_files/toml_reader_detail.h"

#include <algorithm>

namespace poise::engine {
namespace detail {

// "group[3].load[0].mass" -> "group[].load[].mass": the schema's form of a path.
std::string schema_path(const std::string& path) {
  std::string out;
  for (std::size_t i = 0; i < path.size(); ++i) {
    out += path[i];
    if (path[i] == '[') {
      while (i + 1 < path.size() && path[i + 1] != ']') ++i;
    }
  }
  return out;
}

}  // namespace detail

namespace {
using detail::location_of;
using detail::schema_path;

thread_local KeySchemaRecorder* g_recorder = nullptr;

// The key asked for at the same place as the unknown `path` whose name is nearest to it.
std::string nearest_key(const std::string& path, const ReadContext& ctx) {
  const std::string sp = schema_path(path);
  const auto dot = sp.rfind('.');
  const std::string parent = dot == std::string::npos ? "" : sp.substr(0, dot);
  const std::string name = dot == std::string::npos ? sp : sp.substr(dot + 1);
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, name.size() / 3) + 1;
  for (const auto& k : ctx.asked) {
    const auto kd = k.path.rfind('.');
    const std::string kp = kd == std::string::npos ? "" : k.path.substr(0, kd);
    const std::string kn = kd == std::string::npos ? k.path : k.path.substr(kd + 1);
    if (kp != parent || kn == name) continue;
    const std::size_t d = edit_distance(name, kn);
    if (d < best_d) {
      best_d = d;
      best = kn;
    }
  }
  return best;
}

void walk_unknown(const toml::table& t, const std::string& prefix, ReadContext& ctx) {
  for (const auto& [k, v] : t) {
    const std::string path = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (!ctx.used.count(path)) {
      const std::string near = nearest_key(path, ctx);
      ctx.errors.emplace_back(location_of(ctx.file, &v), path, describe_node(v),
                              near.empty() ? "no such key here (unknown key; `poise keys KIND` lists the keys)"
                                           : "no such key here (unknown key); did you mean '" + near + "'?");
      continue;
    }
    if (const auto* sub = v.as_table()) walk_unknown(*sub, path, ctx);
    if (const auto* arr = v.as_array()) {
      for (std::size_t i = 0; i < arr->size(); ++i) {
        if (const auto* st = arr->get(i)->as_table()) {
          walk_unknown(*st, path + "[" + std::to_string(i) + "]", ctx);
        }
      }
    }
  }
}
}  // namespace

KeySchemaRecorder::KeySchemaRecorder(std::string kind) : kind_(std::move(kind)), previous_(g_recorder) {
  g_recorder = this;
}
KeySchemaRecorder::~KeySchemaRecorder() { g_recorder = previous_; }
KeySchemaRecorder* KeySchemaRecorder::active() { return g_recorder; }

void KeySchemaRecorder::add(const ReadContext& ctx) {
  auto& into = ctx.file == kSchemaStudyFile ? study_keys : model_keys;
  for (const auto& k : ctx.asked) {
    if (std::none_of(into.begin(), into.end(), [&](const KeyDoc& d) { return d.path == k.path; })) into.push_back(k);
  }
}

void finish(const toml::table& root, ReadContext& ctx) {
  if (KeySchemaRecorder* rec = KeySchemaRecorder::active()) {
    rec->add(ctx);
    return;
  }
  walk_unknown(root, "", ctx);
  if (!ctx.errors.empty()) {
    std::stable_sort(ctx.errors.begin(), ctx.errors.end(),
                     [](const InputError& a, const InputError& b) { return a.where().line < b.where().line; });
    throw ValidationError(ctx.errors);
  }
}

}  // namespace poise::engine
