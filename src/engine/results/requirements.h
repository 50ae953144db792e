#pragma once
/// Requirements and their verdicts: the question a study answers.
///
/// Any study file may state requirements on its outputs:
///
///     [[requirement]]
///     output = "g_rmse_torque_mNm"   # any output of the study (`poise keys KIND`)
///     statistic = "p95"              # mean | min | p0_135 | p2_5 | p50 | p95 | p97_5 | p99_73
///                                    # | p99_865 | max
///     at_most = "1.5 mN*m"           # or at_least, with a unit the output's converts to
///     confidence = 0.95              # one-sided, default 0.95
///
/// or a two-sided specification (engine/results/specification_limits.h):
///
///     [[requirement]]
///     output = "gap_mm"
///     within = ["0.05 mm", "0.80 mm"]
///     yield_at_least = 0.9973        # or ppm_at_most = 2700, or cpk_at_least = 1.33
///
/// The verdict is decided on the statistic's one-sided bound at that confidence, the bounds
/// `poise optimize` uses (engine/results/confidence_bound.h: order statistics for quantiles, Student t
/// for the mean, Woodruff's bound over randomized replicates):
///   met        the bound on the requirement's side meets the limit (at_most: the upper bound
///              is at most the limit);
///   not met    the bound on the other side is beyond the limit;
///   undecided  the limit lies between them; the verdict then says how many samples would
///              likely decide it, were the statistic where it is now (half-width ~ 1/sqrt(n)).
/// A maximum has no distribution-free bound: "max <= limit" is "not met" when a sample
/// exceeds the limit and otherwise "met by every sample run" (said so in the verdict's note);
/// a minimum mirrors it.
///
/// Every requirement's verdict goes to summary.json "requirements", and one sentence,
/// "answer", says whether every requirement is met and, if not, which and by how much. The
/// report opens with it and the terminal ends with it (the same words everywhere).
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace poise::engine {

class TomlReader;   // engine/study_files/toml_reader.h
struct OutputSpec;  // engine/kind_interface/study_kind.h

/// One [[requirement]] of a study file (or a kind's shorthand for one).
struct Requirement {
  std::string output;
  std::string statistic = "p95";    ///< requirement_statistics(), or yield | ppm | cpk with `within`
  bool at_most = true;              ///< false: at_least
  std::string limit_text;           ///< as written ("1.5 mN*m"; a yield's "0.9973", "2700 ppm")
  std::vector<std::string> within;  ///< a specification's [lower, upper] as written, or empty
  double confidence = 0.95;         ///< one-sided
  std::string origin;               ///< where it was stated ("studies/x.toml:12", or a shorthand's key)
  std::string file;
  int line = 0;
};

/// The statistics a requirement may name with at_most or at_least.
const std::vector<std::string>& requirement_statistics();

/// Reads the study file's [[requirement]] tables (errors recorded on `root`). A plain table
/// [requirement] is left to the kind (a shorthand such as the seeker's los_error).
std::vector<Requirement> read_requirements(TomlReader& root);

/// Checks each requirement against the study's outputs: the output exists and the limit's
/// unit converts to the output's. Throws ValidationError naming file, line, key and value.
void check_requirements(const std::vector<Requirement>& requirements, const std::vector<OutputSpec>& outputs);

/// The values of one output for the verdicts: ok samples in order, each sample's index and
/// the run's replicate size (0: independent samples).
struct OutputValues {
  const std::vector<double>* values = nullptr;
  const std::vector<std::size_t>* ok_index = nullptr;
  std::size_t replicate_size = 0;
  /// Samples that failed (no value), which a specification's yield counts as outside.
  std::size_t failed = 0;
  /// Whether the samples are independent draws (plain Monte Carlo) or come in randomized
  /// replicates; false for an lhs or sobol design without replicates, whose order-statistic
  /// and Student-t bounds are then not guaranteed (each verdict says so).
  bool independent = true;
};

/// The verdict of each requirement (summary.json "requirements": output, statistic, limit
/// {value, unit, as_written}, value, bound, confidence, verdict, ...). `values_of(name)`
/// gives an output's values (null values: none ran).
nlohmann::json judge_requirements(const std::vector<Requirement>& requirements, const std::vector<OutputSpec>& outputs,
                                  const std::function<OutputValues(const std::string&)>& values_of);

/// The one sentence that answers the study: every requirement met, or which are not (or
/// undecided) and by how much. With no requirement, says so and gives the first output's
/// p95. `status` is the run's ("complete", "failed", ...): a partial run says it.
std::string answer_sentence(const nlohmann::json& verdicts, const nlohmann::json& outputs_summary,
                            const std::vector<OutputSpec>& outputs, const std::string& status, std::size_t samples);

/// Sets summary.json "requirements" (the verdicts) and "answer" (the sentence) of a run of
/// `samples` samples with status `status`. A sensitivity run (Saltelli layout: its rows are
/// not independent draws) states no verdict and says so.
void add_answer(nlohmann::json& summary, const std::vector<Requirement>& requirements,
                const std::vector<OutputSpec>& outputs,
                const std::function<OutputValues(const std::string&)>& values_of, const std::string& status,
                std::size_t samples, bool saltelli_layout);

/// The statistics a report shows for a study (in sweeps, contributions): each (output,
/// statistic) the verdicts name, once; with none, p95 of the first `fallback` outputs.
std::vector<std::pair<std::string, std::string>> shown_statistics(const nlohmann::json& verdicts,
                                                                  const std::vector<OutputSpec>& outputs,
                                                                  std::size_t fallback);

/// Whether every requirement of a summary.json is met (false if one is not met or
/// undecided); nullopt when it declares none.
std::optional<bool> requirements_met(const nlohmann::json& summary);

/// A figure in the output's unit, 4 significant digits ("1.25 mN*m", "0.42" when unitless).
std::string with_unit(double v, const std::string& unit);
/// A statistic's name for people ("p99_73" -> "p99.73", "cpk" -> "Cpk").
std::string statistic_label(const std::string& statistic);
/// What a requirement's verdict is on: "p95 of g_rmse_torque_mNm", "yield of gap_mm within
/// [0.05 mm, 0.80 mm]".
std::string requirement_subject(const nlohmann::json& verdict);
/// What a requirement's verdict says, in words: "p95 of g_rmse_torque_mNm at most 1.5 mN*m",
/// "yield of gap_mm within [0.05 mm, 0.80 mm] at least 0.9973".
std::string requirement_text(const nlohmann::json& verdict);

}  // namespace poise::engine
