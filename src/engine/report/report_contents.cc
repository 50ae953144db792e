#include "engine/report/report_contents.h"

#include <cctype>
#include <regex>
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

std::vector<Section> sections_of(const std::string& page) {
  static const std::regex heading(R"~(<h2(\s+id\s*=\s*['"]([^'"]*)['"])?\s*>([\s\S]*?)</h2>)~");
  std::vector<Section> out;
  std::set<std::string> used;
  for (auto it = std::sregex_iterator(page.begin(), page.end(), heading); it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    Section s;
    s.begin = static_cast<std::size_t>(m.position(0));
    s.end = s.begin + 3;  // after "<h2"
    s.has_id = m[1].matched;
    s.text = plain_text(m[3].str());
    s.id = s.has_id ? m[2].str() : slug(s.text);
    for (int k = 2; !s.has_id && used.count(s.id); ++k) s.id = slug(s.text) + "-" + std::to_string(k);
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
