#pragma once
/// A reviewer's error budget file (`poise budget BUDGET.toml`): the lines an author wrote,
/// each with the inputs it follows from, so that every line can be recomputed and set beside
/// what was declared.
///
///   [budget]   name, title, unit (of every contribution and of the combined figure),
///              level = "1sigma" | "2sigma" | "3sigma" (what a contribution stands for),
///              combination = "rss" | "linear" | "bias_linear_random_rss",
///              requirement (optional), confidence (0 < p < 1; two-sided normal multiple),
///              model, output, samples, seed (optional: the Monte Carlo beside the budget),
///              declared = "x" or ["least", "greatest"] (optional: the author's combined figure),
///              pixel = "18.75 arcsec" (optional IFOV: requirement in px, and
///              declared_in_pixels = ["0.56 px", "0.95 px"], the author's figure in pixels),
///              field_points (optional, default 13: grid points per [field] variable),
///              notes, source (free text)
///   [field]    variable = ["-30 deg", "30 deg"] (or [0.4, 0.96]), or
///              variable = { range = [...], model_key = "..." }: what gains may use
///   [[line]]   name, kind = "random" | "bias", and either
///                value = "2 arcsec"                       (given: nothing to recompute), or
///                tolerance, lever (optional), distribution, tolerance_is, gain (optional);
///              declared = "x" or ["least", "greatest"] (optional), model_key (optional),
///              propagation (optional: the factor with which the line enters its group or the
///              combined figure, not part of its declared value), notes, source
///   [[group]]  name, members = [names of lines or groups], combination (default the
///              budget's), declared, propagation: a sub-total an author wrote (e.g. an axis total)
///
/// Distributions and tolerance_is follow the model files exactly (sampling/distribution.h):
/// the standard deviation of a "uniform" +-t read as "bounds" is t/sqrt(3), and so on.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/units.h"
#include "sampling/distribution.h"

namespace poise::budget {

enum class Combination { kRss, kLinear, kBiasLinearRandomRss };
enum class LineKind { kRandom, kBias };

std::string to_string(Combination c);

/// A variable of [field], the range a gain is evaluated over.
struct FieldVariable {
  std::string name;
  double lo = 0.0, hi = 0.0;  ///< SI (rad for angles)
  std::string unit;           ///< display unit as written ("deg", "" when dimensionless)
  bool angle = false;
  std::string model_key;  ///< optional: the model tolerance this variable stands for
  int line = 0;
};

/// What the author wrote for a line, a group or the combined figure.
struct Declared {
  bool present = false;
  bool ranged = false;                 ///< ["least", "greatest"] over the field
  double least = 0.0, greatest = 0.0;  ///< SI of the budget's dimension (or px for pixels)
  std::string as_written;
  int line = 0;
};

struct LineSpec {
  std::string name;
  std::string path;  ///< "line[3]", for messages
  int line = 0;      ///< in the file
  int name_line = 0;
  LineKind kind = LineKind::kRandom;
  bool given = false;      ///< a `value` line
  double value = 0.0;      ///< SI, when given
  double tolerance = 0.0;  ///< SI, as written
  std::string tolerance_text;
  std::optional<double> lever;  ///< m
  std::string lever_text;
  sampling::DistributionKind distribution = sampling::DistributionKind::kNormal;
  sampling::ToleranceConvention convention = sampling::ToleranceConvention::kOneSigma;
  std::string gain = "1";   ///< muParser expression of the field variables
  std::string propagation;  ///< "" = 1
  int gain_line = 0, propagation_line = 0;
  Declared declared;
  std::string model_key;
  int model_key_line = 0;
};

struct GroupSpec {
  std::string name;
  std::string path;
  int line = 0;
  int name_line = 0, members_line = 0;
  std::vector<std::string> members;
  Combination combination = Combination::kRss;
  std::string propagation;
  int propagation_line = 0;
  Declared declared;
};

struct BudgetSpec {
  std::string file;
  std::string name, title, notes, source;
  std::string unit;          ///< e.g. "arcsec"
  double unit_factor = 1.0;  ///< SI per unit
  units::Dimension dimension{};
  int level = 1;  ///< sigmas a contribution stands for
  Combination combination = Combination::kRss;
  std::optional<double> requirement;  ///< SI
  std::string requirement_text;
  double confidence = 0.9973;
  std::string model_path;  ///< resolved against the budget file's folder; "" = none
  std::string model_as_written;
  int model_line = 0;
  std::string output;
  int output_line = 0;
  std::size_t samples = 4000;
  std::uint64_t seed = 1;
  std::size_t field_points = 13;
  std::optional<double> pixel;  ///< IFOV, rad per px
  Declared declared;            ///< of the combined figure
  Declared declared_in_pixels;
  std::vector<FieldVariable> field;
  std::vector<LineSpec> lines;
  std::vector<GroupSpec> groups;
};

/// Reads and validates a budget file; every problem is collected and thrown at once as a
/// engine::ValidationError naming file, line, key, value and what was expected.
BudgetSpec load_budget(const std::string& path);

/// Sigmas of a level: "1sigma" -> 1.
int level_sigmas(const std::string& level);

}  // namespace poise::budget
