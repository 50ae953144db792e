#pragma once
/// Figures of report.html: gnuplot scripts (started without a shell) run into SVG files in
/// the run's plots/ folder, then set inline into the report.
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace poise::engine {

/// A perceptually uniform palette for field maps (viridis' anchor colours), as a gnuplot
/// command line: lightness grows monotonically, and it reads in grey and with colour blindness.
inline constexpr const char* kViridisPalette =
    "set palette defined (0 '#440154', 0.125 '#472d7b', 0.25 '#3b528b', 0.375 '#2c728e', 0.5 '#21918c', "
    "0.625 '#28ae80', 0.75 '#5ec962', 0.875 '#addc30', 1 '#fde725')\n";

/// A gnuplot string literal in single quotes (' doubled): titles and labels as written.
std::string gnuplot_quoted(const std::string& text);

/// Text set inside a gnuplot sprintf format in single quotes (a hover text): % and ' doubled,
/// so that a unit "%" or a name with an apostrophe prints as itself.
std::string gnuplot_format_literal(const std::string& text);

/// Runs gnuplot on a script; returns false (and the reason) if it failed or is absent.
bool run_gnuplot(const std::string& script_path, std::string* why);

/// Writes dir/name.gp (SVG terminal, 720x420, grid, then `script`) and runs gnuplot: on
/// success appends "name.svg" to `figures`; on failure writes why into `html` (a small note
/// where the figure would be). Returns whether the figure was made.
bool svg_plot(const std::filesystem::path& dir, const std::string& name, const std::string& script,
              std::vector<std::string>& figures, std::ostringstream& html);

/// Rewrites a gnuplot SVG so that its hover texts (`with labels hypertext`) are the SVG's own
/// <title> tooltips, which every browser shows without gnuplot's JavaScript, and drops the
/// "gnuplot_plot_N" titles of unnamed series (they would show as tooltips too).
void native_tooltips(const std::filesystem::path& svg_file);

/// The SVG file's drawing, inline in report.html (the report is one self-contained file),
/// in a <figure> with an optional caption.
std::string inline_svg(const std::filesystem::path& svg_file, const std::string& caption);
/// inline_svg of each of `figures` (file names in plots_dir).
std::string figures_html(const std::filesystem::path& plots_dir, const std::vector<std::string>& figures);

/// The opening of every report.html: the page head with the shared style sheet (tables that
/// fit the page, figures scaled to it, verdict colours) and the title.
std::string report_page_head(const std::string& title);

/// summary.json's "provenance" as a readable two-column table (libraries as a nested list).
std::string provenance_html(const nlohmann::json& provenance);

}  // namespace poise::engine
