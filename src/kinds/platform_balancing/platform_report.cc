// The platform study's own report sections (PlatformStudy::report_sections, details).

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include "core/format.h"
#include "core/units.h"
#include "engine/kind_interface/study_evaluation.h"
#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"
#include "engine/run/procedure_runner.h"
#include "kinds/platform_balancing/platform_study.h"
#include "kinds/platform_balancing/platform_study_config.h"
#include "sampling/random_stream.h"
#include "sampling/statistics.h"

namespace poise::kinds::platform_balancing {
using namespace poise::engine;
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

// Pairs a platform sample with a unit of the shafting study: an independent draw.
constexpr std::uint64_t kPairingStream = 0x1F0;

struct Quantiles {
  double p50 = NAN, p95 = NAN, p9973 = NAN;
};
Quantiles quantiles(std::vector<double> v) {
  Quantiles q;
  if (v.empty()) return q;
  q.p50 = sampling::quantile_value(v, 0.5);
  q.p95 = sampling::quantile_value(v, 0.95);
  q.p9973 = sampling::quantile_value(v, 0.9973);
  return q;
}
json quantiles_json(const Quantiles& q) { return {{"p50", q.p50}, {"p95", q.p95}, {"p99_73", q.p9973}}; }

const std::vector<double>& values_of(const McResult& mc, const std::vector<std::string>& names, const std::string& n) {
  static const std::vector<double> kEmpty;
  const auto it = std::find(names.begin(), names.end(), n);
  const auto k = static_cast<std::size_t>(it - names.begin());
  return it == names.end() || k >= mc.values.size() ? kEmpty : mc.values[k];
}

// What the unbalance LOS lines rest on: the loop, stated with its derived figures.
std::string loop_statement(models::StabilizationLoop l) {
  l.inertia = 1.0;  // the gains scale with J; poles and crossover do not
  std::ostringstream os;
  if (l.type == models::LoopType::kRatePi) {
    os << "PI rate loop, true open-loop crossover " << significant(l.frequency_hz) << " Hz, integral ratio "
       << significant(l.integral_ratio) << " (no integral of the angle: a held torque leaves a held error)";
  } else {
    os << "PID position loop with integrator, PD natural frequency " << significant(l.frequency_hz)
       << " Hz (K_p = J w_n^2; "
       << "open-loop crossover " << significant(l.crossover_hz()) << " Hz), zeta " << significant(l.damping)
       << ", integral ratio " << significant(l.integral_ratio);
  }
  return os.str();
}

// Quantiles of each axis' residual outputs, before balancing and after each test order.
json residual_by_order_json(const McResult& mc, const std::vector<std::string>& names, const PlatformStudySection& ps) {
  json res;
  for (models::Axis a : models::kAllAxes) {
    const std::string ax = models::axis_name(a);
    res[ax]["initial_torque_max_mNm"] =
        quantiles_json(quantiles(values_of(mc, names, "initial_" + ax + "_torque_max_mNm")));
    for (const auto& l : ps.order_labels) {
      for (const char* o : {"residual_gmm", "residual_grid_max_gmm", "torque_max_mNm", "torque_rms_mNm",
                            "torque_max_acc_mNm", "torque_rms_acc_mNm"}) {
        res[ax][l][o] = quantiles_json(quantiles(values_of(mc, names, l + "_" + ax + "_" + o)));
      }
    }
  }
  return res;
}

// The platform's gimbals, their loop and the test campaign's set-up.
void platform_table(const json& d, const PlatformStudySection& ps, std::ostringstream& h) {
  h << "<h2>The platform and its test campaign</h2>\n<table><tr><th class='l'>gimbal (axis)</th><th>mass (kg)</th>"
       "<th>inertia about the axis, outboard (kg m&sup2;)</th><th>K<sub>T</sub> (N m/A)</th><th>counterweight R / "
       "plane h (mm)</th>"
       "<th>stabilization: least disturbance stiffness (N m/rad)</th></tr>\n";
  for (const auto& g : d["gimbals"]) {
    h << "<tr><td class='l'>" << g["axis"].get<std::string>() << "</td><td>" << significant(g["mass_kg"].get<double>())
      << "</td><td>" << significant(g["axis_inertia_kg_m2"].get<double>()) << "</td><td>"
      << significant(g["kt_nominal_N_m_per_A"].get<double>()) << "</td><td>"
      << significant(g["counterweight_radius_m"].get<double>() * 1e3) << " / "
      << significant(g["counterweight_plane_m"].get<double>() * 1e3) << "</td><td>"
      << significant(g["loop_min_stiffness_N_m_per_rad"].get<double>()) << "</td></tr>\n";
  }
  h << "</table>\n";
  if (!d["gimbals"].empty()) {
    const json& loop = d["gimbals"][0]["loop"];
    h << "<p>Stabilization loop: " << html_escape(d["loop_statement"].get<std::string>())
      << ". Closed-loop poles (Hz, the "
         "same on every axis: the gains scale with its inertia):";
    for (const auto& pole : loop["closed_loop_poles_Hz"]) {
      h << " " << significant(pole[0].get<double>()) << (pole[1].get<double>() < 0 ? " - " : " + ")
        << significant(std::abs(pole[1].get<double>())) << "j";
    }
    h << "; least disturbance stiffness at " << significant(loop["least_stiffness_at_Hz"].get<double>())
      << " Hz.</p>\n";
  }
  h << "<p>Each axis test is the complete simulated single-axis procedure (" << ps.positions
    << " turntable positions, servo-driven oscillation integrated with CVODE, sampled current, Eq. 21, Eq. 22 fit, Eq. "
       "23 "
       "counterweight with its placement tolerances in the gimbal's correction plane) on the assembly that turns about "
       "the axis, the other gimbals locked with their locking errors. Residual torque: the exact statics on a grid of "
    << d["grid"]["points"].get<std::size_t>() << " gimbal angles (outer "
    << significant(d["grid"]["outer_deg"][0].get<double>()) << " to "
    << significant(d["grid"]["outer_deg"][1].get<double>()) << " deg, middle "
    << significant(d["grid"]["middle_deg"][0].get<double>()) << " to "
    << significant(d["grid"]["middle_deg"][1].get<double>()) << " deg, inner "
    << significant(d["grid"]["inner_deg"][0].get<double>()) << " to "
    << significant(d["grid"]["inner_deg"][1].get<double>())
    << " deg), under gravity and under gravity plus the stated carrier "
       "acceleration ("
    << significant(ps.acceleration[0]) << ", " << significant(ps.acceleration[1]) << ", "
    << significant(ps.acceleration[2]) << ") m/s&sup2; in the base frame.</p>\n";
}

// Residual torques per axis and order.
void residual_table(const json& d, const PlatformStudySection& ps, std::ostringstream& h) {
  h << "<h2>Residual unbalance torque per axis and test order</h2>\n<table><tr><th class='l'>axis</th><th "
       "class='l'>order</th>"
       "<th>residual S<sub>&perp;</sub> p50 / p95 (g mm), lock angles | greatest over the grid</th><th>max over grid, "
       "gravity: p50 / p95 / p99.73 (mN m)</th>"
       "<th>RMS over grid, gravity p50 (mN m)</th><th>max, gravity + acceleration: p50 / p95 / p99.73 (mN "
       "m)</th></tr>\n";
  for (models::Axis a : models::kAllAxes) {
    const std::string ax = models::axis_name(a);
    const json& r = d["residual_by_order"][ax];
    const json& ini = r["initial_torque_max_mNm"];
    h << "<tr><td class='l'>" << ax << "</td><td class='l'>before balancing</td><td></td><td>"
      << significant(ini["p50"].get<double>()) << " / " << significant(ini["p95"].get<double>()) << " / "
      << significant(ini["p99_73"].get<double>()) << "</td><td></td><td></td></tr>\n";
    for (std::size_t o = 0; o < ps.order_labels.size(); ++o) {
      const json& x = r[ps.order_labels[o]];
      h << "<tr><td class='l'>" << ax << "</td><td class='l'>" << html_escape(ps.order_texts[o]) << "</td><td>"
        << significant(x["residual_gmm"]["p50"].get<double>()) << " / "
        << significant(x["residual_gmm"]["p95"].get<double>()) << " | "
        << significant(x["residual_grid_max_gmm"]["p50"].get<double>()) << " / "
        << significant(x["residual_grid_max_gmm"]["p95"].get<double>()) << "</td><td>"
        << significant(x["torque_max_mNm"]["p50"].get<double>()) << " / "
        << significant(x["torque_max_mNm"]["p95"].get<double>()) << " / "
        << significant(x["torque_max_mNm"]["p99_73"].get<double>()) << "</td><td>"
        << significant(x["torque_rms_mNm"]["p50"].get<double>()) << "</td><td>"
        << significant(x["torque_max_acc_mNm"]["p50"].get<double>()) << " / "
        << significant(x["torque_max_acc_mNm"]["p95"].get<double>()) << " / "
        << significant(x["torque_max_acc_mNm"]["p99_73"].get<double>()) << "</td></tr>\n";
    }
  }
  h << "</table>\n<p><small>Why the order matters: an axis test sees only the part of the outboard first moment "
       "perpendicular to its axis, with the carried gimbals at their lock angles. Testing outer or middle before the "
       "gimbals they carry balances them against an unbalance that later moves (the inner gimbal's x/z offset turns "
       "with "
       "gamma) or is changed afterwards (the later counterweights, and their offsets along their own axes), so they "
       "end "
       "unbalanced over the range of angles. Inside to outside, each counterweight's side effects land on axes still "
       "to "
       "be tested.</small></p>\n";
}

// Per axis, the distribution of the residual torque under gravity + acceleration per order.
void residual_plots(const McResult& mc, const std::vector<std::string>& names, const PlatformStudySection& ps,
                    const fs::path& dir, std::vector<std::string>& figures, std::ostringstream& h) {
  for (models::Axis a : models::kAllAxes) {
    const std::string ax = models::axis_name(a), name = "residual_" + ax;
    std::string cmd = "set title 'Residual torque on the " + ax +
                      " axis: max over the angle grid, gravity + acceleration'\n"
                      "set xlabel 'residual torque (mN m)'\nset ylabel 'fraction of platforms'\nset logscale x\n"
                      "set key bottom right\nset yrange [0:1]\nplot ";
    for (std::size_t o = 0; o < ps.order_labels.size(); ++o) {
      std::vector<double> v = values_of(mc, names, ps.order_labels[o] + "_" + ax + "_torque_max_acc_mNm");
      std::sort(v.begin(), v.end());
      const std::string file = name + "_" + ps.order_labels[o] + ".dat";
      std::ostringstream f;
      for (std::size_t j = 0; j < v.size(); ++j)
        f << v[j] << ' ' << (static_cast<double>(j) + 0.5) / static_cast<double>(v.size()) << '\n';
      write_file_atomic((dir / file).string(), f.str());
      cmd += std::string(o ? ", " : "") + "'" + file + "' u 1:2 w l lw 2 title '" + ps.order_texts[o] + "'";
    }
    svg_plot(dir, name, cmd + "\n", figures, h);
  }
}

// The combined LOS budget table with its assumptions.
void los_budget_table(const json& d, const PlatformStudySection& ps, std::ostringstream& h) {
  const double px = d["pixel_arcsec"].get<double>();
  h << "<h2>Combined LOS budget (pairing assumption)</h2>\n<p><b>Assumptions.</b> "
    << html_escape(d["los_budget_assumptions"]["pairing"].get<std::string>()) << ". The unbalance lines "
    << html_escape(d["los_budget_assumptions"]["loop"].get<std::string>()) << ".</p>\n"
    << "<p>Residual unbalance torque c<sub>k</sub>&middot;(g - a(t)) on each axis through "
       "its stabilization loop (on the outboard inertia; a loop with a position integrator takes out the constant "
       "gravity "
       "part, a rate loop holds the error c<sub>k</sub>&middot;g / K<sub>p</sub>), LOS error |&delta;&omega; &times; "
       "d| at each grid point over a profile of "
    << significant(ps.duration) << " s: a manoeuvre (" << significant(ps.manoeuvre[0]) << ", "
    << significant(ps.manoeuvre[1]) << ", " << significant(ps.manoeuvre[2]) << ") m/s&sup2; from "
    << significant(ps.onset) << " s over " << significant(ps.rise_time) << " s, and " << ps.vibration.size()
    << " vibration line(s). The gimbals hold their angles during the profile. Temporal: over the profile of one unit; "
       "ensemble: over the units (samples).</p>\n<table><tr><th class='l'>line</th><th "
       "class='l'>nature</th><th>p50</th>"
       "<th>p95</th><th>p99.73 (arcsec)</th>"
    << (px > 0 ? "<th>p99.73 (px)</th>" : "") << "</tr>\n";
  for (const auto& l : d["los_budget"]) {
    const json& q = l["arcsec"];
    auto cell = [&](const char* k) { return q.contains(k) ? significant(q[k].get<double>()) : std::string(""); };
    h << "<tr><td class='l'>" << html_escape(l["line"].get<std::string>()) << "</td><td class='l'>"
      << html_escape(l["nature"].get<std::string>()) << "</td><td>" << cell("p50") << "</td><td>" << cell("p95")
      << "</td><td>" << cell("p99_73") << "</td>";
    if (px > 0) h << "<td>" << significant(q["p99_73"].get<double>() / px) << "</td>";
    h << "</tr>\n";
  }
  h << "</table>\n";
  if (ps.shafting_study.empty())
    h << "<p><small>No [platform.shafting] study: the budget has no shafting line.</small></p>\n";
}

}  // namespace

