#include "engine/report/report_contents.h"

#include <cctype>
#include <set>
#include <vector>

namespace poise::engine {
namespace {

struct Section {
  std::size_t begin = 0, end = 0;  ///< the opening tag's place in the page
  std::string id, text;
  bool has_id = false;
};

std::string plain_text(const std::string& html) {
  std::string out;
  bool in_tag = false;
  for (char c : html) {
    if (c == '<') in_tag = true;
    if (!in_tag) out += c;
    if (c == '>') in_tag = false;
  }
  return out;
}

std::string slug(const std::string& text) {
  std::string s;
  for (unsigned char c : text) {
    if (std::isalnum(c)) {
      s += static_cast<char>(std::tolower(c));
    } else if (!s.empty() && s.back() != '-') {
      s += '-';
    }
    if (s.size() >= 40) break;
  }
  while (!s.empty() && s.back() == '-') s.pop_back();
  return s.empty() ? "section" : s;
}

bool space_char(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

/// The section heading whose "<h2" is at `at`: <h2> or <h2 id='x'> (spaces allowed), up to
/// its </h2>; false for anything else. A scan by hand: the page holds MBs of inline figures.
bool heading_at(const std::string& page, std::size_t at, Section& s) {
  std::size_t i = at + 3;
  auto skip_spaces = [&] {
    while (i < page.size() && space_char(page[i])) ++i;
  };
  const bool spaced = i < page.size() && space_char(page[i]);
  skip_spaces();
  s.has_id = false;
  if (spaced && page.compare(i, 2, "id") == 0) {
    i += 2;
    skip_spaces();
    if (i >= page.size() || page[i] != '=') return false;
    ++i;
    skip_spaces();
    if (i >= page.size() || (page[i] != '\'' && page[i] != '"')) return false;
    const std::size_t end = page.find_first_of("'\"", i + 1);
    if (end == std::string::npos) return false;
    s.id = page.substr(i + 1, end - i - 1);
    s.has_id = true;
    i = end + 1;
    skip_spaces();
  }
  if (i >= page.size() || page[i] != '>') return false;
  const std::size_t close = page.find("</h2>", i + 1);
  if (close == std::string::npos) return false;
  s.begin = at;
  s.end = at + 3;  // after "<h2"
  s.text = plain_text(page.substr(i + 1, close - i - 1));
  return true;
}

std::vector<Section> sections_of(const std::string& page) {
  std::vector<Section> out;
  std::set<std::string> used;
  for (std::size_t at = page.find("<h2"); at != std::string::npos; at = page.find("<h2", at + 3)) {
    Section s;
    if (!heading_at(page, at, s)) continue;
    if (!s.has_id) {
      s.id = slug(s.text);
      for (int k = 2; used.count(s.id); ++k) s.id = slug(s.text) + "-" + std::to_string(k);
    }
    used.insert(s.id);
    out.push_back(s);
  }
  return out;
}

std::string escaped(const std::string& text) {
  std::string o;
  for (char c : text) {
    if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '\'') o += "&#39;";
    else o += c;
  }
  return o;
}

}  // namespace

std::string with_contents(const std::string& page) {
  const std::vector<Section> sections = sections_of(page);
  if (sections.size() < 3) return page;
  std::string nav = "<nav class='toc'><b>Contents</b><ol>";
  for (const auto& s : sections) nav += "<li><a href='#" + s.id + "'>" + escaped(s.text) + "</a></li>";
  nav += "</ol></nav>\n";
  std::string out;
  out.reserve(page.size() + nav.size() + 16 * sections.size());
  std::size_t at = 0;
  for (std::size_t k = 0; k < sections.size(); ++k) {
    const Section& s = sections[k];
    out.append(page, at, s.begin - at);
    if (k == 0) out += nav;
    out += "<h2";
    if (!s.has_id) out += " id='" + s.id + "'";
    at = s.end;
  }
  out.append(page, at, std::string::npos);
  return out;
}

}  // namespace poise::engine
