// The answer of a study in words (engine/results/requirements.h): each verdict's clause, the
// sentence they make, and the words a requirement is read in.
#include <algorithm>
#include <cctype>
#include <cmath>

#include "engine/kind_interface/study_kind.h"
#include "engine/results/requirements.h"
#include "engine/results/result_io.h"
#include "engine/results/specification_limits.h"

namespace poise::engine {
namespace {
using nlohmann::json;

// The sentence without a requirement: the p95 of the first output with a summary.
std::string no_requirement_sentence(const json& outputs_summary, const std::vector<OutputSpec>& outputs,
                                    std::size_t samples, const std::string& partial) {
  std::string s = "No requirement is declared";
  for (const auto& o : outputs) {
    if (!outputs_summary.contains(o.name)) continue;
    const json& p95 = outputs_summary[o.name]["p95"];
    s += ": p95 of " + o.name + " is " + with_unit(p95["value"].get<double>(), o.unit);
    if (p95["ci95"][0].is_number() && p95["ci95"][1].is_number()) {
      s += " [" + format_significant(p95["ci95"][0].get<double>(), 4) + ", " +
           format_significant(p95["ci95"][1].get<double>(), 4) + "]";
    }
    s += " over " + std::to_string(samples) + " samples";
    break;
  }
  return s + partial + " (state one with [[requirement]] to get a verdict).";
}

// The requirements' clauses by verdict.
struct VerdictClauses {
  std::vector<std::string> met, not_met, undecided;
};

// One verdict's clause: its figures, with the bound that decides it.
void add_clause(const json& v, VerdictClauses& c) {
  const std::string unit = v["limit"]["unit"].get<std::string>();
  const double limit = v["limit"]["value"].get<double>();
  std::string clause = requirement_text(v);
  if (v["value"].is_null()) {
    c.undecided.push_back(clause + ": no sample ran");
    return;
  }
  const double value = v["value"].get<double>();
  const std::string pct = std::to_string(static_cast<int>(std::round(v["confidence"].get<double>() * 100.0))) + "%";
  const std::string side = v["bound_side"].get<std::string>();
  const std::string verdict = v["verdict"].get<std::string>();
  // The bound that decides: on the requirement's side for "met", on the other for "not met".
  const bool other = verdict == "not met";
  const json& bound = v[other ? "other_bound" : "bound"];
  const std::string bound_side = other ? (side == "upper" ? "lower" : "upper") : side;
  std::string figures = "is " + with_unit(value, unit);
  if (bound.is_number())
    figures += " (" + bound_side + " " + pct + " bound " + format_significant(bound.get<double>(), 4) + ")";
  if (verdict == "met") {
    c.met.push_back(requirement_subject(v) + " " + figures + (v["at_most"].get<bool>() ? " <= " : " >= ") +
                    v["limit"]["as_written"].get<std::string>());
  } else if (verdict == "not met") {
    const double over = std::abs(value - limit);
    std::string by = with_unit(over, unit);
    if (limit != 0.0) by += " (" + format_significant(100.0 * over / std::abs(limit), 3) + "%)";
    c.not_met.push_back(clause + ": it " + figures + ", " + by + (v["at_most"].get<bool>() ? " over" : " short"));
  } else {
    std::string u = clause + ": it " + figures + " and the interval straddles the limit";
    if (v.contains("note")) {
      u += "; " + v["note"].get<std::string>();
    } else if (v.contains("samples_to_decide")) {
      u += "; about " + std::to_string(v["samples_to_decide"].get<std::size_t>()) + " samples would likely decide it";
    }
    c.undecided.push_back(u);
  }
}

std::string join_clauses(const std::vector<std::string>& parts) {
  std::string s;
  for (const auto& p : parts) s += (s.empty() ? "" : "; ") + p;
  return s;
}

// The answer from the clauses: any failure first, then what is undecided, then what is met.
std::string verdicts_sentence(const VerdictClauses& c, std::size_t n_verdicts, const std::string& partial) {
  const auto& join = join_clauses;
  const std::string count = std::to_string(n_verdicts);
  std::string s;
  if (!c.not_met.empty()) {
    s = n_verdicts == 1 ? "NOT met" + partial + ": " + join(c.not_met)
                        : "NOT met: " + std::to_string(c.not_met.size()) + " of " + count + " requirements fail" +
                              partial + ": " + join(c.not_met);
    if (!c.undecided.empty()) s += "; undecided: " + join(c.undecided);
  } else if (!c.undecided.empty()) {
    s = "Undecided" + partial + ": " + join(c.undecided);
    if (!c.met.empty()) s += "; met: " + join(c.met);
  } else {
    s = (n_verdicts == 1 ? std::string("The requirement is met")
                         : "Every requirement is met (" + count + " of " + count + ")") +
        partial + ": " + join(c.met);
  }
  return s;
}

}  // namespace

std::string answer_sentence(const json& verdicts, const json& outputs_summary, const std::vector<OutputSpec>& outputs,
                            const std::string& status, std::size_t samples) {
  const std::string partial =
      status == "complete" ? "" : " (on the " + std::to_string(samples) + " samples of a run that is " + status + ")";
  if (verdicts.empty()) return no_requirement_sentence(outputs_summary, outputs, samples, partial);
  VerdictClauses clauses;
  for (const auto& v : verdicts) add_clause(v, clauses);
  std::string s = verdicts_sentence(clauses, verdicts.size(), partial);
  for (const auto& v : verdicts) {
    if (v.contains("design_note")) {
      s += " (the bounds assume independent samples, which this lhs or sobol design without replicate_size does not "
           "guarantee)";
      break;
    }
  }
  return s + ".";
}

void add_answer(json& summary, const std::vector<Requirement>& requirements, const std::vector<OutputSpec>& outputs,
                const std::function<OutputValues(const std::string&)>& values_of, const std::string& status,
                std::size_t samples, bool saltelli_layout) {
  if (saltelli_layout) {
    summary["requirements"] = json::array();
    summary["answer"] =
        requirements.empty()
            ? std::string("A sensitivity run: Sobol indices of every output (no requirement is declared).")
            : "A sensitivity run: its samples follow the Saltelli layout, not independent draws, so it "
              "states no verdict; `poise run` decides the " +
                  std::to_string(requirements.size()) + " requirement(s).";
    return;
  }
  summary["requirements"] = judge_requirements(requirements, outputs, values_of);
  summary["answer"] =
      answer_sentence(summary["requirements"], summary.value("outputs", json::object()), outputs, status, samples);
}

std::vector<std::pair<std::string, std::string>> shown_statistics(const json& verdicts,
                                                                  const std::vector<OutputSpec>& outputs,
                                                                  std::size_t fallback) {
  std::vector<std::pair<std::string, std::string>> shown;
  for (const auto& v : verdicts) {
    const std::string output = v["output"].get<std::string>(), statistic = v["statistic"].get<std::string>();
    // A specification is shown by the output's natural process limits (p0.135 and p99.865).
    std::vector<std::string> statistics = {statistic};
    if (is_specification_statistic(statistic)) statistics = {"p0_135", "p99_865"};
    for (const std::string& stat : statistics) {
      const std::pair<std::string, std::string> p{output, stat};
      if (std::find(shown.begin(), shown.end(), p) == shown.end()) shown.push_back(p);
    }
  }
  if (shown.empty()) {
    for (std::size_t k = 0; k < outputs.size() && k < fallback; ++k) shown.emplace_back(outputs[k].name, "p95");
  }
  return shown;
}

std::optional<bool> requirements_met(const json& summary) {
  const auto it = summary.find("requirements");
  if (it == summary.end() || !it->is_array() || it->empty()) return std::nullopt;
  for (const auto& v : *it) {
    if (v.value("verdict", "") != "met") return false;
  }
  return true;
}

// A figure in the output's unit, 4 significant digits ("1.25 mN*m", "0.42" when unitless).
std::string with_unit(double v, const std::string& unit) {
  const std::string number = format_significant(v, 4);
  return unit.empty() || unit == "1" ? number : number + " " + unit;
}

std::string statistic_label(const std::string& statistic) {
  if (statistic == "cpk") return "Cpk";
  if (statistic.size() > 1 && statistic[0] == 'p' && std::isdigit(static_cast<unsigned char>(statistic[1]))) {
    std::string label = statistic;
    std::replace(label.begin(), label.end(), '_', '.');
    return label;
  }
  return statistic;
}

std::string requirement_subject(const json& v) {
  const std::string statistic = v["statistic"].get<std::string>();
  std::string s = statistic_label(statistic) + " of " + v["output"].get<std::string>();
  if (v.contains("within")) {
    const json& w = v["within"]["as_written"];
    s += std::string(statistic == "ppm"   ? " outside"
                     : statistic == "cpk" ? " on"
                                          : " within") +
         " [" + w[0].get<std::string>() + ", " + w[1].get<std::string>() + "]";
  }
  return s;
}

// What a requirement says, in words: "p95 of g_rmse_torque_mNm at most 1.5 mN*m".
std::string requirement_text(const json& v) {
  return requirement_subject(v) + (v["at_most"].get<bool>() ? " at most " : " at least ") +
         v["limit"]["as_written"].get<std::string>();
}

}  // namespace poise::engine
