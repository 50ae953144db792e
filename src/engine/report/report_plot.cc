#include "engine/report/report_plot.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

#include "core/format.h"
#include "engine/results/result_io.h"

extern char** environ;

namespace poise::engine {
namespace fs = std::filesystem;

bool svg_plot(const std::filesystem::path& dir, const std::string& name, const std::string& script,
              std::vector<std::string>& figures, std::ostringstream& html) {
  write_file_atomic((dir / (name + ".gp")).string(),
                    "set terminal svg size 720,420 dynamic noenhanced font 'Helvetica,12'\n"
                    "set output '" +
                        name + ".svg'\nset grid\n" + script);
  std::string why;
  if (run_gnuplot((dir / (name + ".gp")).string(), &why)) {
    native_tooltips(dir / (name + ".svg"));
    figures.push_back(name + ".svg");
    return true;
  }
  html << "<p><small>" << html_escape(name) << ": " << html_escape(why) << "</small></p>\n";
  return false;
}

std::string gnuplot_quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

std::string gnuplot_format_literal(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '%' ? std::string("%%") : c == '\'' ? std::string("''") : std::string(1, c);
  return out;
}

bool run_gnuplot(const std::string& script_path, std::string* why) {
  // gnuplot is started without a shell (an argv vector), in the script's folder, its
  // messages into gnuplot.log there: any path works, quotes and spaces included.
  const fs::path script(script_path);
  const fs::path dir = script.parent_path().empty() ? fs::path(".") : script.parent_path();
  const std::string log = (dir / "gnuplot.log").string();
  const std::string dir_s = dir.string(), file_s = script.filename().string();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addchdir_np(&actions, dir_s.c_str());
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "gnuplot.log", O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  std::string prog = "gnuplot";
  std::vector<char*> argv{prog.data(), const_cast<char*>(file_s.c_str()), nullptr};
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    if (why)
      *why = std::string("gnuplot could not be started (") + std::strerror(rc) +
             "; scripts/install_deps.sh installs it); the scripts and data are kept in plots/";
    return false;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!(WIFEXITED(status) && WEXITSTATUS(status) == 0)) {
    std::string first;
    if (std::ifstream in(log); in) std::getline(in, first);
    if (why) {
      *why = "gnuplot failed on " + file_s + (first.empty() ? std::string() : ": " + first) +
             " (plots/gnuplot.log has its messages); the scripts and data are kept";
    }
    return false;
  }
  return true;
}

namespace {

/// The SVG with every id it defines prefixed, and the references to them (url(#id), href="#id"),
/// so that several figures from gnuplot (each with its gnuplot_canvas, gpDot, gpPt0...) can stand
/// in one page with unique ids.
bool word_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }
bool name_char(char c) { return word_char(c) || c == '.' || c == ':' || c == '-'; }
bool space_char(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

/// Where the quoted value of an attribute `id = '...'` starting at `at` begins (after its
/// quote), or npos when `at` does not start one ("id" as a whole word, spaces allowed).
std::size_t id_value_at(const std::string& svg, std::size_t at) {
  if (svg.compare(at, 2, "id") != 0 || (at > 0 && word_char(svg[at - 1]))) return std::string::npos;
  std::size_t i = at + 2;
  while (i < svg.size() && space_char(svg[i])) ++i;
  if (i >= svg.size() || svg[i] != '=') return std::string::npos;
  ++i;
  while (i < svg.size() && space_char(svg[i])) ++i;
  return i < svg.size() && (svg[i] == '\'' || svg[i] == '"') ? i + 1 : std::string::npos;
}

/// The SVG with every id it defines prefixed, and the references to them (url(#id), href="#id"),
/// so that several figures from gnuplot (each with its gnuplot_canvas, gpDot, gpPt0...) can stand
/// in one page with unique ids. A scan by hand: figures of a few MB pass through it on every run.
std::string prefixed_ids(const std::string& svg, const std::string& prefix) {
  std::set<std::string> ids;
  for (std::size_t at = svg.find("id"); at != std::string::npos; at = svg.find("id", at + 2)) {
    const std::size_t v = id_value_at(svg, at);
    if (v == std::string::npos) continue;
    const std::size_t end = svg.find(svg[v - 1], v);
    if (end == std::string::npos) break;
    if (end > v && svg.find_first_of("'\"", v) == end) ids.insert(svg.substr(v, end - v));
  }
  if (ids.empty()) return svg;
  std::string out;
  out.reserve(svg.size() + 64 * ids.size());
  std::size_t last = 0;
  for (std::size_t i = 0; i < svg.size(); ++i) {
    std::size_t name = std::string::npos;
    if (svg[i] == '#') {
      name = i + 1;
    } else if (svg[i] == 'i') {
      name = id_value_at(svg, i);
    }
    if (name == std::string::npos || name >= svg.size() ||
        !(std::isalpha(static_cast<unsigned char>(svg[name])) || svg[name] == '_')) {
      continue;
    }
    std::size_t end = name;
    while (end < svg.size() && name_char(svg[end])) ++end;
    if (ids.count(svg.substr(name, end - name))) {
      out.append(svg, last, name - last);
      out += prefix;
      last = name;
    }
    i = end - 1;
  }
  out.append(svg, last, std::string::npos);
  return out;
}

}  // namespace

