#include "balancing/campaign_analysis.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include <fmt/format.h>

#include "core/error.h"
#include "core/format.h"

namespace poise::balancing {
namespace {
using estimators::Phasor;
using estimators::PhasorInterval;

// Rows of the runs the calibration leaves out, grouped by declared run, in the campaign's order.
std::vector<RunAnswer> answers_of_unused_runs(const std::vector<estimators::BalancingRun>& all,
                                              const BalancingCampaign& c, const CampaignAnalysis& a) {
  std::map<std::size_t, std::vector<const estimators::BalancingRun*>> rows;
  for (const auto& r : all) {
    if (!r.masses || r.check) rows[r.declared].push_back(&r);
  }
  std::vector<RunAnswer> out;
  for (const auto& [declared, runs] : rows) {
    std::vector<std::vector<Phasor>> readings;
    for (const auto* r : runs) readings.push_back(r->readings);
    RunAnswer answer{runs.front()->name,
                     declared,
                     runs.front()->check,
                     runs.size(),
                     estimators::unbalance_answers(a.calibration, readings, c.plane_radius),
                     runs.front()->masses};
    if (!answer.check) answer.applied.reset();
    out.push_back(std::move(answer));
  }
  return out;
}

std::string answer_sentence(const BalancingCampaign& c, const CampaignAnalysis& a) {
  std::string s;
  for (const auto& t : a.model_tests) {
    // A declared sense the readings contradict comes first: every answer below assumes it.
    if (t.significant && t.name == "phase sense" && t.finding.find("opposite senses") != std::string::npos) {
      s = "The readings contradict the declared phase and angle senses (they follow the masses' mirror images): "
          "declare the other phase or weight_angles; as declared, ";
    }
  }
  s += s.empty() ? "Correction (trial masses removed):" : "the correction (trial masses removed):";
  for (std::size_t p = 0; p < c.planes.size(); ++p) {
    s += p ? ", " : " ";
    s += c.planes[p] + " " + phasor_text(a.correction_masses.planes[p], "g");
    if (p < a.correction_holes.size() && !a.correction_holes[p].empty()) {
      s += " (on its holes: " + holes_text(a.correction_holes[p]) + ")";
    }
  }
  double before = 0.0;
  for (const auto& z : a.calibration.initial) before += std::norm(z.value);
  before = std::sqrt(before / static_cast<double>(a.calibration.initial.size()));
  s += "; the predicted residual RMS " + significant(a.correction.residual_rms, 3) + " " + c.amplitude_unit +
       " (from " + significant(before, 3) + " " + c.amplitude_unit + ")";
  std::size_t checks = 0, covered = 0, with_region = 0;
  for (const auto& r : a.runs) {
    if (!r.check) continue;
    ++checks;
    for (std::size_t p = 0; p < c.planes.size(); ++p) {
      if (!r.unbalance.planes[p].radius()) continue;
      ++with_region;
      covered += r.unbalance.planes[p].contains((*r.applied)[p]) ? 1 : 0;
    }
  }
  if (checks > 0 && with_region > 0) {
    s += fmt::format("; check runs: {} of {} plane masses within their 95% regions", covered, with_region);
  }
  if (a.calibration.dof == 0 && !a.calibration.noise_declared) {
    s += "; no intervals (as many runs as unknowns: one more run, or the instrument's reading_noise, would give them)";
  }
  if (a.calibration.noise_declared) s += "; regions from the declared reading noise alone (no degrees of freedom)";
  std::string missing;
  for (const auto& t : a.model_tests) {
    if (t.significant) missing += (missing.empty() ? "" : ", ") + t.name;
  }
  if (!missing.empty())
    s += "; the linear model does not hold on these readings (" + missing + ": see the model tests)";
  return s + ".";
}

}  // namespace

double degrees(const Phasor& z) {
  double d = std::arg(z) * 180.0 / std::numbers::pi;
  if (d < 0.0) d += 360.0;
  return d;
}

std::string holes_text(const std::vector<HoleMass>& holes) {
  std::string s;
  for (std::size_t k = 0; k < holes.size(); ++k) {
    s += fmt::format("{}{} g @ {:.1f} deg", k ? " and " : "", significant(holes[k].mass_g, 4),
                     degrees(std::polar(1.0, holes[k].angle)));
  }
  return s;
}

std::string phasor_text(const PhasorInterval& z, const std::string& unit, double factor) {
  std::string s = significant(std::abs(z.value) * factor, 4);
  if (!unit.empty()) s += " " + unit;
  s += fmt::format(" @ {:.1f} deg", degrees(z.value));
  if (const auto r = z.radius()) {
    s += " (95%: +- " + significant(*r * factor, 2);
    if (!unit.empty()) s += " " + unit;
    s += ")";
  }
  return s;
}

namespace {

// Masses' angles back in the campaign's declared sense (inside Poise: against rotation).
void mirror(PhasorInterval& z) {
  z.value = std::conj(z.value);
  if (z.covariance) (*z.covariance)[1] = -(*z.covariance)[1];
}
void mirror(estimators::PlaneAnswers& u) {
  for (auto& z : u.planes) mirror(z);
  if (u.static_unbalance) mirror(*u.static_unbalance);
  if (u.couple_unbalance) mirror(*u.couple_unbalance);
}

// Each reading of the runs beside the calibration's model of it.
std::vector<ReadingPoint> reading_points(const std::vector<estimators::BalancingRun>& runs,
                                         const estimators::InfluenceCalibration& cal) {
  std::vector<ReadingPoint> out;
  for (const auto& r : runs) {
    for (std::size_t s = 0; s < r.readings.size(); ++s) {
      ReadingPoint p{r.name, s, r.readings[s], std::nullopt, r.check};
      if (r.masses) {
        Phasor m = cal.initial[s].value;
        for (std::size_t q = 0; q < cal.planes; ++q) m += cal.h[s][q].value * (*r.masses)[q];
        p.model = m;
      }
      out.push_back(p);
    }
  }
  return out;
}

CampaignAnalysis analyse_runs(const BalancingCampaign& c, const std::vector<estimators::BalancingRun>& runs,
                              std::optional<double> speed_rpm) {
  CampaignAnalysis a;
  a.speed_rpm = speed_rpm;
  a.calibration = estimators::calibrate(runs, c.planes.size(), c.reading_noise);
  a.correction = estimators::correction(a.calibration);
  const bool radii = std::all_of(c.plane_radius.begin(), c.plane_radius.end(), [](double r) { return r > 0.0; });
  a.moment_unit = radii ? "g mm" : "g";
  a.moment_factor = radii ? 1e3 : 1.0;  // g m -> g mm
  a.correction_masses = estimators::correction_answers(a.calibration, c.plane_radius);
  a.initial_unbalance = estimators::initial_unbalance_answers(a.calibration, c.plane_radius);
  a.residual_readings = estimators::residual_reading_answers(a.calibration);
  // As the instrument shows a reading: the probe's angle taken off, lead where it gives lead (the
  // regions are circles: only their centre moves).
  for (std::size_t s = 0; s < a.residual_readings.size(); ++s) {
    PhasorInterval z = a.residual_readings[s];
    z.value *= std::polar(1.0, s < c.sensor_angle.size() ? -c.sensor_angle[s] : 0.0);
    if (c.phase_lead) z.value = std::conj(z.value);
    a.residual_as_read.push_back(z);
  }
  a.runs = answers_of_unused_runs(runs, c, a);
  if (c.weights_with_rotation) {
    mirror(a.correction_masses);
    mirror(a.initial_unbalance);
    for (auto& r : a.runs) {
      mirror(r.unbalance);
      if (r.applied) {
        for (auto& m : *r.applied) m = std::conj(m);
      }
    }
  }
  a.model_tests = estimators::test_linear_model(runs, c.planes.size());
  a.points = reading_points(runs, a.calibration);
  for (std::size_t p = 0; p < c.planes.size(); ++p) {
    a.correction_holes.push_back(c.plane_holes[p] >= 2 ? split_onto_holes(a.correction_masses.planes[p].value,
                                                                          c.plane_holes[p], c.plane_first_hole[p])
                                                       : std::vector<HoleMass>{});
  }
  a.answer = answer_sentence(c, a);
  if (speed_rpm) a.answer = "At " + significant(*speed_rpm, 5) + " rpm: " + a.answer;
  return a;
}

// The runout test across the speeds and the cross-talk statement, on the balancing speed's
// analysis; a significant runout joins its answer.
void add_runout_test(CampaignAnalyses& out) {
  std::vector<estimators::InfluenceCalibration> calibrations;
  for (const auto& s : out.speeds) calibrations.push_back(s.calibration);
  CampaignAnalysis& first = out.speeds.front();
  first.model_tests.push_back(estimators::test_runout(calibrations));
  estimators::ModelTest crosstalk;
  crosstalk.name = "sensor cross-talk";
  crosstalk.needs =
      "a reading of each probe with the others disconnected, or a known shaker input: on a campaign's readings "
      "cross-talk is absorbed in the influence coefficients and the answers do not depend on it";
  first.model_tests.push_back(crosstalk);
  if (first.model_tests[first.model_tests.size() - 2].significant) {
    first.answer.pop_back();
    first.answer +=
        "; a runout that does not follow the masses is significant across the speeds (see the model tests).";
  }
}

}  // namespace

std::vector<HoleMass> split_onto_holes(const Phasor& w, int holes, double first) {
  const double pitch = 2.0 * std::numbers::pi / holes;
  double from_first = std::remainder(std::arg(w) - first, 2.0 * std::numbers::pi);
  if (from_first < 0.0) from_first += 2.0 * std::numbers::pi;
  const double k = std::floor(from_first / pitch);
  const double phi_a = first + k * pitch, phi_b = phi_a + pitch, theta = first + from_first;
  // The sine rule of the triangle w = m_a e^{i phi_a} + m_b e^{i phi_b}.
  const double m = std::abs(w), s = std::sin(pitch);
  const auto wrap = [](double a) { return std::remainder(a, 2.0 * std::numbers::pi); };
  return {{wrap(phi_a), m * std::sin(phi_b - theta) / s}, {wrap(phi_b), m * std::sin(theta - phi_a) / s}};
}

namespace {

// The design study's comparisons, in the balancing speed's answer.
void add_design(const BalancingCampaign& c, const DesignRunner& design, CampaignAnalyses& out) {
  if (!c.design || !design) return;
  DesignResult r = design(c, out.speeds.front());
  out.design = std::move(r.comparisons);
  out.calibration = std::move(r.calibration);
  std::string& answer = out.speeds.front().answer;
  answer.pop_back();  // its full stop
  std::size_t outside = 0, placed = 0;
  for (const auto& d : out.design) {
    if (!d.real) continue;
    ++placed;
    outside += d.within ? 0 : 1;
  }
  if (placed > 0) {
    answer += outside == 0 ? fmt::format(
                                 "; the machine behaves as its design study predicts ({} figure(s) within its "
                                 "simulated central 95%)",
                                 placed)
                           : fmt::format(
                                 "; {} of {} real figure(s) lie OUTSIDE the design study's simulated central "
                                 "95%: the machine does not behave as designed",
                                 outside, placed);
  }
  if (out.calibration) answer += "; " + out.calibration->sentence;
  answer += ".";
}

}  // namespace

CampaignAnalyses analyse_campaign(const BalancingCampaign& c, const DesignRunner& design) {
  if (c.sensors.size() < c.planes.size()) {
    throw Error(
        fmt::format("{} sensors cannot separate {} planes: each plane needs a sensor of its own (the "
                    "influence matrix is sensors x planes)",
                    c.sensors.size(), c.planes.size()));
  }
  CampaignAnalyses out;
  if (c.speeds_rpm.size() <= 1) {
    out.speeds.push_back(analyse_runs(c, c.runs, c.speeds_rpm.empty() ? std::nullopt : std::optional(c.speeds_rpm[0])));
    add_runout_test(out);
    add_design(c, design, out);
    return out;
  }
  // The balancing speed first: the declared one's group, else the highest.
  std::vector<double> order = c.speeds_rpm;
  std::size_t first = order.size() - 1;
  if (c.balancing_speed_rpm) {
    first = 0;
    for (std::size_t k = 0; k < order.size(); ++k) {
      if (std::abs(order[k] - *c.balancing_speed_rpm) < std::abs(order[first] - *c.balancing_speed_rpm)) first = k;
    }
  }
  std::rotate(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(first),
              order.begin() + static_cast<std::ptrdiff_t>(first) + 1);
  for (std::size_t k = 0; k < order.size(); ++k) {
    std::vector<estimators::BalancingRun> runs;
    for (const auto& r : c.runs) {
      if (r.speed_rpm && *r.speed_rpm == order[k]) runs.push_back(r);
    }
    try {
      out.speeds.push_back(analyse_runs(c, runs, order[k]));
    } catch (const Error& e) {
      if (k == 0) throw Error("at the balancing speed " + significant(order[k], 5) + " rpm: " + e.what());
      out.notes.push_back("at " + significant(order[k], 5) + " rpm, no calibration: " + e.what());
    }
  }
  add_runout_test(out);
  add_design(c, design, out);
  return out;
}

}  // namespace poise::balancing
