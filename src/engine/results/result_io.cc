#include "engine/results/result_io.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "core/format.h"
#include "engine/results/checked_file.h"

namespace poise::engine {

nlohmann::json estimate_json(const sampling::Estimate& e) {
  using nlohmann::json;
  json j{{"value", e.value}, {"ci95", {e.lo ? json(*e.lo) : json(nullptr), e.hi ? json(*e.hi) : json(nullptr)}}};
  if (!e.note.empty()) j["ci95_note"] = e.note;  // one-sided or approximate, and why
  return j;
}

nlohmann::json summary_json(const sampling::Summary& s) {
  nlohmann::json j{{"n", s.n}, {"mean", estimate_json(s.mean)}, {"std", estimate_json(s.std)}};
  j["min"] = estimate_json(s.min);
  for (const sampling::SummaryQuantile& q : sampling::summary_quantiles()) j[q.name] = estimate_json(s.*q.field);
  j["max"] = estimate_json(s.max);
  return j;
}

std::string csv_number(double v) {
  // Shortest text that reads back to the same double: a resumed run's statistics, computed
  // from samples.csv, are then exactly those of an uninterrupted run.
  if (std::isnan(v)) return "nan";
  char buf[40];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

char* put_csv_number(char* at, double v) {
  *at++ = ',';
  if (std::isnan(v)) return std::copy_n("nan", 3, at);
  return std::to_chars(at, at + (kCsvNumberChars - 1), v).ptr;
}

void append_csv_number(std::string& row, double v) {
  char buf[kCsvNumberChars];
  row.append(buf, put_csv_number(buf, v));
}

void write_file_atomic(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  std::error_code ec;
  try {
    CheckedFile out(tmp, false);
    out.write(text);
    out.close();
  } catch (const WriteError&) {
    std::filesystem::remove(tmp, ec);  // never leave a half-written .tmp behind
    throw;
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    const std::string reason = ec.message();
    std::filesystem::remove(tmp, ec);
    throw WriteError(path, "cannot move " + tmp + " over it: " + reason);
  }
}

std::string csv_text(std::string s) {
  for (auto& ch : s) {
    if (ch == '"' || ch == ',' || ch == '\n' || ch == '\r') ch = ' ';
  }
  return s;
}

std::string html_escape(const std::string& s) {
  std::string o;
  o.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '&': o += "&amp;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

}  // namespace poise::engine

namespace poise::engine {

std::string format_significant(double v, int digits) {
  if (!std::isfinite(v)) return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
  return significant(v, digits);
}

}  // namespace poise::engine
