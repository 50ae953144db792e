#pragma once
/// The report's scatter of a main output against the inputs that drive it most, for every kind.
///
/// Which inputs: each input column's main-effect share of the output's variance, estimated by
/// binning (the correlation ratio eta^2 = Var(E[Y | X in bin]) / Var(Y), 10 equal-count bins:
/// Sobol's first-order index read off the samples, which also catches a non-monotone effect
/// such as a phase angle, unlike a rank correlation). With n rows its bias is about
/// (bins - 1) / n (0.01 at the 1000 rows used), so shares below 0.02 are not shown as drivers.
/// Read from the first rows of samples.csv (a Sobol or LHS design's first points cover the
/// space), at most `max_rows` of them: the figure's cost does not grow with the run.
#include <filesystem>
#include <string>
#include <vector>

#include "engine/kind_interface/output_spec.h"

namespace poise::engine {

/// One input's estimated main-effect share of the output's variance.
struct DriverShare {
  std::string input;  ///< samples.csv column
  double share = 0.0;
};

/// Main-effect shares of every input for `y` (binned correlation ratio), largest first.
std::vector<DriverShare> main_effect_shares(const std::vector<std::string>& inputs,
                                            const std::vector<std::vector<double>>& x, const std::vector<double>& y,
                                            std::size_t bins = 10);

/// Reads samples.csv (its first `max_rows` ok rows), picks the output's (up to) three strongest
/// drivers and draws the output against each, side by side, every point with its values on
/// hover. Nothing when the file is missing, holds too few rows, or no input reaches 0.02.
/// False (with `why`) when gnuplot failed.
bool driver_scatter(const std::filesystem::path& plots_dir, const std::filesystem::path& samples_csv,
                    const std::vector<std::string>& inputs, const OutputSpec& output, std::vector<std::string>& figures,
                    std::string& why, std::size_t max_rows = 1000);

}  // namespace poise::engine
