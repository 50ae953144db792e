#pragma once
/// The figures every study's report carries, made the same way for every kind:
///   - the distribution of each main output: histogram, and the empirical CDF with its 95%
///     band (Dvoretzky-Kiefer-Wolfowitz, simultaneous over the whole curve), each with the
///     declared references and the requirement as labelled vertical lines;
///   - its mean and p95 against sample count, with 95% intervals (where the run settled);
///   - a tornado chart of Sobol total and first-order indices (poise sensitivity).
/// gnuplot scripts and their data are kept in plots/, the SVGs go inline into report.html.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace poise::engine {

/// A vertical line on a distribution figure: a declared reference or a requirement.
struct FigureLine {
  double x = 0.0;  ///< in the output's unit
  std::string label;
  std::string colour = "#cc3311";
};

/// The outputs whose distribution the report draws: every output a declared reference
/// names, then the first outputs up to `limit` in all.
std::vector<std::string> main_outputs(const std::vector<std::string>& outputs, const nlohmann::json& references,
                                      std::size_t limit = 4);

/// Writes and runs the histogram, CDF and convergence figures of one output (values in
/// sample order, `order` their sample indices); appends the SVG names made to `figures`.
/// Returns false (with the reason in `why`) when gnuplot could not make them.
bool distribution_figures(const std::filesystem::path& plots_dir, const std::string& output, const std::string& unit,
                          const std::string& description, const std::vector<double>& values,
                          const std::vector<std::size_t>& order, const std::vector<FigureLine>& lines,
                          std::vector<std::string>& figures, std::string& why);

/// A tornado chart of summary.json's "sensitivity" for one output (the largest total indices,
/// first-order beside them, 95% intervals as error bars). False if gnuplot failed.
bool sensitivity_tornado(const std::filesystem::path& plots_dir, const nlohmann::json& sensitivity,
                         const std::string& output, std::vector<std::string>& figures, std::string& why);

/// A tornado chart of a drop per input ("which tolerance drives the error"): labels and
/// values (largest first is drawn on top). False if gnuplot failed.
bool tornado_figure(const std::filesystem::path& plots_dir, const std::string& name, const std::string& title,
                    const std::string& xlabel, const std::vector<std::pair<std::string, double>>& bars,
                    std::vector<std::string>& figures, std::string& why);

/// One point of a sweep figure: the swept value (in the unit it was written in) and a
/// statistic with its 95% interval (NaN ends: none).
struct SweepFigurePoint {
  double x = 0.0, y = 0.0, lo = 0.0, hi = 0.0;
};

/// A statistic against a swept parameter with 95% error bars and, when given, the
/// requirement's limit as a horizontal line. False (with `why`) if gnuplot failed.
bool sweep_figure(const std::filesystem::path& plots_dir, const std::string& name, const std::string& title,
                  const std::string& xlabel, const std::string& ylabel, const std::vector<SweepFigurePoint>& points,
                  const std::vector<FigureLine>& limits, std::vector<std::string>& figures, std::string& why);

}  // namespace poise::engine
