#include "cli/budget_text.h"

#include <cmath>

#include "core/format.h"

namespace poise::cli {
namespace {

using nlohmann::json;

std::string percent(const json& v) {
  if (v.is_null()) return "";
  return fmt::format("{:+.1f}%", 100.0 * v.get<double>());  // as printed before: a tiny negative is "-0.0%"
}

void print_item(const json& it, const std::string& unit, std::ostream& out) {
  const std::string verdict = it["verdict"].get<std::string>();
  out << "  " << it["name"].get<std::string>() << " (" << it["kind"].get<std::string>() << ")\n";
  if (verdict == "given") {
    out << "      given as " << budget_number(it["value"]) << " " << unit << ": nothing to recompute\n";
    return;
  }
  out << "      recomputed " << recomputed_text(it, unit);
  if (verdict == "no_declared") {
    out << "; nothing declared to compare\n";
    return;
  }
  out << ", declared " << declared_text(it["declared"], unit);
  const std::string rd = percent(it["relative_difference"]);
  if (!rd.empty()) out << " (" << rd << ")";
  out << ": " << (verdict == "agrees" ? "agrees (within 1%)" : "DISAGREES");
  if (verdict == "disagrees" && it.contains("verdict_least")) {
    out << " (least " << it["verdict_least"].get<std::string>() << ", greatest "
        << it["verdict_greatest"].get<std::string>() << ")";
  }
  out << '\n';
  if (it.contains("slip")) out << "      likely slip: " << it["slip"].get<std::string>() << '\n';
  if (it.contains("from_members_declared") && verdict == "disagrees") {
    out << "      its members' declared values give " << budget_number(it["from_members_declared"]["least"]) << " to "
        << budget_number(it["from_members_declared"]["greatest"]) << " " << unit << '\n';
  }
}

// The budget's name and file, how many declared figures follow from their inputs, and the
// field it holds over.
void print_heading(const json& j, const std::string& unit, std::ostream& out) {
  const json& b = j["budget"];
  int agree = 0, disagree = 0;
  for (const auto* list : {&j["lines"], &j["groups"]}) {
    for (const auto& it : *list) {
      agree += it["verdict"] == "agrees";
      disagree += it["verdict"] == "disagrees";
    }
  }
  out << "Budget \"" << b["name"].get<std::string>() << "\" (" << b["file"].get<std::string>()
      << "): " << j["lines"].size() << " lines, " << j["groups"].size() << " groups, in " << unit
      << ", each contribution at " << b["level"].get<std::string>() << ", combined by "
      << b["combination"].get<std::string>() << ".\n";
  if (!b["title"].get<std::string>().empty()) out << b["title"].get<std::string>() << '\n';
  out << agree << " declared figures follow from their inputs, " << disagree << " do not.\n";
  if (!b["field"].empty()) {
    out << "Over the field";
    for (const auto& f : b["field"]) {
      out << " " << f["name"].get<std::string>() << " from " << budget_number(f["least"]) << " to "
          << budget_number(f["greatest"]) << (f["unit"].get<std::string>().empty() ? "" : " ")
          << f["unit"].get<std::string>() << ";";
    }
    out << " " << b["field_grid_points"] << " grid points (ends and zero included).\n";
  }
}

// The combination of the lines, against its declared value (and in pixels).
void print_combined(const json& c, const std::string& unit, std::ostream& out) {
  out << "\nCombined by " << c["combination"].get<std::string>() << " at " << c["level"].get<std::string>() << ": "
      << recomputed_text(c, unit);
  if (!c["declared"].is_null()) {
    out << "; declared " << declared_text(c["declared"], unit);
    const std::string rd = percent(c["relative_difference"]);
    if (!rd.empty()) out << " (" << rd << ")";
    out << ": " << (c["verdict"] == "agrees" ? "agrees" : "DISAGREES");
    if (c["verdict"] == "disagrees" && c.contains("verdict_least")) {
      out << " (least " << c["verdict_least"].get<std::string>() << ", greatest "
          << c["verdict_greatest"].get<std::string>() << ")";
    }
  }
  out << '\n';
  if (c.contains("slip")) out << "      likely slip: " << c["slip"].get<std::string>() << '\n';
  if (c.contains("from_declared") && c["verdict"] == "disagrees") {
    out << "      the declared entries combined give " << budget_number(c["from_declared"]["least"]) << " to "
        << budget_number(c["from_declared"]["greatest"]) << " " << unit << '\n';
  }
  if (c.contains("in_pixels")) {
    out << "      in pixels: " << budget_number(c["least_px"]) << " to " << budget_number(c["greatest_px"])
        << " px; declared " << declared_text(c["in_pixels"]["declared"], "px") << ": "
        << (c["in_pixels"]["verdict"] == "agrees" ? "agrees" : "DISAGREES");
    if (c["in_pixels"]["verdict"] == "disagrees" && c["in_pixels"].contains("verdict_least")) {
      out << " (least " << c["in_pixels"]["verdict_least"].get<std::string>() << ", greatest "
          << c["in_pixels"]["verdict_greatest"].get<std::string>() << ")";
    }
    out << '\n';
  }
}

// The combination at the stated confidence, and the requirement by the combination rule.
void print_at_confidence(const json& j, const std::string& unit, std::ostream& out) {
  const json& b = j["budget"];
  const json& a = j["at_confidence"];
  out << "At the confidence " << a["confidence"].get<double>() << " (normal two-sided multiple "
      << fixed(a["multiple"].get<double>(), 3) << ", random lines x " << budget_number(a["random_scale"])
      << "): " << recomputed_text(a, unit) << '\n';
  if (!j["requirement_met"].is_null()) {
    out << "Requirement " << budget_number(b["requirement"]) << " " << unit << " ("
        << b["requirement_as_written"].get<std::string>()
        << "): " << (j["requirement_met"].get<bool>() ? "met" : "NOT met")
        << " by the combination rule alone (the budget's greatest " << budget_number(a["greatest"]) << " " << unit
        << "); the answer below decides on the Monte Carlo where there is one.\n";
  }
}

// The Monte Carlo of the model's exact chain, against the budget.
void print_monte_carlo(const json& j, const std::string& unit, std::ostream& out) {
  const json& a = j["at_confidence"];
  const json& m = j["monte_carlo"];
  out << "\nMonte Carlo of the model's exact chain (" << m["model"].get<std::string>() << ", " << m["samples"]
      << " samples, " << m["failures"] << " failed, seed " << m["seed"] << "):\n  " << m["output"].get<std::string>()
      << " at " << m["quantile"].get<double>() << ": " << budget_number(m["value"]) << " " << unit << " (95% interval "
      << budget_number(m["ci95"][0]) << " to " << budget_number(m["ci95"][1]) << ")\n  The budget ("
      << budget_number(a["greatest"]) << " " << unit << ") is " << j["budget_vs_monte_carlo"].get<std::string>()
      << " against it"
      << (j["budget_vs_monte_carlo_decided"].get<bool>() ? "" : " (within the Monte Carlo's 95% interval: not decided)")
      << ".\n";
}

}  // namespace

void print_budget_text(const json& j, std::ostream& out) {
  const std::string unit = j["budget"]["unit"].get<std::string>();
  print_heading(j, unit, out);
  out << "\nLines, recomputed from their inputs:\n";
  for (const auto& it : j["lines"]) print_item(it, unit, out);
  if (!j["groups"].empty()) {
    out << "\nGroups (sub-totals), recomputed from their members:\n";
    for (const auto& it : j["groups"]) print_item(it, unit, out);
  }
  print_combined(j["combined"], unit, out);
  print_at_confidence(j, unit, out);
  if (!j["monte_carlo"].is_null()) print_monte_carlo(j, unit, out);
  if (!j["unmapped_model_tolerances"].empty()) {
    out << "Model tolerances no line covers (the budget leaves them out):";
    for (const auto& k : j["unmapped_model_tolerances"]) out << " " << k.get<std::string>();
    out << '\n';
  }
  for (const auto& k : j["unknown_model_keys"]) {
    out << "Warning: " << k["in"].get<std::string>() << " (line " << k["line"] << ") names \""
        << k["key"].get<std::string>() << "\", which the model does not have.\n";
  }
}

}  // namespace poise::cli
