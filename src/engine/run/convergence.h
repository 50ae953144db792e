#pragma once
/// When a run has sampled enough, and when it must stop.
///   --until OUTPUT.STAT<=WIDTH   stop once the 95% interval of STAT (mean, std, p50, p95,
///                                p99_73) of OUTPUT is at most WIDTH wide (in the output's
///                                unit, or "WIDTH%" of the figure itself). Checked on rank 0
///                                at chunk boundaries of the sample order, geometrically
///                                spaced (every ~10% more samples) and, with replicates,
///                                only at whole replicates: the stopping count is the same
///                                for any thread or rank count and for a resumed run.
///   max_failure_share            stop with an error once more than this share of the
///                                planned samples failed, or once at least 50 ran and the
///                                Wilson interval of the failure share lies above it.
/// The figures of a run are summarized by replicate (sampling::summarize_replicates) when the
/// design has replicates, else as independent samples (sampling::summarize).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "sampling/statistics.h"

namespace poise::engine {

struct UntilTarget {
  std::string text;       ///< as given
  std::string output;     ///< output name
  std::string statistic;  ///< mean | std | p50 | p95 | p99_73
  double width = 0.0;     ///< full 95% interval width (output unit), or a share of the figure
  bool relative = false;
};

/// Parses "OUTPUT.STAT<=WIDTH" or "OUTPUT.STAT<=WIDTH%"; throws Error naming what is wrong
/// (and the outputs there are) if the output or statistic is unknown.
UntilTarget parse_until(const std::string& text, const std::vector<std::string>& outputs);

/// Refuses (UsageError, exit 2) an --until on a quantile that the design cannot support:
/// with replicates (replicate_size > 0) of fewer than kMinTailPerReplicate / min(p, 1 - p)
/// samples each (e.g. 3704 for p99_73, 200 for p95), each replicate holds fewer than 10
/// samples beyond the quantile, its interval is approximate (sampling/statistics.h) and a
/// rule that stops at the first narrow interval would stop on replicates that agree by chance.
void check_until_design(const UntilTarget& target, std::size_t replicate_size);

/// The figure's estimate in a Summary ("p99_73" -> s.p99_73).
const sampling::Estimate& statistic_of(const sampling::Summary& s, const std::string& statistic);
/// Width of an interval (infinite when an end is missing).
double interval_width(const sampling::Estimate& e);

/// Summary of one output's ok values (in sample order, with their sample indices).
sampling::Summary summarize_output(const std::vector<double>& values, const std::vector<std::size_t>& ok_index,
                                   std::size_t replicate_size);

/// The stop rule of a run, called on rank 0 after each chunk with the results so far.
class StopRule {
 public:
  StopRule(std::vector<std::string> outputs, std::size_t planned, double max_failure_share,
           std::optional<UntilTarget> until, std::size_t replicate_size, bool verbose);
  /// "" to go on, else why the run stops ("until: ..." or "failures: ...").
  std::string operator()(const std::vector<std::vector<double>>& values, const std::vector<std::size_t>& ok_index,
                         std::size_t failures, std::size_t completed);
  bool failed() const { return failed_; }
  /// {"target", "met", "met_at_samples", "checks": [{samples, value, lo, hi, width}]}; null without --until.
  nlohmann::json until_json() const;

 private:
  std::vector<std::string> outputs_;
  std::size_t planned_;
  double max_failure_share_;
  std::optional<UntilTarget> until_;
  std::size_t replicate_size_;
  bool verbose_;
  std::size_t next_check_ = 0;
  bool failed_ = false;
  std::optional<std::size_t> met_at_;
  nlohmann::json checks_ = nlohmann::json::array();
};

/// summary.json "sample_convergence": per output and figure, its interval's relative half-width
/// and the samples a +-1% and a +-5% interval would need (half-width ~ 1/sqrt(n)), so that
/// a reader sees how many samples each figure needed; plus the --until record.
nlohmann::json convergence_json(const std::vector<std::string>& outputs,
                                const std::vector<sampling::Summary>& summaries, std::size_t samples,
                                std::size_t replicate_size, const nlohmann::json& until);

/// summary.json "failures": count, share, and the first failed samples with their seed,
/// reason and the command that replays each alone.
nlohmann::json failures_json(std::size_t count, std::size_t ran,
                             const std::vector<std::pair<std::size_t, std::string>>& first, std::uint64_t seed,
                             const std::string& study_file);

/// After the result folder is written: throws Interrupted (status "interrupted", with what was
/// done and how to resume) or Error (status "failed", the failure share exceeded).
void finish_run_status(const std::string& status, const std::string& reason, int signal, std::size_t ran,
                       std::size_t planned, std::size_t failures, const std::string& dir,
                       const std::string& study_file);

}  // namespace poise::engine
