#include "engine/report/report_figures.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"
#include "sampling/statistics.h"

namespace poise::engine {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kTerminal = "set terminal svg size 720,420 dynamic noenhanced font 'Helvetica,12'\n";

// A label in a gnuplot data file: in double quotes (single ones would be shown).
std::string data_label(const std::string& s) {
  std::string out = "\"";
  for (char c : s) out += c == '"' ? '\'' : c;
  return out + "\"";
}

bool run(const fs::path& dir, const std::string& name, const std::string& script, std::vector<std::string>& figures,
         std::string& why) {
  write_file_atomic((dir / (name + ".gp")).string(),
                    kTerminal + ("set output '" + name + ".svg'\nset grid\n") + script);
  if (!run_gnuplot((dir / (name + ".gp")).string(), &why)) return false;
  native_tooltips(dir / (name + ".svg"));
  figures.push_back(name + ".svg");
  return true;
}

// A series' values on hover: the points of `data` (columns x and y) as hypertext points of
// the series' colour, each with its text (a gnuplot sprintf of the columns); the SVG's own
// tooltip then shows them (native_tooltips). `every` thins a long series (a CDF of 10^6).
std::string hover_points(const std::string& data, const std::string& x, const std::string& y, const std::string& text,
                         const std::string& colour, std::size_t every = 1) {
  return ", '" + data + "'" + (every > 1 ? " every " + std::to_string(every) : std::string()) + " u " + x + ":" + y +
         ":(" + text + ") with labels hypertext point pt 7 ps 0.5 lc rgb '" + colour + "' notitle";
}

// Labelled vertical lines; a label beside a line in the right half of the values [lo, hi]
// stands to its left, so that it stays inside the figure.
std::string vertical_lines(const std::vector<FigureLine>& lines, double lo, double hi) {
  std::ostringstream g;
  int i = 0;
  for (const auto& l : lines) {
    const bool left = l.x > 0.5 * (lo + hi);
    g << "set arrow from " << l.x << ", graph 0 to " << l.x << ", graph 1 nohead lw 2 dt 2 lc rgb '" << l.colour
      << "'\n"
      << "set label " << gnuplot_quoted(l.label) << " at " << l.x << ", graph " << (0.95 - 0.08 * (i++ % 6))
      << (left ? " right offset -0.5,0" : " offset 0.5,0") << " tc rgb '" << l.colour << "'\n";
  }
  return g.str();
}

// Histogram bins of sorted values: Freedman-Diaconis width 2 IQR n^(-1/3) (Sturges' count
// when the IQR is zero), 5 to 60 bins, each sample in exactly one bin.
struct HistogramBins {
  double first = 0.0, width = 1.0;
  std::vector<std::size_t> counts;
};

HistogramBins histogram_bins(const std::vector<double>& sorted) {
  HistogramBins h;
  const std::size_t n = sorted.size();
  const double lo = sorted.front(), hi = sorted.back(), range = hi - lo;
  const double iqr = sorted[(3 * n) / 4] - sorted[n / 4];
  std::size_t bins = static_cast<std::size_t>(std::ceil(std::log2(static_cast<double>(n)))) + 1;  // Sturges
  if (iqr > 0.0 && range > 0.0) {
    bins = static_cast<std::size_t>(std::ceil(range / (2.0 * iqr * std::cbrt(1.0 / static_cast<double>(n)))));
  }
  bins = std::clamp<std::size_t>(bins, 5, 60);
  h.width = range > 0.0 ? range / static_cast<double>(bins) : (std::abs(hi) > 0.0 ? std::abs(hi) * 1e-3 : 1e-9);
  h.first = range > 0.0 ? lo : lo - 0.5 * h.width * static_cast<double>(bins);
  h.counts.assign(bins, 0);
  for (double x : sorted) {
    const auto b = static_cast<std::size_t>(std::floor((x - h.first) / h.width));
    ++h.counts[std::min(b, bins - 1)];  // the largest value closes the last bin
  }
  return h;
}

// How an output is named in a figure: its description, the axis label with its unit, the unit
// as declared and as set into hover texts (gnuplot_format_literal).
struct FigureText {
  std::string what, axis, unit, hover_unit;
};

// Mean and p95 against sample count (`finite` values in all), written and drawn.
bool convergence_figure(const fs::path& dir, const std::string& output, const FigureText& text,
                        const std::vector<double>& values, const std::vector<std::size_t>& order, std::size_t finite,
                        std::vector<std::string>& figures, std::string& why) {
  // Statistics against sample count (in sample order): mean with its t interval and p95
  // with its binomial order-statistic interval, at geometrically spaced counts.
  std::vector<std::size_t> counts;
  for (double c = static_cast<double>(finite); c >= 8; c /= 1.5) counts.push_back(static_cast<std::size_t>(c));
  if (counts.size() >= 3) {  // a curve needs a few sample counts
    std::ostringstream d;
    d << "# samples  mean  mean_lo  mean_hi  p95  p95_lo  p95_hi  [" << text.unit << "]\n";
    std::vector<std::pair<std::size_t, double>> by_order;
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (std::isfinite(values[i])) by_order.emplace_back(i < order.size() ? order[i] : i, values[i]);
    }
    std::sort(by_order.begin(), by_order.end());
    std::reverse(counts.begin(), counts.end());
    for (std::size_t c : counts) {
      std::vector<double> head;
      for (std::size_t i = 0; i < c; ++i) head.push_back(by_order[i].second);
      const sampling::Summary s = sampling::summarize(head);
      auto end = [](const std::optional<double>& e, double fallback) { return e ? *e : fallback; };
      d << c << ' ' << s.mean.value << ' ' << end(s.mean.lo, s.mean.value) << ' ' << end(s.mean.hi, s.mean.value) << ' '
        << s.p95.value << ' ' << end(s.p95.lo, s.p95.value) << ' ' << end(s.p95.hi, s.p95.value) << '\n';
    }
    write_file_atomic((dir / (output + "_convergence.dat")).string(), d.str());  // gnuplot reads it next
    std::ostringstream conv;
    // The x axis ends at the run's sample count (not gnuplot's next power of ten).
    conv << "set title " << gnuplot_quoted(text.what + ": mean and p95 against sample count (95% intervals)")
         << "\nset xlabel 'samples'\nset logscale x\nset xrange [" << static_cast<double>(counts.front()) * 0.8 << ':'
         << static_cast<double>(finite) * 1.1 << "]\nset ylabel " << gnuplot_quoted(text.axis)
         << "\nset key outside bottom center horizontal\nplot '" << output
         << "_convergence.dat' u 1:2:3:4 with yerrorlines lw 2 pt 1 lc rgb '#4477aa' title 'mean', '' u 1:5:6:7 with "
            "yerrorlines lw 2 dt 2 pt 6 lc rgb '#ee7733' title 'p95'"
         << hover_points(output + "_convergence.dat", "1", "2",
                         "sprintf('%d samples: mean %.4g [%.4g, %.4g] " + text.hover_unit + "', $1, $2, $3, $4)",
                         "#4477aa")
         << hover_points(output + "_convergence.dat", "1", "5",
                         "sprintf('%d samples: p95 %.4g [%.4g, %.4g] " + text.hover_unit + "', $1, $5, $6, $7)",
                         "#ee7733")
         << "\n";
    if (!run(dir, output + "_convergence", conv.str(), figures, why)) return false;
  }
  return true;
}

}  // namespace

