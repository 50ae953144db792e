#include "engine/run/convergence.h"
#include "core/diagnostics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/format.h"
#include "engine/results/result_io.h"
#include "engine/run/study_runner.h"
#include "sampling/interrupt.h"

namespace poise::engine {
using nlohmann::json;

namespace {
// The figures --until may name: the mean, the sd and every quantile of the summary.
const std::vector<std::string> kStatistics = [] {
  std::vector<std::string> names = {"mean", "std"};
  for (const sampling::SummaryQuantile& q : sampling::summary_quantiles()) names.emplace_back(q.name);
  return names;
}();

std::string statistics_listed() {
  std::string s;
  for (const auto& name : kStatistics) s.append(s.empty() ? "" : ", ").append(name);
  return s;
}
}  // namespace

UntilTarget parse_until(const std::string& text, const std::vector<std::string>& outputs) {
  UntilTarget t;
  t.text = text;
  const std::size_t op = text.find("<=");
  const std::size_t dot = text.rfind('.', op);
  auto listing = [&] {
    std::string s;
    for (const auto& o : outputs) s += (s.empty() ? "" : ", ") + o;
    return s;
  };
  if (op == std::string::npos || dot == std::string::npos) {
    throw UsageError("--until \"" + text +
                     "\": expected OUTPUT.STAT<=WIDTH, e.g. \"los_max_arcsec.p99_73<=0.5\" or "
                     "\"los_max_arcsec.p95<=1%\" (STAT: " +
                     statistics_listed() +
                     "; WIDTH: the 95% interval's full width in the output's unit, or a percentage of the figure)");
  }
  t.output = text.substr(0, dot);
  t.statistic = text.substr(dot + 1, op - dot - 1);
  std::string w = text.substr(op + 2);
  while (!w.empty() && w.front() == ' ') w.erase(w.begin());
  if (!w.empty() && w.back() == '%') {
    t.relative = true;
    w.pop_back();
  }
  if (std::find(outputs.begin(), outputs.end(), t.output) == outputs.end()) {
    throw UsageError("--until \"" + text + "\": no output \"" + t.output + "\" in this study; its outputs are " +
                     listing());
  }
  if (std::find(kStatistics.begin(), kStatistics.end(), t.statistic) == kStatistics.end()) {
    throw UsageError("--until \"" + text + "\": statistic \"" + t.statistic + "\" is not one of " +
                     statistics_listed());
  }
  try {
    std::size_t used = 0;
    t.width = std::stod(w, &used);
    if (used != w.size()) throw Error("");
  } catch (...) {
    throw UsageError("--until \"" + text + "\": width \"" + w + "\" is not a number");
  }
  if (!(t.width > 0) || !std::isfinite(t.width))
    throw UsageError("--until \"" + text + "\": the width must be positive");
  if (t.relative) t.width /= 100.0;
  return t;
}

void check_until_design(const UntilTarget& target, std::size_t replicate_size) {
  if (replicate_size == 0 || target.statistic.empty() || target.statistic[0] != 'p') return;
  double p = 0.5;
  for (const sampling::SummaryQuantile& q : sampling::summary_quantiles()) {
    if (target.statistic == q.name) p = q.p;
  }
  const double tail = static_cast<double>(replicate_size) * std::min(p, 1.0 - p);
  if (tail >= sampling::kMinTailPerReplicate) return;
  const auto needed = static_cast<std::size_t>(std::ceil(sampling::kMinTailPerReplicate / std::min(p, 1.0 - p)));
  throw UsageError("--until \"" + target.text + "\": replicates of " + std::to_string(replicate_size) +
                   " samples cannot support an interval on " + target.statistic + ": each holds about " +
                   significant(tail) + " samples beyond it (replicate_size x " + (p > 0.5 ? "(1 - p)" : "p") + " < " +
                   significant(sampling::kMinTailPerReplicate) +
                   "), so the spread of the replicates is a spread of a few "
                   "counts and a run that stops at its first narrow interval would stop on replicates that agree by "
                   "chance. Set [sampling] replicate_size to at least " +
                   std::to_string(needed) +
                   ", use method = \"monte_carlo\", or put --until on a less extreme figure (p95 needs replicates of "
                   "200, p50 of 20)");
}

const sampling::Estimate& statistic_of(const sampling::Summary& s, const std::string& statistic) {
  if (statistic == "mean") return s.mean;
  if (statistic == "std") return s.std;
  for (const sampling::SummaryQuantile& q : sampling::summary_quantiles()) {
    if (statistic == q.name) return s.*q.field;
  }
  if (statistic == "max") return s.max;
  throw Error("unknown statistic " + statistic);
}

double interval_width(const sampling::Estimate& e) {
  if (!e.lo || !e.hi) return std::numeric_limits<double>::infinity();
  return *e.hi - *e.lo;
}

sampling::Summary summarize_output(const std::vector<double>& values, const std::vector<std::size_t>& ok_index,
                                   std::size_t replicate_size) {
  if (replicate_size == 0) return sampling::summarize(values);
  std::vector<std::size_t> rep(ok_index.size());
  for (std::size_t k = 0; k < rep.size(); ++k) rep[k] = ok_index[k] / replicate_size;
  return sampling::summarize_replicates(values, rep);
}

StopRule::StopRule(std::vector<std::string> outputs, std::size_t planned, double max_failure_share,
                   std::optional<UntilTarget> until, std::size_t replicate_size, bool verbose)
    : outputs_(std::move(outputs)),
      planned_(planned),
      max_failure_share_(max_failure_share),
      until_(std::move(until)),
      replicate_size_(replicate_size),
      verbose_(verbose),
      next_check_(replicate_size > 0 ? 2 * replicate_size : 100) {}

std::string StopRule::operator()(const std::vector<std::vector<double>>& values,
                                 const std::vector<std::size_t>& ok_index, std::size_t failures,
                                 std::size_t completed) {
  const double limit = max_failure_share_ * static_cast<double>(planned_);
  const sampling::Estimate share = sampling::fraction_wilson(failures, std::max<std::size_t>(completed, 1));
  if (static_cast<double>(failures) > limit || (completed >= 50 && share.lo && *share.lo > max_failure_share_)) {
    failed_ = true;
    return fmt::format(
        "failures: {} of the {} samples run failed ({:.1f}%, 95% interval {:.1f}-{:.1f}%), more than "
        "max_failure_share = {:.3g} of the {} planned allows",
        failures, completed, 100.0 * share.value, 100.0 * share.lo.value_or(0), 100.0 * share.hi.value_or(1),
        max_failure_share_, planned_);
  }
  if (!until_ || completed < next_check_) return "";
  if (replicate_size_ > 0 && completed % replicate_size_ != 0) return "";
  next_check_ = std::max(completed + 1, static_cast<std::size_t>(std::ceil(1.1 * static_cast<double>(completed))));
  const auto k =
      static_cast<std::size_t>(std::find(outputs_.begin(), outputs_.end(), until_->output) - outputs_.begin());
  if (k >= values.size() || values[k].size() < 2) return "";
  const sampling::Summary s = summarize_output(values[k], ok_index, replicate_size_);
  const sampling::Estimate& e = statistic_of(s, until_->statistic);
  const double width = interval_width(e);
  const double target = until_->relative ? until_->width * std::abs(e.value) : until_->width;
  checks_.push_back({{"samples", completed},
                     {"value", e.value},
                     {"ci95", estimate_json(e)["ci95"]},
                     {"width", width},
                     {"target_width", target}});
  if (verbose_) {
    diagnostics::progress("\n  until: " + until_->output + "." + until_->statistic + " = " + significant(e.value) +
                          ", 95% interval width " + significant(width) + " (target " + significant(target) + ") at " +
                          std::to_string(completed) + " samples");
  }
  if (width <= target) {
    met_at_ = completed;
    return "until: " + until_->text + " met at " + std::to_string(completed) + " samples (width " + significant(width) +
           " <= " + significant(target) + ")";
  }
  return "";
}

json StopRule::until_json() const {
  if (!until_) return nullptr;
  return {{"target", until_->text},
          {"output", until_->output},
          {"statistic", until_->statistic},
          {"width", until_->width},
          {"relative", until_->relative},
          {"met", met_at_.has_value()},
          {"met_at_samples", met_at_ ? json(*met_at_) : json(nullptr)},
          {"cap_samples", planned_},
          {"checks", checks_}};
}

json convergence_json(const std::vector<std::string>& outputs, const std::vector<sampling::Summary>& summaries,
                      std::size_t samples, std::size_t replicate_size, const json& until) {
  json figures = json::object();
  for (std::size_t k = 0; k < outputs.size() && k < summaries.size(); ++k) {
    json o = json::object();
    for (const std::string& stat : kStatistics) {
      const sampling::Estimate& e = statistic_of(summaries[k], stat);
      const double half = 0.5 * interval_width(e);
      const double rel = std::abs(e.value) > 0 ? half / std::abs(e.value) : std::numeric_limits<double>::infinity();
      auto need = [&](double target) -> json {
        if (!std::isfinite(rel)) return nullptr;
        return static_cast<std::size_t>(std::ceil(static_cast<double>(samples) * (rel / target) * (rel / target)));
      };
      o[stat] = {{"value", e.value},
                 {"relative_half_width", std::isfinite(rel) ? json(rel) : json(nullptr)},
                 {"samples_for_1pct", need(0.01)},
                 {"samples_for_5pct", need(0.05)}};
      if (!e.note.empty()) o[stat]["ci95_note"] = e.note;
    }
    figures[outputs[k]] = o;
  }
  return {{"samples", samples},
          {"intervals", replicate_size > 0 ? "by replicate (" + std::to_string(replicate_size) + " samples each)"
                                           : std::string("independent samples")},
          {"note",
           "samples_for_Xpct: samples a 95% interval of +-X% of the figure would need, from this run's "
           "interval (half-width ~ 1/sqrt(n)); null where the interval has no end"},
          {"figures", figures},
          {"until", until}};
}

json failures_json(std::size_t count, std::size_t ran, const std::vector<std::pair<std::size_t, std::string>>& first,
                   std::uint64_t seed, const std::string& study_file) {
  json j{{"count", count},
         {"share", ran > 0 ? static_cast<double>(count) / static_cast<double>(ran) : 0.0},
         {"first", json::array()}};
  for (const auto& [i, why] : first) {
    j["first"].push_back({{"sample", i},
                          {"seed", seed},
                          {"reason", why},
                          {"replay", "poise replay " + study_file + " --sample " + std::to_string(i) + " --seed " +
                                         std::to_string(seed)}});
  }
  return j;
}

void finish_run_status(const std::string& status, const std::string& reason, int signal, std::size_t ran,
                       std::size_t planned, std::size_t failures, const std::string& dir,
                       const std::string& study_file) {
  if (status == "interrupted") {
    throw Interrupted(std::string(signal == 2    ? "SIGINT"
                                  : signal == 15 ? "SIGTERM"
                                                 : "a signal") +
                          ": stopped after " + std::to_string(ran) + " of " + std::to_string(planned) + " samples (" +
                          std::to_string(failures) + " failed). Every finished sample is in " + dir +
                          "/samples.csv and summary.json covers them. Complete the run with:\n  poise run " +
                          study_file + " --resume " + dir,
                      signal);
  }
  if (status == "failed") {
    throw Error(reason + ". The run stopped; " + dir + "/samples.csv keeps every sample with its reason and " + dir +
                "/summary.json lists the first failures with the command that replays each. Raise [sampling] "
                "max_failure_share if such failures are expected.");
  }
  // A signal while the summary and report were written: every sample had run and the files
  // are whole, but the stop asked for is honoured in the exit status.
  if (sampling::interrupt_requested()) {
    const int sig = sampling::interrupt_signal();
    throw Interrupted(std::string(sig == 2    ? "SIGINT"
                                  : sig == 15 ? "SIGTERM"
                                              : "a signal") +
                          " while the results were written: the run is complete (" + std::to_string(ran) +
                          " samples); " + dir + " holds samples.csv, summary.json and report.html",
                      sig);
  }
}

}  // namespace poise::engine