// Per gimbal: its mass properties, counterweight and stabilization loop.
json PlatformStudy::gimbals_json() const {
  const PlatformStudySection& ps = platform_sections(config_).platform;
  json gimbals = json::array();
  for (models::Axis a : models::kAllAxes) {
    const auto ia = static_cast<std::size_t>(a);
    const PlatformGimbal& g = model_.gimbal(a);
    json lines = json::array();
    for (const auto& v : ps.vibration) {
      lines.push_back({{"frequency_Hz", v.frequency},
                       {"stiffness_N_m_per_rad", loops_[ia].disturbance_stiffness(2 * units::kPi * v.frequency)}});
    }
    const models::StabilizationLoop& loop = loops_[ia];
    json poles = json::array();
    for (const auto& p : loop.closed_loop_poles())
      poles.push_back({p.real() / (2 * units::kPi), p.imag() / (2 * units::kPi)});
    const auto [k_min, f_min] = loop.least_disturbance_stiffness();
    gimbals.push_back({{"axis", models::axis_name(a)},
                       {"mass_kg", g.mass},
                       {"axis_inertia_kg_m2", axis_inertia_[ia]},
                       {"kt_nominal_N_m_per_A", g.kt_nominal},
                       {"counterweight_radius_m", g.counterweight_radius},
                       {"counterweight_plane_m", g.counterweight_plane},
                       {"lock_angle_deg", g.lock_angle / units::kRadPerDeg},
                       {"loop",
                        {{"type", models::loop_type_name(loop.type)},
                         {"K_p_N_m_per_rad", loop.kp()},
                         {"K_d_N_m_s_per_rad", loop.kd()},
                         {"K_i_N_m_per_rad_s", loop.ki()},
                         {"closed_loop_poles_Hz", poles},
                         {"crossover_Hz", loop.crossover_hz()},
                         {"least_stiffness_at_Hz", f_min}}},
                       {"loop_min_stiffness_N_m_per_rad", k_min},
                       {"loop_stiffness_at_vibration_lines", lines}});
  }
  return gimbals;
}