std::vector<std::string> main_outputs(const std::vector<std::string>& outputs, const json& references,
                                      std::size_t limit) {
  std::vector<std::string> out;
  if (references.is_array()) {
    for (const auto& r : references) {
      const std::string o = r.value("output", "");
      if (!o.empty() && std::find(out.begin(), out.end(), o) == out.end()) out.push_back(o);
    }
  }
  for (const auto& o : outputs) {  // every referenced output, then the first ones up to `limit`
    if (out.size() >= limit) break;
    if (std::find(out.begin(), out.end(), o) == out.end()) out.push_back(o);
  }
  return out;
}

bool distribution_figures(const fs::path& dir, const std::string& output, const std::string& unit,
                          const std::string& description, const std::vector<double>& values,
                          const std::vector<std::size_t>& order, const std::vector<FigureLine>& lines,
                          std::vector<std::string>& figures, std::string& why) {
  std::vector<double> v;
  for (double x : values) {
    if (std::isfinite(x)) v.push_back(x);
  }
  if (v.size() < 2) return true;
  std::vector<double> sorted = v;
  std::sort(sorted.begin(), sorted.end());
  const double n = static_cast<double>(sorted.size());
  // DKW: P(sup |F_n - F| > eps) <= 2 exp(-2 n eps^2) = 0.05.
  const double eps = std::sqrt(std::log(2.0 / 0.05) / (2.0 * n));
  {
    std::ostringstream d;
    d << "# " << output << " [" << unit << "]  empirical_cdf  band_lo  band_hi (DKW 95%)\n";
    for (std::size_t i = 0; i < sorted.size(); ++i) {
      const double f = (static_cast<double>(i) + 1.0) / n;
      d << sorted[i] << ' ' << f << ' ' << std::max(0.0, f - eps) << ' ' << std::min(1.0, f + eps) << '\n';
    }
    write_file_atomic((dir / (output + "_cdf.dat")).string(), d.str());
  }
  const std::string what = description.empty() ? output : description;
  const std::string unit_text = gnuplot_format_literal(unit == "1" ? std::string() : unit);  // in hover texts
  const std::string xl = what + (unit.empty() || unit == "1" ? "" : " [" + unit + "]");
  const std::size_t cdf_every = std::max<std::size_t>(1, sorted.size() / 200);
  const HistogramBins bins = histogram_bins(sorted);
  {
    std::ostringstream d;
    d.precision(10);
    d << "# bin_centre  samples  (bin width " << bins.width << ")\n";
    for (std::size_t b = 0; b < bins.counts.size(); ++b) {
      d << bins.first + (static_cast<double>(b) + 0.5) * bins.width << ' ' << bins.counts[b] << '\n';
    }
    write_file_atomic((dir / (output + "_hist.dat")).string(), d.str());
  }
  const std::size_t most = *std::max_element(bins.counts.begin(), bins.counts.end());
  std::ostringstream hist;
  hist.precision(10);
  hist << "set title "
       << gnuplot_quoted("Distribution of " + what + " (" + output + ") over " + std::to_string(sorted.size()) +
                         " samples")
       << "\nset xlabel " << gnuplot_quoted(xl) << "\nset ylabel 'samples'\nset key outside bottom center horizontal\n"
       << "set boxwidth " << bins.width << " absolute\nset yrange [0:*]\n"
       << (most <= 10 ? "set ytics 1\n" : "") << "set style fill solid 0.6\n"
       << vertical_lines(lines, sorted.front(), sorted.back()) << "plot '" << output
       << "_hist.dat' u 1:2 with boxes lc rgb '#4477aa' title 'simulated'"
       << hover_points(output + "_hist.dat", "1", "2", "sprintf('%.4g " + unit_text + ": %d samples', $1, $2)",
                       "#4477aa")
       << "\n";
  if (!run(dir, output + "_hist", hist.str(), figures, why)) return false;
  std::ostringstream cdf;
  cdf << "set title " << gnuplot_quoted("CDF of " + what + " with its 95% band (DKW)") << "\nset xlabel "
      << gnuplot_quoted(xl)
      << "\nset ylabel 'share of samples at or below'\nset yrange [0:1]\nset key outside bottom center horizontal\n"
      << vertical_lines(lines, sorted.front(), sorted.back()) << "plot '" << output
      << "_cdf.dat' u 1:3:4 with filledcurves lc rgb '#bbccee' title '95% band', '' u 1:2 with steps lw 2 lc rgb "
         "'#4477aa' title 'empirical CDF'"
      << hover_points(output + "_cdf.dat", "1", "2",
                      "sprintf('%.4g " + unit_text + ": share %.3f [%.3f, %.3f]', $1, $2, $3, $4)", "#4477aa",
                      cdf_every)
      << "\n";
  if (!run(dir, output + "_cdf", cdf.str(), figures, why)) return false;
  return convergence_figure(dir, output, {what, xl, unit, unit_text}, values, order, v.size(), figures, why);
}

