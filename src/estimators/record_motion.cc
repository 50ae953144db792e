#include "estimators/record_motion.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/angles.h"
#include "core/format.h"
#include "estimators/oscillation_detail.h"

namespace poise::estimators {
namespace osc {
namespace {

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const auto at = static_cast<std::ptrdiff_t>(std::floor(q * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + at, v.end());
  return v[static_cast<std::size_t>(at)];
}

std::string turns_text(double turns) { return significant(turns, 3) + (turns > 1.0 ? " turns" : " turn"); }

std::string directions(const RecordMotion& m) {
  return m.forward && m.backward ? "both directions" : m.forward ? "forward only" : "backward only";
}

}  // namespace

RecordMotion recognise_motion(const Signals& s, bool timed, int window) {
  RecordMotion m;
  m.timed = timed;
  m.span = s.span_all;
  m.turns = m.span / angles::kTwoPi;
  // Moving rows: the angle's own step to the next row is at least 10 % of the 90th percentile
  // of the steps (a held position's encoder jitter of a count is not a move; the smoothed rate
  // would spread a step's move over a derivative window).
  std::vector<double> steps;
  for (Eigen::Index k = 1; k < s.phi.size(); ++k) steps.push_back(std::abs(s.phi[k] - s.phi[k - 1]));
  const double threshold = 0.1 * quantile(steps, 0.9);
  std::vector<double> moving;
  std::size_t forward = 0, backward = 0;
  for (Eigen::Index k = 1; k < s.phi.size(); ++k) {
    if (!(steps[static_cast<std::size_t>(k - 1)] > threshold)) continue;
    moving.push_back(std::abs(s.rate[k]));
    (s.phi[k] > s.phi[k - 1] ? forward : backward)++;
  }
  m.moving_share = static_cast<double>(moving.size()) / static_cast<double>(std::max<std::size_t>(1, steps.size()));
  m.forward = forward > 0 && 10 * forward >= moving.size();
  m.backward = backward > 0 && 10 * backward >= moving.size();
  m.speed = quantile(moving, 0.5);
  m.speed_variation = m.speed > 0 ? (quantile(moving, 0.75) - quantile(moving, 0.25)) / m.speed : 0.0;
  // Reversals: direction changes with a window of rows on each side.
  Eigen::Index run_start = 0;
  double run_sign = s.direction.size() > 0 ? s.direction[0] : 0.0;
  bool previous_long = false;
  for (Eigen::Index k = 1; k <= s.direction.size(); ++k) {
    if (k < s.direction.size() && s.direction[k] == run_sign) continue;
    const bool long_run = k - run_start >= window;
    if (long_run && previous_long && k > window) ++m.reversals;
    if (long_run) previous_long = true;
    if (k < s.direction.size()) run_start = k, run_sign = s.direction[k];
  }
  const std::string unit = timed ? "turn/s" : "turn per row";
  if (m.turns < 0.5 && m.reversals >= 1 && timed) {
    m.kind = "swing";
    m.description = fmt::format("a swing about a position: {} deg peak to peak, {} reversals",
                                significant(m.span / angles::kPi * 180.0, 3), m.reversals);
  } else if (!timed || m.moving_share < 0.5) {
    m.kind = "steps";
    m.description =
        fmt::format("a quasi-static map ({}), {}: {}{}", timed ? "stepped and held" : "rows in file order, no time",
                    directions(m), turns_text(m.turns),
                    timed ? fmt::format(", moving in {}% of the rows", std::lround(100 * m.moving_share)) : "");
  } else {
    m.kind = "laps";
    m.description = fmt::format("laps at {} speed, {}: {} at {} {} (speed varies by {}% interquartile)",
                                m.speed_variation < 0.3 ? "a steady" : "a varying", directions(m), turns_text(m.turns),
                                significant(m.speed / angles::kTwoPi, 3), unit, std::lround(100 * m.speed_variation));
  }
  return m;
}

}  // namespace osc

RecordMotion record_motion(const OscillationRecord& rec, const OscillationOptions& opt) {
  return osc::recognise_motion(osc::derive_signals(rec, opt), !rec.no_time, opt.derivative_window);
}

}  // namespace poise::estimators
