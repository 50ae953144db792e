#include "engine/study_files/toml_nesting.h"

#include <string>

namespace poise::engine {
namespace {

// One pass over the text: where it is, and the levels the current value nests in.
struct NestingScan {
  std::string_view text;
  int limit = 0;
  int line = 1;
  std::size_t line_start = 0;
  int header_depth = 0;  // levels of the current [table] / [[array.of.tables]] header
  std::string open;      // open arrays ('a') and inline tables ('t') of the current value
  bool in_key = true;    // reading a key (line start, after '{' or ',' in an inline table)
  bool at_line_start = true;
  int key_depth = 0;  // levels of the dotted key being read

  NestingScan(std::string_view t, int max_depth) : text(t), limit(max_depth) {}

  NestingPlace place(std::size_t i) const { return NestingPlace{line, static_cast<int>(i - line_start) + 1}; }
  int depth() const { return header_depth + static_cast<int>(open.size()) + key_depth; }

  // A newline at i: outside arrays and inline tables, the next line starts a key.
  void end_line(std::size_t i) {
    ++line;
    line_start = i + 1;
    if (open.empty()) {
      in_key = true;
      at_line_start = true;
      key_depth = 0;
    }
  }

  // A comment at i: the index of its last character (the end of the line).
  std::size_t skip_comment(std::size_t i) const {
    while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
    return i;
  }

  // A string at i (basic or literal, one line or multi-line): the index the scan goes on from.
  std::size_t skip_string(std::size_t i) {
    const std::size_t n = text.size();
    const char c = text[i];
    const bool multi = i + 2 < n && text[i + 1] == c && text[i + 2] == c;
    std::size_t j = i + (multi ? 3 : 1);
    for (; j < n; ++j) {
      if (text[j] == '\n') {
        if (!multi) break;  // an unterminated string: toml++ reports it
        ++line;
        line_start = j + 1;
      } else if (c == '"' && text[j] == '\\') {
        ++j;
      } else if (text[j] == c && (!multi || (j + 2 < n && text[j + 1] == c && text[j + 2] == c))) {
        if (multi) j += 2;
        break;
      }
    }
    if (in_key && key_depth == 0) key_depth = 1;
    at_line_start = false;
    return (j < n && text[j] == '\n') ? j - 1 : j;
  }

  // A table header at i: [a.b] or [[a.b]]; `i` moves to the end of its line.
  std::optional<NestingPlace> header(std::size_t& i) {
    const std::size_t n = text.size();
    header_depth = 1;
    for (std::size_t j = i; j < n && text[j] != '\n' && text[j] != ']'; ++j) {
      if (text[j] == '.') {
        if (++header_depth > limit) return place(j);
      } else if (text[j] == '"' || text[j] == '\'') {  // a quoted key part
        const char q = text[j];
        for (++j; j < n && text[j] != q && text[j] != '\n'; ++j) {
        }
        if (j >= n || text[j] == '\n') break;
      }
    }
    i = skip_comment(i);  // the rest of the header line
    at_line_start = false;
    in_key = false;
    key_depth = 0;
    return std::nullopt;
  }

  // A character of a key: '=' ends it, each '.' is a level.
  std::optional<NestingPlace> key_char(char c, std::size_t i) {
    if (c == '=') {
      in_key = false;
    } else if (c == '.') {
      ++key_depth;
      if (depth() > limit) return place(i);
    } else if (key_depth == 0) {
      key_depth = 1;
    }
    return std::nullopt;
  }

  // A character of a value: arrays and inline tables open and close; an inline table's
  // '{' and ',' start a key.
  std::optional<NestingPlace> value_char(char c, std::size_t i) {
    if (c == '[' || c == '{') {
      open.push_back(c == '[' ? 'a' : 't');
      if (depth() > limit) return place(i);
      if (c == '{') {
        in_key = true;
        key_depth = 0;
      }
    } else if (c == ']' || c == '}') {
      if (!open.empty()) open.pop_back();
    } else if (c == ',' && !open.empty() && open.back() == 't') {
      in_key = true;
      key_depth = 0;
    }
    return std::nullopt;
  }
};

}  // namespace

std::optional<NestingPlace> find_too_deep_nesting(std::string_view text, int limit) {
  NestingScan s(text, limit);
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      s.end_line(i);
      continue;
    }
    if (c == ' ' || c == '\t' || c == '\r') continue;
    std::optional<NestingPlace> deep;
    if (c == '#') {  // a comment: to the end of the line
      i = s.skip_comment(i);
    } else if (c == '"' || c == '\'') {
      i = s.skip_string(i);
    } else if (s.at_line_start && s.open.empty() && c == '[') {
      deep = s.header(i);
    } else {
      s.at_line_start = false;
      deep = s.in_key ? s.key_char(c, i) : s.value_char(c, i);
    }
    if (deep) return deep;
  }
  return std::nullopt;
}

}  // namespace poise::engine