// The combined LOS budget lines (reference order = the first): shafting, unbalance peak and
// RMS, and each platform paired with shafting units.
json PlatformStudy::los_budget_json(const McResult& mc) const {
  const PlatformStudySection& ps = platform_sections(config_).platform;
  const auto& names = output_names();
  json budget = json::array();
  const std::string ref = ps.order_labels.empty() ? "" : ps.order_labels[0];
  const std::vector<double>& peak = values_of(mc, names, ref + "_los_max_arcsec");
  const std::vector<double>& rms = values_of(mc, names, ref + "_los_rms_arcsec");
  Quantiles qs;
  if (!shafting_sorted_.empty()) {
    qs = quantiles(shafting_sorted_);
    budget.push_back(
        {{"line",
          "shafting geometric error of the seeker study " + ps.shafting_study +
              " (exact chain), greatest over the field of regard. PAIRING ASSUMPTION: that seeker's shafting and pixel "
              "are paired with this platform by the study file; neither paper measured them together"},
         {"nature", "ensemble over units; static (a function of the gimbal angles, no time)"},
         {"samples", shafting_sorted_.size()},
         {"arcsec", quantiles_json(qs)}});
  }
  const Quantiles qp = quantiles(peak), qr = quantiles(rms);
  const std::string loop_dep = "; depends on the loop type: " + loop_statement(model_.stabilization);
  budget.push_back(
      {{"line", "residual unbalance under the carrier profile: peak over the profile, worst grid point (order " + ref +
                    ")" + loop_dep},
       {"nature", "temporal peak per unit; ensemble over units"},
       {"samples", peak.size()},
       {"arcsec", quantiles_json(qp)}});
  budget.push_back(
      {{"line", "residual unbalance under the carrier profile: RMS over the profile, worst grid point (order " + ref +
                    ")" + loop_dep},
       {"nature", "temporal RMS per unit; ensemble over units"},
       {"samples", rms.size()},
       {"arcsec", quantiles_json(qr)}});
  if (!shafting_sorted_.empty() && !peak.empty()) {
    // Each platform unit paired with K independent shafting units (K ~ the shafting count
    // over the platform count), so the combined tails rest on as many pairs as the larger study.
    const std::size_t k_pairs = std::max<std::size_t>(1, shafting_sorted_.size() / peak.size());
    std::vector<double> lin, rss;
    lin.reserve(peak.size() * k_pairs);
    rss.reserve(peak.size() * k_pairs);
    for (std::size_t j = 0; j < peak.size(); ++j) {
      sampling::RandomStream rs(seed_, static_cast<sampling::StreamId>(kPairingStream), j);
      for (std::size_t m = 0; m < k_pairs; ++m) {
        const double s = shafting_sorted_[rs.next_bits() % shafting_sorted_.size()];
        lin.push_back(s + peak[j]);
        rss.push_back(std::hypot(s, peak[j]));
      }
    }
    const std::string pairing = " [pairing assumption: this platform with the shafting of " + ps.shafting_study +
                                "; the unbalance part depends on the loop type]";
    budget.push_back(
        {{"line", "combined per unit: shafting + unbalance peak, added linearly (each platform paired with " +
                      std::to_string(k_pairs) + " random shafting units)" + pairing},
         {"nature", "ensemble over units of (static + temporal peak); upper bound on the instantaneous error"},
         {"samples", lin.size()},
         {"arcsec", quantiles_json(quantiles(lin))}});
    budget.push_back({{"line", "combined per unit: root sum of squares of shafting and unbalance peak" + pairing},
                      {"nature", "ensemble over units; the two errors as perpendicular on the sky"},
                      {"samples", rss.size()},
                      {"arcsec", quantiles_json(quantiles(rss))}});
    budget.push_back({{"line", "p99.73 lines stacked: shafting p99.73 + unbalance peak p99.73" + pairing},
                      {"nature", "worst-case stacking of two ensemble p99.73s (conservative)"},
                      {"arcsec", {{"p99_73", qs.p9973 + qp.p9973}}}});
  }
  return budget;
}

