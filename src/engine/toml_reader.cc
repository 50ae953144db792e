#include "engine/toml_reader.h"

#include "engine/toml_nesting.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <deque>
#include <iterator>
#include <mutex>
#include <optional>
#include <sstream>

namespace poise::studies {
namespace {
std::string join_errors(const std::vector<InputError>& errors) {
  std::string out = std::to_string(errors.size()) + (errors.size() == 1 ? " error" : " errors") +
                    " in the input:";
  constexpr std::size_t kMaxListed = 20;  // a message a person reads, not a dump
  for (std::size_t k = 0; k < errors.size() && k < kMaxListed; ++k) out += "\n  " + std::string(errors[k].what());
  if (errors.size() > kMaxListed) out += "\n  and " + std::to_string(errors.size() - kMaxListed) + " more";
  return out;
}

SourceLocation location_of(const std::string& file, const toml::node* n) {
  SourceLocation loc{file, 0, 0};
  if (n) {
    loc.line = static_cast<int>(n->source().begin.line);
    loc.column = static_cast<int>(n->source().begin.column);
  }
  return loc;
}

thread_local KeySchemaRecorder* g_recorder = nullptr;

std::string describe_number(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

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

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

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

ValidationError::ValidationError(std::vector<InputError> errors)
    : Error(join_errors(errors)), errors_(std::move(errors)) {}

std::string quote_value(const std::string& v) {
  constexpr std::size_t kMaxQuoted = 80;
  if (v.size() <= kMaxQuoted) return "\"" + v + "\"";
  std::size_t cut = kMaxQuoted;
  while (cut > 0 && (static_cast<unsigned char>(v[cut]) & 0xC0) == 0x80) --cut;  // whole UTF-8 characters
  return "\"" + v.substr(0, cut) + "...\" (" + std::to_string(v.size()) + " bytes)";
}

std::string describe_node(const toml::node& n) {
  if (const auto* s = n.as_string()) return quote_value(s->get());
  if (n.is_table()) return "{...}";
  if (n.is_array()) return "[...]";
  std::ostringstream os;
  n.visit([&os](const auto& v) {
    if constexpr (toml::is_integer<decltype(v)> || toml::is_floating_point<decltype(v)> ||
                  toml::is_boolean<decltype(v)> || toml::is_date<decltype(v)> ||
                  toml::is_time<decltype(v)> || toml::is_date_time<decltype(v)>) {
      os << v.get();
    } else {
      os << "(value)";
    }
  });
  return os.str();
}

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

namespace {

// The last files parsed, with their text: a study's model file is read by several stages
// (validation, references, outputs, the run), and a file holding a 1 MB string must not be
// parsed ten times. A file is taken from here only when its text is unchanged.
struct ParsedFile {
  std::string path, text;
  toml::table table;
};
std::mutex g_parsed_mutex;
std::deque<ParsedFile> g_parsed;

std::optional<toml::table> parsed_before(const std::string& path, const std::string& text) {
  const std::lock_guard<std::mutex> lock(g_parsed_mutex);
  for (const auto& f : g_parsed) {
    if (f.path == path && f.text == text) return f.table;
  }
  return std::nullopt;
}

void remember_parsed(const std::string& path, std::string text, const toml::table& table) {
  constexpr std::size_t kKept = 4;
  const std::lock_guard<std::mutex> lock(g_parsed_mutex);
  g_parsed.push_front(ParsedFile{path, std::move(text), table});
  if (g_parsed.size() > kKept) g_parsed.pop_back();
}

}  // namespace

toml::table parse_toml_file(const std::string& path) {
  if (const KeySchemaRecorder* rec = KeySchemaRecorder::active()) {
    toml::table t;
    if (path == kSchemaStudyFile) t.insert("study", toml::table{{"kind", rec->kind()}});
    return t;
  }
  // Only regular files of sane size: a directory would read as an empty file, a device
  // such as /dev/zero or a FIFO would be read forever.
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  std::string problem;
  if (ec && ec != std::errc::no_such_file_or_directory) {
    problem = "cannot be read: " + ec.message();  // e.g. "File name too long"
  } else if (!std::filesystem::exists(status)) {
    problem = "no such file";
  } else if (std::filesystem::is_directory(status)) {
    problem = "a directory";
  } else if (!std::filesystem::is_regular_file(status)) {
    problem = "not a regular file (a device, FIFO or socket)";
  } else if (const auto size = std::filesystem::file_size(path, ec); !ec && size > kMaxInputFileBytes) {
    problem = std::to_string(size) + " bytes";
  }
  if (!problem.empty()) {
    throw ValidationError({InputError(SourceLocation{path, 0, 0}, "(file)", problem,
                                      "a readable TOML file (a regular file of at most " +
                                          std::to_string(kMaxInputFileBytes >> 20) + " MiB)")});
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw ValidationError({InputError(SourceLocation{path, 0, 0}, "(file)", "cannot be opened",
                                      "a readable TOML file")});
  }
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (auto parsed = parsed_before(path, text)) return std::move(*parsed);
  // toml++ descends recursively: a file nested tens of thousands of levels deep would
  // overflow the stack. Such a file is refused before it is parsed.
  if (const auto deep = find_too_deep_nesting(text)) {
    throw ValidationError({InputError(SourceLocation{path, deep->line, deep->column}, "(syntax)", "",
                                      "valid TOML nested at most " + std::to_string(kMaxTomlNesting) +
                                          " levels deep (table headers, dotted keys, arrays and inline tables "
                                          "together); it goes deeper here")});
  }
  try {
    toml::table table = toml::parse(text, path);
    remember_parsed(path, std::move(text), table);
    return table;
  } catch (const toml::parse_error& e) {
    SourceLocation loc{path, static_cast<int>(e.source().begin.line),
                       static_cast<int>(e.source().begin.column)};
    if (e.source().begin.line == 0) {
      throw ValidationError({InputError(loc, "(file)", "", "a readable TOML file: " +
                                                              std::string(e.description()))});
    }
    throw ValidationError(
        {InputError(loc, "(syntax)", "", "valid TOML: " + std::string(e.description()))});
  }
}

TomlReader::TomlReader(const toml::table& table, std::shared_ptr<ReadContext> ctx,
                       std::string prefix)
    : table_(&table), ctx_(std::move(ctx)), prefix_(std::move(prefix)) {}

std::string TomlReader::path(const std::string& key) const {
  return prefix_.empty() ? key : prefix_ + "." + key;
}

bool TomlReader::has(const std::string& key) const { return table_->contains(key); }

int TomlReader::line_of(const std::string& key) const {
  const toml::node* n = table_->get(key);
  return n ? static_cast<int>(n->source().begin.line) : 0;
}

void TomlReader::ask(const std::string& key, const std::string& expected, const std::string& fallback, bool required) {
  const std::string p = schema_path(path(key));
  for (const auto& k : ctx_->asked) {
    if (k.path == p) return;
  }
  ctx_->asked.push_back({p, expected, fallback, required});
}

const toml::node* TomlReader::node(const std::string& key) {
  const toml::node* n = table_->get(key);
  if (n) ctx_->used.insert(path(key));
  return n;
}

void TomlReader::error(const std::string& key, const std::string& value,
                       const std::string& expected) {
  if (schema_only()) return;
  const toml::node* n = table_->get(key);
  SourceLocation loc = location_of(ctx_->file, n);
  if (!n) {  // missing key: point at the table
    loc.line = static_cast<int>(table_->source().begin.line);
    loc.column = 0;
  }
  ctx_->errors.emplace_back(loc, path(key), value, expected);
}

TomlReader TomlReader::table(const std::string& key, bool required) {
  static const toml::table kEmpty;
  ask(key, "a table [" + schema_path(path(key)) + "]", required ? "" : "(optional)", required);
  const toml::node* n = node(key);
  if (!n) {
    if (required) error(key, "", "a table [" + path(key) + "] (missing)");
    return TomlReader(kEmpty, ctx_, path(key));
  }
  if (!n->is_table()) {
    error(key, describe_node(*n), "a table [" + path(key) + "]");
    return TomlReader(kEmpty, ctx_, path(key));
  }
  return TomlReader(*n->as_table(), ctx_, path(key));
}

std::vector<std::string> TomlReader::keys() const {
  std::vector<std::pair<int, std::string>> ordered;
  for (const auto& [k, v] : *table_) {
    ordered.emplace_back(static_cast<int>(v.source().begin.line), std::string(k.str()));
  }
  std::stable_sort(ordered.begin(), ordered.end());
  std::vector<std::string> out;
  for (auto& p : ordered) out.push_back(p.second);
  return out;
}

std::vector<TomlReader> TomlReader::table_array(const std::string& key) {
  static const toml::table kEmpty;
  std::vector<TomlReader> out;
  ask(key, "tables [[" + schema_path(path(key)) + "]]", "(optional)", false);
  const toml::node* n = node(key);
  if (!n && schema_only()) out.emplace_back(kEmpty, ctx_, path(key) + "[]");  // its keys, for the schema
  if (!n) return out;
  const auto* arr = n->as_array();
  if (!arr || !arr->is_array_of_tables()) {
    error(key, describe_node(*n), "an array of tables [[" + path(key) + "]]");
    return out;
  }
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const std::string p = path(key) + "[" + std::to_string(i) + "]";
    out.emplace_back(*arr->get(i)->as_table(), ctx_, p);
  }
  return out;
}

std::string TomlReader::string(const std::string& key, std::optional<std::string> fallback) {
  ask(key, "a string", fallback ? (fallback->empty() ? "\"\"" : "\"" + *fallback + "\"") : "", !fallback);
  const toml::node* n = node(key);
  if (!n) {
    if (!fallback) error(key, "", "a string (missing)");
    return fallback.value_or("");
  }
  if (const auto* s = n->as_string()) return s->get();
  error(key, describe_node(*n), "a string in quotes");
  return fallback.value_or("");
}

std::string TomlReader::choice(const std::string& key, const std::vector<std::string>& choices,
                               std::optional<std::string> fallback) {
  std::string options;
  for (const auto& c : choices) options += (options.empty() ? "\"" : " | \"") + c + "\"";
  ask(key, "one of " + options, fallback ? "\"" + *fallback + "\"" : "", !fallback);
  if (schema_only()) {
    const toml::node* n = node(key);
    if (n && n->is_string()) return n->as_string()->get();
    return fallback ? *fallback : choices.front();
  }
  const bool present = has(key);
  std::string v = string(key, fallback ? fallback : std::optional<std::string>(""));
  if (!present && !fallback) {
    std::string list;
    for (const auto& c : choices) list += (list.empty() ? "\"" : ", \"") + c + "\"";
    error(key, "", "one of " + list + " (missing)");
    return choices.front();
  }
  for (const auto& c : choices) {
    if (c == v) return v;
  }
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "\"" : ", \"") + c + "\"";
  error(key, quote_value(v), "one of " + list);
  return choices.front();
}

double TomlReader::quantity(const std::string& key, const units::Dimension& dim,
                            const std::function<std::string(double)>& check,
                            std::optional<double> fallback) {
  const std::string example = units::example_unit(dim);
  ask(key, units::dimension_name(dim) + " with its unit, e.g. \"1 " + example + "\"",
      fallback ? units::format(*fallback, example) : "", !fallback);
  if (schema_only()) {  // a value the check accepts, so that readers go on
    node(key);
    if (fallback) return *fallback;
    for (double v : {1.0, 0.5, 0.0, -1.0}) {
      if (!check || check(v).empty()) return v;
    }
    return 1.0;
  }
  const toml::node* n = node(key);
  if (!n) {
    if (!fallback) {
      error(key, "", units::dimension_name(dim) + " with its unit, e.g. \"1 " + example +
                         "\" (missing)");
    }
    return fallback.value_or(0.0);
  }
  const auto* s = n->as_string();
  if (!s) {
    if (n->is_number() && !(dim == units::kDimensionless)) {
      error(key, describe_node(*n), units::dimension_name(dim) + " with its unit in quotes, e.g. \"" +
                                        describe_node(*n) + " " + example + "\" (missing unit)");
    } else {
      error(key, describe_node(*n), units::dimension_name(dim) + " as a string, e.g. \"1 " +
                                        example + "\"");
    }
    return fallback.value_or(0.0);
  }
  try {
    const double v = units::parse_as(s->get(), dim);
    if (check) {
      const std::string problem = check(v);
      if (!problem.empty()) {
        error(key, describe_node(*n), problem);
        return fallback.value_or(v);
      }
    }
    return v;
  } catch (const Error& e) {
    // units::parse_as says "<problem>; expected <what>": lead with what was expected.
    const std::string msg = e.what();
    const auto split = msg.find("; expected ");
    error(key, describe_node(*n),
          split == std::string::npos ? msg : msg.substr(split + 11) + " (" + msg.substr(0, split) + ")");
    return fallback.value_or(0.0);
  }
}

double TomlReader::number(const std::string& key, const std::function<std::string(double)>& check,
                          std::optional<double> fallback) {
  ask(key, "a plain number (no unit)", fallback ? describe_number(*fallback) : "", !fallback);
  if (schema_only()) {
    node(key);
    if (fallback) return *fallback;
    for (double v : {1.0, 0.5, 0.0, -1.0}) {
      if (!check || check(v).empty()) return v;
    }
    return 1.0;
  }
  const toml::node* n = node(key);
  if (!n) {
    if (!fallback) error(key, "", "a number (missing)");
    return fallback.value_or(0.0);
  }
  std::optional<double> v;
  if (const auto* f = n->as_floating_point()) v = f->get();
  if (const auto* i = n->as_integer()) v = static_cast<double>(i->get());
  if (!v) {
    error(key, describe_node(*n), "a plain number (no unit), e.g. 0.4");
    return fallback.value_or(0.0);
  }
  if (!std::isfinite(*v)) {  // TOML has nan and inf; no input of Poise means them
    error(key, describe_node(*n), "a finite number");
    return fallback.value_or(0.0);
  }
  if (check) {
    const std::string problem = check(*v);
    if (!problem.empty()) {
      error(key, describe_node(*n), problem);
      return fallback.value_or(*v);
    }
  }
  return *v;
}

std::int64_t TomlReader::integer(const std::string& key, std::int64_t min, std::int64_t max,
                                 std::optional<std::int64_t> fallback) {
  const std::string range = "an integer from " + std::to_string(min) + " to " + std::to_string(max);
  ask(key, range, fallback ? std::to_string(*fallback) : "", !fallback);
  const toml::node* n = node(key);
  if (!n) {
    if (!fallback) error(key, "", range + " (missing)");
    return fallback.value_or(min);
  }
  const auto* i = n->as_integer();
  if (!i || i->get() < min || i->get() > max) {
    error(key, describe_node(*n), range);
    return fallback.value_or(min);
  }
  return i->get();
}

bool TomlReader::boolean(const std::string& key, std::optional<bool> fallback) {
  ask(key, "true or false", fallback ? (*fallback ? "true" : "false") : "", !fallback);
  const toml::node* n = node(key);
  if (!n) {
    if (!fallback) error(key, "", "true or false (missing)");
    return fallback.value_or(false);
  }
  if (const auto* b = n->as_boolean()) return b->get();
  error(key, describe_node(*n), "true or false");
  return fallback.value_or(false);
}

std::vector<std::string> TomlReader::string_array(const std::string& key) {
  std::vector<std::string> out;
  ask(key, "an array of strings", "", true);
  const toml::node* n = node(key);
  if (!n) {
    error(key, "", "an array of strings (missing)");
    return out;
  }
  const auto* arr = n->as_array();
  if (!arr) {
    error(key, describe_node(*n), "an array of strings, e.g. [\"60 mm\", \"82 mm\"]");
    return out;
  }
  for (const auto& el : *arr) {
    if (const auto* s = el.as_string()) {
      out.push_back(s->get());
    } else {
      error(key, describe_node(el), "an array of strings only");
    }
  }
  return out;
}

void TomlReader::accept_all() {
  for (const auto& [k, v] : *table_) {
    ctx_->used.insert(path(std::string(k.str())));
    if (v.is_table()) TomlReader(*v.as_table(), ctx_, path(std::string(k.str()))).accept_all();
  }
}

void TomlReader::accept_notes() {
  string("notes", "");
  string("source", "");
}

void finish(const toml::table& root, ReadContext& ctx) {
  if (KeySchemaRecorder* rec = KeySchemaRecorder::active()) {
    rec->add(ctx);
    return;
  }
  walk_unknown(root, "", ctx);
  if (!ctx.errors.empty()) {
    std::stable_sort(ctx.errors.begin(), ctx.errors.end(), [](const InputError& a, const InputError& b) {
      return a.where().line < b.where().line;
    });
    throw ValidationError(ctx.errors);
  }
}

std::string positive(double v) { return v > 0 ? "" : "a positive value"; }
std::string non_negative(double v) { return v >= 0 ? "" : "a value >= 0"; }

}  // namespace poise::studies