void native_tooltips(const std::filesystem::path& svg_file) {
  std::ifstream in(svg_file, std::ios::binary);
  const std::string svg((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  static const std::string open = "<g onmousemove=\"gnuplot_svg.showHypertext(evt,'";
  static const std::string close = "')\" onmouseout=\"gnuplot_svg.hideHypertext()\"><title> </title>";
  static const std::string series = "<title>gnuplot_plot_";
  if (svg.find(open) == std::string::npos && svg.find(series) == std::string::npos) return;
  std::string out;
  out.reserve(svg.size());
  std::size_t at = 0;
  while (at < svg.size()) {
    const std::size_t a = svg.find(open, at), b = svg.find(series, at);
    const std::size_t next = std::min(a, b);
    if (next == std::string::npos) break;
    out.append(svg, at, next - at);
    if (next == a) {
      const std::size_t text_end = svg.find(close, a + open.size());
      if (text_end == std::string::npos) {  // not gnuplot's form: leave the rest as it is
        at = a;
        break;
      }
      out += "<g><title>" + svg.substr(a + open.size(), text_end - a - open.size()) + "</title>";
      at = text_end + close.size();
    } else {
      const std::size_t end = svg.find("</title>", b);
      if (end == std::string::npos) {
        at = b;
        break;
      }
      at = end + 8;
    }
  }
  out.append(svg, at, std::string::npos);
  write_file_atomic(svg_file.string(), out);
}

std::string inline_svg(const std::filesystem::path& svg_file, const std::string& caption) {
  std::ifstream in(svg_file, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto start = text.find("<svg");
  if (!in.good() && text.empty()) {
    return "<p class='bad'><small>" + html_escape(svg_file.filename().string()) + " could not be read</small></p>\n";
  }
  if (start != std::string::npos) text = text.substr(start);
  text = prefixed_ids(text, svg_file.stem().string() + "-");
  // gnuplot's fixed width and height make the figure as wide as drawn: let it scale.
  return "<figure class='fig'>" + text +
         (caption.empty() ? "" : "<figcaption>" + html_escape(caption) + "</figcaption>") + "</figure>\n";
}

std::string figures_html(const std::filesystem::path& plots_dir, const std::vector<std::string>& figures) {
  std::string h;
  for (const auto& f : figures) h += inline_svg(plots_dir / f, "");
  return h;
}

std::string report_page_head(const std::string& title) {
  return "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><meta name='viewport' "
         "content='width=device-width, initial-scale=1'><title>Poise: " +
         html_escape(title) +
         "</title><style>"
         "body{font-family:Helvetica,Arial,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222;"
         "line-height:1.4}"
         "table{border-collapse:collapse;margin:0.6em 0;display:block;max-width:100%;overflow-x:auto}"
         "td,th{border:1px solid #bbb;padding:3px 8px;text-align:right;vertical-align:top}"
         "th{background:#eef}td.l,th.l{text-align:left}"
         ".bad{background:#fdd}.close{background:#ffe9b3}.ok{background:#dfd}.target{background:#eee}"
         ".answer{font-size:1.1em;border-left:4px solid #4477aa;padding:0.4em 0.8em;background:#f4f7fb}"
         "small{color:#666}pre{background:#f6f6f6;padding:0.8em;white-space:pre-wrap}"
         "figure.fig{margin:1em 0}figure.fig svg{max-width:100%;height:auto}"
         "figcaption{color:#555;font-size:0.9em}"
         "nav.toc{border:1px solid #ddd;background:#fafafa;padding:0.3em 1em;margin:1em 0;font-size:0.92em}"
         "nav.toc ol{margin:0.3em 0;padding-left:1.4em;columns:2}"
         "</style></head><body>\n";
}

std::string provenance_html(const nlohmann::json& p) {
  std::string h = "<h2>Provenance</h2>\n<table>";
  for (const auto& [key, value] : p.items()) {
    std::string v;
    if (value.is_string()) {
      v = html_escape(value.get<std::string>());
    } else if (value.is_object()) {
      for (const auto& [k2, v2] : value.items()) {
        v += "<code>" + html_escape(k2) + "</code> " + html_escape(v2.is_string() ? v2.get<std::string>() : v2.dump()) +
             "<br>";
      }
    } else if (value.is_number_float()) {
      v = significant(value.get<double>(), 4);  // as every other number ("0.04814", not 0.048136775)
    } else {
      v = html_escape(value.dump());
    }
    h += "<tr><th class='l'>" + html_escape(key) + "</th><td class='l'>" + v + "</td></tr>\n";
  }
  return h + "</table>\n";
}

}  // namespace poise::engine
