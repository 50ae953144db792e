// Reading a TOML file and reporting its errors: parse_toml_file with its parse cache,
// ValidationError (the errors joined into one message), source locations, and values
// described for messages (describe_node, quote_value).
#include "engine/study_files/toml_reader.h"

#include "engine/study_files/toml_nesting.h"
#include "engine/study_files/toml_reader_detail.h"

#include <deque>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <optional>
#include <sstream>

namespace poise::engine {
namespace {
std::string join_errors(const std::vector<InputError>& errors) {
  std::string out = std::to_string(errors.size()) + (errors.size() == 1 ? " error" : " errors") + " in the input:";
  constexpr std::size_t kMaxListed = 20;  // a message a person reads, not a dump
  for (std::size_t k = 0; k < errors.size() && k < kMaxListed; ++k) out += "\n  " + std::string(errors[k].what());
  if (errors.size() > kMaxListed) out += "\n  and " + std::to_string(errors.size() - kMaxListed) + " more";
  return out;
}
}  // namespace

namespace detail {

SourceLocation location_of(const std::string& file, const toml::node* n) {
  SourceLocation loc{file, 0, 0};
  if (n) {
    loc.line = static_cast<int>(n->source().begin.line);
    loc.column = static_cast<int>(n->source().begin.column);
  }
  return loc;
}

}  // namespace detail

ValidationError::ValidationError(std::vector<InputError> errors)
    : Error(join_errors(errors)), errors_(std::move(errors)) {}

std::string quote_value(const std::string& v) {
  constexpr std::size_t kMaxQuoted = 80;
  if (v.size() <= kMaxQuoted) return "\"" + v + "\"";
  std::size_t cut = kMaxQuoted;
  while (cut > 0 && (static_cast<unsigned char>(v[cut]) & 0xC0) == 0x80) --cut;  // whole UTF-8 characters
  std::string out = "\"";  // appended: "\"" + a temporary trips GCC 12's -Wrestrict (PR 105329)
  out.append(v, 0, cut);
  return out + "...\" (" + std::to_string(v.size()) + " bytes)";
}

std::string describe_node(const toml::node& n) {
  if (const auto* s = n.as_string()) return quote_value(s->get());
  if (n.is_table()) return "{...}";
  if (n.is_array()) return "[...]";
  std::ostringstream os;
  n.visit([&os](const auto& v) {
    if constexpr (toml::is_integer<decltype(v)> || toml::is_floating_point<decltype(v)> ||
                  toml::is_boolean<decltype(v)> || toml::is_date<decltype(v)> || toml::is_time<decltype(v)> ||
                  toml::is_date_time<decltype(v)>) {
      os << v.get();
    } else {
      os << "(value)";
    }
  });
  return os.str();
}

namespace {

// The last large files parsed, with their text: a study's model file is read by several stages
// (validation, references, outputs, the run), and a file holding a 1 MB string must not be
// parsed ten times. A file is taken from here only when its text is unchanged. A copy of a
// toml::table loses the source positions of its nodes (toml++ 3.3), so a file small enough to
// parse again in well under a millisecond is parsed again: its errors keep their lines, and
// readers that keep the file's order of keys (by line) see it.
constexpr std::size_t kCachedFileBytes = 64 * 1024;
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
    throw ValidationError({InputError(
        SourceLocation{path, 0, 0}, "(file)", problem,
        "a readable TOML file (a regular file of at most " + std::to_string(kMaxInputFileBytes >> 20) + " MiB)")});
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw ValidationError(
        {InputError(SourceLocation{path, 0, 0}, "(file)", "cannot be opened", "a readable TOML file")});
  }
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.size() >= kCachedFileBytes) {
    if (auto parsed = parsed_before(path, text)) return std::move(*parsed);
  }
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
    if (text.size() >= kCachedFileBytes) remember_parsed(path, std::move(text), table);
    return table;
  } catch (const toml::parse_error& e) {
    SourceLocation loc{path, static_cast<int>(e.source().begin.line), static_cast<int>(e.source().begin.column)};
    if (e.source().begin.line == 0) {
      throw ValidationError({InputError(loc, "(file)", "", "a readable TOML file: " + std::string(e.description()))});
    }
    throw ValidationError({InputError(loc, "(syntax)", "", "valid TOML: " + std::string(e.description()))});
  }
}

}  // namespace poise::engine