json PlatformStudy::details(const McResult& mc) const {
  json d;
  const PlatformStudySection& ps = platform_sections(config_).platform;
  d["gimbals"] = gimbals_json();
  d["loop_statement"] = loop_statement(model_.stabilization);
  d["grid"] = {{"outer_deg", {ps.outer_min / units::kRadPerDeg, ps.outer_max / units::kRadPerDeg, ps.outer_points}},
               {"middle_deg", {ps.middle_min / units::kRadPerDeg, ps.middle_max / units::kRadPerDeg, ps.middle_points}},
               {"inner_deg", {ps.inner_min / units::kRadPerDeg, ps.inner_max / units::kRadPerDeg, ps.inner_points}},
               {"points", grid_.size()}};
  d["stated_acceleration_m_s2"] = ps.acceleration;
  d["orders"] = json::array();
  for (std::size_t o = 0; o < ps.orders.size(); ++o)
    d["orders"].push_back({{"label", ps.order_labels[o]}, {"order", ps.order_texts[o]}});
  d["residual_by_order"] = residual_by_order_json(mc, output_names(), ps);
  // The combined LOS budget (reference order = the first).
  d["los_budget"] = los_budget_json(mc);
  d["los_budget_assumptions"] = {
      {"loop", "the unbalance lines hold for this loop only: " + loop_statement(model_.stabilization) +
                   "; another loop type gives other figures for the same residual unbalance"},
      {"pairing", ps.shafting_study.empty()
                      ? "no shafting study: no combined lines"
                      : "the combined lines pair this platform with the seeker shafting of " + ps.shafting_study +
                            " (the study's assumption, not a measured assembly)"}};
  d["pixel_arcsec"] = pixel_arcsec_;
  return d;
}

void PlatformStudy::report_sections(const McResult& mc, const std::string& plots_dir, bool plots,
                                    std::vector<std::string>& figures, std::ostringstream& h) const {
  const json d = details(mc);
  const PlatformStudySection& ps = platform_sections(config_).platform;
  platform_table(d, ps, h);
  residual_table(d, ps, h);
  if (plots && !mc.values.empty()) residual_plots(mc, output_names(), ps, fs::path(plots_dir), figures, h);
  los_budget_table(d, ps, h);
}

}  // namespace poise::kinds::platform_balancing
