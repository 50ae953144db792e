#include "engine/report/driver_scatter.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <sstream>

#include "core/format.h"
#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"

namespace poise::engine {
namespace fs = std::filesystem;

namespace {

constexpr double kLeastShare = 0.02;  // below: within the estimate's bias at 1000 rows

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::stringstream ss(line);
  while (std::getline(ss, cell, ',')) cells.push_back(cell);
  return cells;
}

// The columns of samples.csv wanted, from its first ok rows (NaN-free).
struct SampleRows {
  std::vector<std::vector<double>> x;  // per input
  std::vector<double> y;
};

SampleRows read_rows(const fs::path& csv, const std::vector<std::string>& inputs, const std::string& output,
                     std::size_t max_rows) {
  SampleRows rows;
  std::ifstream in(csv);
  std::string line;
  if (!in || !std::getline(in, line)) return rows;
  const std::vector<std::string> header = split_csv_line(line);
  auto column = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const std::size_t status = column("status"), yc = column(output);
  if (status >= header.size() || yc >= header.size()) return rows;
  std::vector<std::size_t> xc;
  xc.reserve(inputs.size());
  for (const auto& name : inputs) xc.push_back(column(name));
  rows.x.resize(inputs.size());
  while (rows.y.size() < max_rows && std::getline(in, line)) {
    const std::vector<std::string> cells = split_csv_line(line);
    if (cells.size() <= std::max(status, yc) || cells[status] != "ok") continue;
    const double y = std::strtod(cells[yc].c_str(), nullptr);
    if (!std::isfinite(y)) continue;
    rows.y.push_back(y);
    for (std::size_t k = 0; k < xc.size(); ++k) {
      rows.x[k].push_back(xc[k] < cells.size() ? std::strtod(cells[xc[k]].c_str(), nullptr) : NAN);
    }
  }
  return rows;
}

}  // namespace

std::vector<DriverShare> main_effect_shares(const std::vector<std::string>& inputs,
                                            const std::vector<std::vector<double>>& x, const std::vector<double>& y,
                                            std::size_t bins) {
  std::vector<DriverShare> shares;
  const std::size_t n = y.size();
  if (n < 4 * bins) return shares;
  const double mean = std::accumulate(y.begin(), y.end(), 0.0) / static_cast<double>(n);
  double total = 0.0;
  for (double v : y) total += (v - mean) * (v - mean);
  if (!(total > 0.0)) return shares;
  std::vector<std::size_t> order(n);
  for (std::size_t k = 0; k < inputs.size() && k < x.size(); ++k) {
    if (x[k].size() != n || std::any_of(x[k].begin(), x[k].end(), [](double v) { return !std::isfinite(v); })) continue;
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return x[k][a] < x[k][b]; });
    if (x[k][order.front()] == x[k][order.back()]) continue;  // a constant input drives nothing
    double between = 0.0;
    for (std::size_t b = 0; b < bins; ++b) {  // equal-count bins along the input
      const std::size_t lo = b * n / bins, hi = (b + 1) * n / bins;
      double sum = 0.0;
      for (std::size_t i = lo; i < hi; ++i) sum += y[order[i]];
      const double m = sum / static_cast<double>(hi - lo);
      between += static_cast<double>(hi - lo) * (m - mean) * (m - mean);
    }
    shares.push_back({inputs[k], between / total});
  }
  std::sort(shares.begin(), shares.end(), [](const auto& a, const auto& b) { return a.share > b.share; });
  return shares;
}

bool driver_scatter(const fs::path& plots_dir, const fs::path& samples_csv, const std::vector<std::string>& inputs,
                    const OutputSpec& output, std::vector<std::string>& figures, std::string& why,
                    std::size_t max_rows) {
  if (inputs.empty() || !fs::exists(samples_csv)) return true;
  const SampleRows rows = read_rows(samples_csv, inputs, output.name, max_rows);
  std::vector<DriverShare> shares = main_effect_shares(inputs, rows.x, rows.y);
  while (!shares.empty() && shares.back().share < kLeastShare) shares.pop_back();
  if (shares.size() > 3) shares.resize(3);
  if (shares.empty()) return true;
  const std::string name = output.name + "_drivers";
  {
    std::ostringstream d;
    d.precision(8);
    d << "# " << output.name << " against its strongest drivers, first " << rows.y.size()
      << " ok rows of samples.csv\n#";
    for (const auto& s : shares) d << ' ' << s.input;
    d << ' ' << output.name << '\n';
    for (std::size_t i = 0; i < rows.y.size(); ++i) {
      for (const auto& s : shares) {
        const auto k = static_cast<std::size_t>(std::find(inputs.begin(), inputs.end(), s.input) - inputs.begin());
        d << rows.x[k][i] << ' ';
      }
      d << rows.y[i] << '\n';
    }
    write_file_atomic((plots_dir / (name + ".dat")).string(), d.str());
  }
  const std::string unit = output.unit == "1" ? std::string() : output.unit;
  const auto literal = gnuplot_format_literal;
  const std::string what = output.description.empty() ? output.name : output.description;
  const std::size_t ycol = shares.size() + 1;
  std::ostringstream g;
  g << "set multiplot layout 1," << shares.size() << " title "
    << gnuplot_quoted(what + " against its " + std::to_string(shares.size()) + " strongest drivers (" +
                      std::to_string(rows.y.size()) + " samples; main-effect share of the variance in brackets)")
    << "\nset ylabel " << gnuplot_quoted(what + (unit.empty() ? "" : " [" + unit + "]"))
    << "\nunset key\nset xtics rotate by 30 right\n";
  for (std::size_t k = 0; k < shares.size(); ++k) {
    const std::string share = fmt::format(" ({:.2f})", shares[k].share);
    g << "set xlabel " << gnuplot_quoted(shares[k].input + share) << "\nplot '" << name << ".dat' u " << k + 1 << ':'
      << ycol << ":(sprintf('" << literal(shares[k].input) << " %.4g, " << literal(output.name) << " %.4g "
      << literal(unit) << "', $" << k + 1 << ", $" << ycol
      << ")) with labels hypertext point pt 7 ps 0.3 lc rgb '#4477aa'\n";
    if (k == 0) g << "unset ylabel\n";
  }
  g << "unset multiplot\n";
  std::ostringstream note;
  if (!svg_plot(plots_dir, name, g.str(), figures, note)) {
    why = note.str();
    return false;
  }
  return true;
}

}  // namespace poise::engine
