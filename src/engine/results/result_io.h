#pragma once
/// Shared pieces of every result folder: statistics as JSON (value and 95% CI), numbers and
/// text for samples.csv, and escaping for report.html.
#include <nlohmann/json.hpp>
#include <string>

#include "sampling/statistics.h"

namespace poise::engine {

/// {"value": v, "ci95": [lo or null, hi or null]}
nlohmann::json estimate_json(const sampling::Estimate& e);
/// {"n", "mean", "std", "min", "p0_135", "p2_5", "p50", "p95", "p97_5", "p99_73", "p99_865",
/// "max"}, each an estimate_json (sampling::summary_quantiles()).
nlohmann::json summary_json(const sampling::Summary& s);
/// A number for samples.csv: the shortest text that reads back to the same double ("nan" for NaN).
std::string csv_number(double v);
/// Appends ',' and csv_number(v) to a row without a temporary string (rows of 70 numbers).
void append_csv_number(std::string& row, double v);
/// Room put_csv_number needs at most: ',' and the longest shortest double, -2.2250738585072014e-308.
inline constexpr std::size_t kCsvNumberChars = 25;
/// Writes ',' and csv_number(v) at `at` (kCsvNumberChars free) and returns the end: a row's
/// numbers formatted into one buffer, appended to the text once.
char* put_csv_number(char* at, double v);
/// Free text for one CSV cell: quotes, commas and newlines become spaces.
std::string csv_text(std::string s);
/// Writes a whole file atomically: to a temporary beside it, flushed, then renamed over the
/// target, so a reader (or a run killed meanwhile) never sees half a file. Throws WriteError
/// ("<file>: <system's reason>") on failure, the temporary removed.
void write_file_atomic(const std::string& path, const std::string& text);
/// Text for HTML.
std::string html_escape(const std::string& s);
/// A figure for people: `digits` significant digits, no trailing zeros ("1.25", "3.2e-05").
std::string format_significant(double v, int digits = 4);

}  // namespace poise::engine