bool tornado_figure(const fs::path& dir, const std::string& name, const std::string& title, const std::string& xlabel,
                    const std::vector<std::pair<std::string, double>>& bars, std::vector<std::string>& figures,
                    std::string& why) {
  if (bars.empty()) return true;
  {
    std::ostringstream d;
    d << "# rank  value  label\n";
    for (std::size_t i = 0; i < bars.size(); ++i)
      d << i << ' ' << bars[i].second << ' ' << data_label(bars[i].first) << '\n';
    write_file_atomic((dir / (name + ".dat")).string(), d.str());
  }
  std::ostringstream g;
  g << "set title " << gnuplot_quoted(title) << "\nset xlabel " << gnuplot_quoted(xlabel) << "\nset yrange ["
    << bars.size() << "-0.5:-0.5]\nset ytics scale 0\nset style fill solid 0.7\nunset key\nset lmargin 34\n"
    << "plot '" << name << ".dat' u ($2/2):1:(abs($2)/2):(0.35):ytic(3) with boxxyerror lc rgb '#4477aa'"
    << hover_points(name + ".dat", "2", "1", "sprintf('%s: %.4g', strcol(3), $2)", "#4477aa") << "\n";
  return run(dir, name, g.str(), figures, why);
}

bool sensitivity_tornado(const fs::path& dir, const json& sensitivity, const std::string& output,
                         std::vector<std::string>& figures, std::string& why) {
  if (!sensitivity.contains("outputs") || !sensitivity["outputs"].contains(output)) return true;
  // Per tolerance where the kind names them (a tolerance's columns as one bar), else per column.
  const json& o = sensitivity["outputs"][output];
  const json& idx = o.contains("tolerances") ? o["tolerances"] : o["indices"];
  const std::string name = output + "_sobol";
  {
    std::ostringstream d;
    d << "# rank  total total_lo total_hi  first first_lo first_hi  group\n";
    std::size_t i = 0;
    for (const auto& g : idx) {
      if (i >= 12) break;
      auto val = [](const json& e, int k) {
        if (k < 0) return e["value"].is_number() ? e["value"].get<double>() : 0.0;
        return e["ci95"][k].is_number() ? e["ci95"][k].get<double>()
                                        : (e["value"].is_number() ? e["value"].get<double>() : 0.0);
      };
      d << i++ << ' ' << val(g["total"], -1) << ' ' << val(g["total"], 0) << ' ' << val(g["total"], 1) << ' '
        << val(g["first"], -1) << ' ' << val(g["first"], 0) << ' ' << val(g["first"], 1) << ' '
        << data_label(g["group"].get<std::string>()) << '\n';
    }
    if (i == 0) return true;
    write_file_atomic((dir / (name + ".dat")).string(), d.str());
  }
  std::ostringstream g;
  g << "set title " << gnuplot_quoted("Which inputs drive " + output + ": Sobol indices (95% intervals)")
    << "\nset xlabel 'index (share of the variance)'\nset yrange [*:*] reverse\nset ytics scale 0\nset lmargin 34\n"
    << "set style fill solid 0.7\nset key outside bottom center horizontal\nset xrange [0:*]\n"
    << "plot '" << name
    << ".dat' u ($2/2):($1-0.18):($2/2):(0.16):ytic(8) with boxxyerror lc rgb '#4477aa' title 'total', "
    << "'' u 2:($1-0.18):3:4 with xerrorbars lc rgb '#222222' pt 0 notitle, "
    << "'' u ($5/2):($1+0.18):($5/2):(0.16) with boxxyerror lc rgb '#ee7733' title 'first order', "
    << "'' u 5:($1+0.18):6:7 with xerrorbars lc rgb '#222222' pt 0 notitle"
    << hover_points(name + ".dat", "2", "($1-0.18)", "sprintf('%s: total %.3f [%.3f, %.3f]', strcol(8), $2, $3, $4)",
                    "#4477aa")
    << hover_points(name + ".dat", "5", "($1+0.18)",
                    "sprintf('%s: first order %.3f [%.3f, %.3f]', strcol(8), $5, $6, $7)", "#ee7733")
    << "\n";
  return run(dir, name, g.str(), figures, why);
}

