#include "engine/study_files/toml_nesting.h"

#include <string>

namespace poise::engine {

std::optional<NestingPlace> find_too_deep_nesting(std::string_view text, int limit) {
  int line = 1;
  std::size_t line_start = 0;
  int header_depth = 0;    // levels of the current [table] / [[array.of.tables]] header
  std::string open;        // open arrays ('a') and inline tables ('t') of the current value
  bool in_key = true;      // reading a key (line start, after '{' or ',' in an inline table)
  bool at_line_start = true;
  int key_depth = 0;       // levels of the dotted key being read
  auto place = [&](std::size_t i) {
    return NestingPlace{line, static_cast<int>(i - line_start) + 1};
  };
  auto depth = [&] { return header_depth + static_cast<int>(open.size()) + key_depth; };
  const std::size_t n = text.size();
  for (std::size_t i = 0; i < n; ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      line_start = i + 1;
      if (open.empty()) {
        in_key = true;
        at_line_start = true;
        key_depth = 0;
      }
      continue;
    }
    if (c == ' ' || c == '\t' || c == '\r') continue;
    if (c == '#') {  // a comment: to the end of the line
      while (i + 1 < n && text[i + 1] != '\n') ++i;
      continue;
    }
    if (c == '"' || c == '\'') {  // a string (basic or literal, one line or multi-line)
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
      i = (j < n && text[j] == '\n') ? j - 1 : j;
      continue;
    }
    if (at_line_start && open.empty() && c == '[') {  // a table header: [a.b] or [[a.b]]
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
      while (i + 1 < n && text[i + 1] != '\n') ++i;  // the rest of the header line
      at_line_start = false;
      in_key = false;
      key_depth = 0;
      continue;
    }
    at_line_start = false;
    if (in_key) {
      if (c == '=') {
        in_key = false;
      } else if (c == '.') {
        ++key_depth;
        if (depth() > limit) return place(i);
      } else if (key_depth == 0) {
        key_depth = 1;
      }
      continue;
    }
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
  }
  return std::nullopt;
}

}  // namespace poise::engine
