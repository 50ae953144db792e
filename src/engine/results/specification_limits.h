#pragma once
/// Two-sided specification limits: the requirement a stack-up is judged by.
///
///     [[requirement]]
///     output = "gap_mm"
///     within = ["0.05 mm", "0.80 mm"]   # lower and upper specification limits (LSL, USL)
///     yield_at_least = 0.9973           # or ppm_at_most = 2700, or cpk_at_least = 1.33
///     confidence = 0.95                 # one-sided, default 0.95
///
/// Its figure (the requirement's statistic):
///   yield  the share of units within [LSL, USL]. A failed sample (no value: its formula or its
///          procedure has no answer) counts as outside: a unit nobody can build to the drawing
///          is not a good one. Bounds: Clopper-Pearson (exact binomial) on independent samples,
///          the replicates' spread otherwise (engine/results/confidence_bound.h).
///   ppm    parts per million outside [LSL, USL], 1e6 (1 - yield), with the bounds of the yield.
///   cpk    min(USL - mean, mean - LSL) / (3 s) over the samples that ran (failed samples have
///          no value to enter it; the verdict's note counts them). Its one-sided bound is
///          Bissell's normal approximation (Bissell 1990, J. Appl. Stat. 17:3, eq. 2):
///          Cpk -+ z_c sqrt(1 / (9 n) + Cpk^2 / (2 (n - 1))), which assumes normal values, as
///          Cpk itself does. Its coverage (tests/engine/specification_limits_test.cc) is the
///          stated one for a process off centre and higher (about 97.5% for 95%) for a centred
///          one, where the min() of the two sides biases Cpk low: conservative there.
#include <optional>
#include <string>

#include "engine/results/requirements.h"

namespace poise::engine {

/// Whether a requirement's statistic is one of a two-sided specification (yield, ppm, cpk).
bool is_specification_statistic(const std::string& statistic);

/// Reads within = [LSL, USL] and its one figure (yield_at_least, ppm_at_most, cpk_at_least)
/// of a [[requirement]] table into `r` (statistic, at_most, limit_text, within); errors on `t`.
void read_specification(TomlReader& t, Requirement& r);

/// The figure of a specification requirement and its one-sided bounds at the requirement's
/// confidence, on the requirement's side (`bound`) and the other (`other`).
struct SpecificationFigure {
  double value = 0.0;
  std::optional<double> bound, other;
  std::string note;
};

/// The figure of `r` (a specification statistic) on the output's values, the limits in the
/// output's unit.
SpecificationFigure specification_figure(const Requirement& r, const OutputValues& values, double lower, double upper);

/// Lower and upper specification limits of `r` in the output's unit (its `unit`).
std::pair<double, double> specification_limits(const Requirement& r, const std::string& unit);

/// Bissell's one-sided bound of Cpk (see above) from n normal values at confidence c.
double cpk_bound(double cpk, std::size_t n, double confidence, bool upper);

}  // namespace poise::engine