bool sweep_figure(const fs::path& dir, const std::string& name, const std::string& title, const std::string& xlabel,
                  const std::string& ylabel, const std::vector<SweepFigurePoint>& points,
                  const std::vector<FigureLine>& limits, std::vector<std::string>& figures, std::string& why) {
  if (points.empty()) return true;
  {
    std::ostringstream d;
    d << "# x  statistic  ci95_lo  ci95_hi\n";
    d.precision(10);
    for (const auto& p : points) {
      d << p.x << ' ' << p.y << ' ' << (std::isfinite(p.lo) ? p.lo : p.y) << ' ' << (std::isfinite(p.hi) ? p.hi : p.y)
        << '\n';
    }
    write_file_atomic((dir / (name + ".dat")).string(), d.str());
  }
  std::ostringstream g;
  g << "set title " << gnuplot_quoted(title) << "\nset xlabel " << gnuplot_quoted(xlabel) << "\nset ylabel "
    << gnuplot_quoted(ylabel)
    << "\nset key outside bottom center horizontal\nset offsets graph 0.05, graph 0.05, graph 0.1, graph 0.1\n";
  // The limits as constant functions: the y range then takes them in.
  g << "plot '" << name << ".dat' u 1:2:3:4 with yerrorlines lw 2 pt 7 lc rgb '#4477aa' t "
    << gnuplot_quoted(ylabel + ", 95% interval")
    << hover_points(name + ".dat", "1", "2", "sprintf('%.4g: %.4g [%.4g, %.4g]', $1, $2, $3, $4)", "#4477aa");
  for (const auto& l : limits)
    g << ", " << l.x << " w l lw 2 dt 2 lc rgb '" << l.colour << "' t " << gnuplot_quoted(l.label);
  g << "\n";
  return run(dir, name, g.str(), figures, why);
}

}  // namespace poise::engine
