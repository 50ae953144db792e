#include "balancing/balance_report.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "balancing/iso_figures.h"
#include "core/error.h"
#include "core/format.h"
#include "engine/report/report_contents.h"
#include "engine/report/report_plot.h"
#include "engine/report/result_sections.h"
#include "engine/results/result_io.h"

namespace poise::balancing {
namespace {
namespace fs = std::filesystem;
using engine::html_escape;
using estimators::Phasor;
using estimators::PhasorInterval;

std::string cell(const PhasorInterval& z, const std::string& unit, double factor = 1.0) {
  return html_escape(phasor_text(z, unit, factor));
}

// The readings of each sensor (filled) and the calibration's model of them (open), joined by
// the residual, in the complex plane (lag, the probe's angle added); the rotor's own reading
// and the one predicted after the correction, with its 95% circle.
std::string readings_figure(const BalancingCampaign& c, const CampaignAnalysis& a, const fs::path& dir) {
  std::ostringstream data, plot, html;
  data.precision(9);
  for (std::size_t s = 0; s < c.sensors.size(); ++s) {
    data << "# " << c.sensors[s] << ": re im model_re model_im\n";
    for (const auto& p : a.points) {
      if (p.sensor != s) continue;
      const Phasor m = p.model.value_or(p.reading);
      data << p.reading.real() << ' ' << p.reading.imag() << ' ' << m.real() << ' ' << m.imag() << '\n';
    }
    data << "\n\n";
  }
  engine::write_file_atomic((dir / "readings.dat").string(), data.str());
  std::ostringstream after;
  after.precision(9);
  for (const auto& z : a.residual_readings) {
    after << z.value.real() << ' ' << z.value.imag() << ' ' << z.radius().value_or(0.0) << '\n';
  }
  engine::write_file_atomic((dir / "after.dat").string(), after.str());
  const std::string unit = c.amplitude_unit;
  // One square range about the origin for both parts: equal scales, ticks that do not crowd.
  double reach = 0.0;
  for (const auto& p : a.points) reach = std::max({reach, std::abs(p.reading), std::abs(p.model.value_or(p.reading))});
  for (const auto& z : a.residual_readings) reach = std::max(reach, std::abs(z.value) + z.radius().value_or(0.0));
  reach = reach > 0.0 ? 1.1 * reach : 1.0;
  plot << "set xrange [" << -reach << ":" << reach << "]\nset yrange [" << -reach << ":" << reach
       << "]\nset size ratio -1\nset xtics rotate by -45\nset key outside right\nset xlabel "
       << engine::gnuplot_quoted("real part [" + unit + "]") << "\nset ylabel "
       << engine::gnuplot_quoted("imaginary part [" + unit + "]")
       << "\nset title 'Readings (filled), the linear model a + H w (open), residuals (lines)'\nplot ";
  for (std::size_t s = 0; s < c.sensors.size(); ++s) {
    const int colour = static_cast<int>(s) + 1;
    plot << "'readings.dat' index " << s << " u 3:4:($1-$3):($2-$4) w vectors nohead lc " << colour << " notitle, "
         << "'readings.dat' index " << s << " u 1:2 w p pt 7 ps 0.8 lc " << colour << " t "
         << engine::gnuplot_quoted(c.sensors[s]) << ", 'readings.dat' index " << s << " u 3:4 w p pt 6 ps 1.2 lc "
         << colour << " notitle, ";
  }
  plot << "'after.dat' u 1:2:3 w circles lc rgb '#555555' dt 2 t 'after correction, 95%', "
          "'after.dat' u 1:2 w p pt 2 ps 1.2 lc rgb '#000000' notitle\n";
  std::vector<std::string> figures;
  if (engine::svg_plot(dir, "readings", plot.str(), figures, html)) {
    html << engine::inline_svg(dir / "readings.svg",
                               "Each sensor's readings and the model's: a long line is a reading the linear model "
                               "does not explain. Black crosses: the readings predicted after the correction, their "
                               "95% prediction circles dashed.");
  }
  return html.str();
}

// The vibration of each sensor as found and as predicted after the correction.
std::string before_after_html(const BalancingCampaign& c, const CampaignAnalysis& a, const fs::path& dir) {
  std::ostringstream h, data;
  h << "<h2 id='after'>Before and after the correction</h2>\n<table><tr><th class='l'>sensor</th><th>as found ["
    << html_escape(c.amplitude_unit) << "]</th><th>after the correction (95% prediction)</th></tr>\n";
  data << "# sensor before after upper95\n";
  for (std::size_t s = 0; s < c.sensors.size(); ++s) {
    const auto& z = a.residual_as_read[s];
    h << "<tr><td class='l'>" << html_escape(c.sensors[s]) << "</td><td>"
      << significant(std::abs(a.calibration.initial[s].value), 4) << "</td><td>" << cell(z, c.amplitude_unit)
      << "</td></tr>\n";
    data << s << ' ' << std::abs(a.calibration.initial[s].value) << ' ' << std::abs(z.value) << ' '
         << std::abs(z.value) + z.radius().value_or(0.0) << '\n';
  }
  h << "</table>\n";
  engine::write_file_atomic((dir / "after_bars.dat").string(), data.str());
  std::string xtics;
  for (std::size_t s = 0; s < c.sensors.size(); ++s) {
    xtics += (s ? ", " : "") + engine::gnuplot_quoted(c.sensors[s]) + " " + std::to_string(s);
  }
  const std::string plot = "set style fill solid 0.6\nset boxwidth 0.35\nset yrange [0:*]\nset xtics (" + xtics +
                           ")\nset ylabel " + engine::gnuplot_quoted("1X amplitude [" + c.amplitude_unit + "]") +
                           "\nset key below horizontal\nplot 'after_bars.dat' u ($1-0.2):2 w boxes lc rgb '#d62728' "
                           "t 'as found', 'after_bars.dat' u ($1+0.2):3 w boxes lc rgb '#1f77b4' t 'after the "
                           "correction (predicted)', 'after_bars.dat' u ($1+0.2):3:3:4 w yerrorbars lc rgb '#000000' "
                           "pt 0 t '95% upper end'\n";
  std::vector<std::string> figures;
  if (engine::svg_plot(dir, "after", plot, figures, h)) {
    h << engine::inline_svg(dir / "after.svg", "The vibration each sensor reads, as found and after the correction.");
  }
  return h.str();
}

std::string correction_html(const BalancingCampaign& c, const CampaignAnalysis& a) {
  std::ostringstream h;
  h << "<h2 id='correction'>Correction</h2>\n<table><tr><th class='l'>plane</th><th>mass at the plane's radius "
       "(95% region)</th><th class='l'>on its holes</th></tr>\n";
  for (std::size_t p = 0; p < c.planes.size(); ++p) {
    const std::string holes = holes_text(a.correction_holes[p]);
    h << "<tr><td class='l'>" << html_escape(c.planes[p]) << "</td><td>" << cell(a.correction_masses.planes[p], "g")
      << "</td><td class='l'>" << html_escape(holes.empty() ? "any angle" : holes) << "</td></tr>\n";
  }
  h << "</table>\n<p>Angles " << (c.weights_with_rotation ? "with" : "against")
    << " rotation from the reference mark, as the campaign declares; the trial masses removed. The 95% region is an "
       "ellipse in the complex plane; &plusmn; gives its largest half axis.</p>\n";
  return h.str();
}

std::string coefficients_html(const BalancingCampaign& c, const CampaignAnalysis& a) {
  const auto& cal = a.calibration;
  std::ostringstream h;
  h << "<h2 id='coefficients'>Influence coefficients</h2>\n<p>" << cal.runs << " readings of runs with known masses, "
    << cal.dof << " degrees of freedom per sensor; condition number of the influence matrix "
    << significant(cal.condition, 3)
    << (cal.condition > 100.0 ? " (the planes are hardly separable on these sensors)" : " (the planes separate)")
    << ".</p>\n<table><tr><th class='l'>sensor</th>";
  for (const auto& p : c.planes)
    h << "<th>from " << html_escape(p) << " [" << html_escape(c.amplitude_unit) << "/g]</th>";
  h << "</tr>\n";
  for (std::size_t s = 0; s < c.sensors.size(); ++s) {
    h << "<tr><td class='l'>" << html_escape(c.sensors[s]) << "</td>";
    for (std::size_t p = 0; p < c.planes.size(); ++p) {
      const auto& e = cal.h[s][p];
      h << "<td>" << html_escape(phasor_text({e.value, {}, 0.0, 0.95}, ""))
        << (e.se ? " (se " + significant(*e.se, 2) + ")" : std::string()) << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</table>\n";
  return h.str();
}

std::string plane_answers_row(const BalancingCampaign& c, const CampaignAnalysis& a, const std::string& what,
                              const estimators::PlaneAnswers& u) {
  std::string row = "<tr><td class='l'>" + html_escape(what) + "</td>";
  for (std::size_t p = 0; p < c.planes.size(); ++p) row += "<td>" + cell(u.planes[p], "g") + "</td>";
  if (u.static_unbalance) {
    row += "<td>" + cell(*u.static_unbalance, a.moment_unit, a.moment_factor) + "</td><td>" +
           cell(*u.couple_unbalance, a.moment_unit, a.moment_factor) + "</td>";
  }
  return row + "</tr>\n";
}

std::string unbalance_html(const BalancingCampaign& c, const CampaignAnalysis& a) {
  std::ostringstream h;
  h << "<h2 id='unbalance'>Unbalance</h2>\n<table><tr><th class='l'>rotor</th>";
  for (const auto& p : c.planes) h << "<th>" << html_escape(p) << "</th>";
  if (a.initial_unbalance.static_unbalance) h << "<th>static</th><th>couple</th>";
  h << "</tr>\n" << plane_answers_row(c, a, "as found (calibrated)", a.initial_unbalance);
  for (const auto& r : a.runs) {
    h << plane_answers_row(c, a, (r.check ? "check run '" : "run '") + r.name + "'", r.unbalance);
    if (!r.applied) continue;
    h << "<tr><td class='l'>&nbsp;&nbsp;applied</td>";
    for (std::size_t p = 0; p < c.planes.size(); ++p) {
      const auto& u = r.unbalance.planes[p];
      h << "<td>" << html_escape(phasor_text({(*r.applied)[p], {}, 0.0, 0.95}, "g"))
        << (u.radius() ? (u.contains((*r.applied)[p]) ? " <span class='ok'>within</span>"
                                                      : " <span class='bad'>outside</span>")
                       : std::string())
        << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</table>\n<p>Runs of unknown masses and check runs: the masses that explain their readings beyond the "
       "calibrated rotor's (least squares over the sensors), with 95% regions.</p>\n";
  return h.str();
}

std::string model_tests_html(const BalancingCampaign& c, const CampaignAnalysis& a) {
  std::ostringstream h;
  h << "<h2 id='tests'>Tests of the linear model</h2>\n<table><tr><th class='l'>test</th><th class='l'>result</th>"
       "<th>p</th><th>residual RMS before &rarr; after ["
    << html_escape(c.amplitude_unit)
    << "]</th><th>check runs before &rarr; after</th><th class='l'>finding, or what it needs</th></tr>\n";
  const auto num = [](const std::optional<double>& v) { return v ? significant(*v, 3) : std::string("&ndash;"); };
  for (const auto& t : a.model_tests) {
    h << "<tr><td class='l'>" << html_escape(t.name) << "</td><td class='l'>"
      << (!t.ran          ? "cannot be tested"
          : t.significant ? "<span class='bad'>significant</span>"
                          : "not significant")
      << "</td><td>" << num(t.p_value) << "</td><td>" << num(t.residual_before) << " &rarr; " << num(t.residual_after)
      << "</td><td>" << num(t.check_before) << " &rarr; " << num(t.check_after) << "</td><td class='l'>"
      << html_escape(t.ran ? (t.significant ? t.finding : std::string()) : "needs " + t.needs) << "</td></tr>\n";
  }
  h << "</table>\n<p>Each test adds terms to v = a + H w and asks, sensor by sensor, whether they lower the residual "
       "more than noise would (F tests, combined by Fisher's method; family level 0.01).</p>\n";
  return h.str();
}

std::string iso_html(const BalancingCampaign& c, const CampaignAnalysis& a) {
  const IsoFigures iso = iso_figures(c, a);
  if (iso.urr.empty() && iso.umar.empty()) return "";
  std::ostringstream h;
  const auto range = [](const std::optional<double>& lo, const std::optional<double>& hi, double scale) {
    return lo ? significant(*lo * scale, 3) + " to " + significant(*hi * scale, 3) : std::string("&ndash;");
  };
  h << "<h2 id='iso'>ISO 21940-21 figures</h2>\n<table><tr><th class='l'>figure</th><th>value</th><th>95% "
       "interval</th></tr>\n";
  for (const auto& f : iso.urr) {
    h << "<tr><td class='l'>URR, check run '" << html_escape(f.run) << "', " << html_escape(f.plane) << "</td><td>"
      << significant(100.0 * f.urr, 3) << "%</td><td>" << range(f.lower, f.upper, 100.0) << "%</td></tr>\n";
  }
  for (const auto& f : iso.umar) {
    h << "<tr><td class='l'>U_mar, " << html_escape(f.plane) << " (" << f.positions << " positions)</td><td>"
      << significant(f.umar, 3) << " " << html_escape(f.unit) << "</td><td>" << range(f.lower, f.upper, 1.0) << " "
      << html_escape(f.unit) << "</td></tr>\n";
  }
  h << "</table>\n<p>URR = 1 - |D - T| / |T| of each test mass T and its indication D; U_mar = half the spread of the "
       "indicated amounts over the U_mar test's positions, times the plane's radius. The intervals follow from the "
       "regions of D (conservative).</p>\n";
  return h.str();
}

// A model key fitted to the real coefficients: the sentence and each coefficient before and after.
std::string calibration_html(const DesignCalibration& d) {
  std::ostringstream h;
  h << "<h2 id='calibration'>Calibration of the design study</h2>\n<p>" << html_escape(d.sentence)
    << ". The study's mean |h| over its simulated machines against the real ones (" << d.evaluations
    << " runs of the study):</p>\n<table><tr><th class='l'>coefficient</th><th>real</th><th>study, before</th>"
       "<th>study, after</th></tr>\n";
  for (const auto& f : d.figures) {
    h << "<tr><th class='l'>plane " << html_escape(f.plane) << " at sensor " << html_escape(f.sensor) << "</th><td>"
      << significant(f.real, 4) << " &plusmn; " << significant(f.real_se, 2) << " " << html_escape(f.unit)
      << "</td><td>" << significant(f.before, 4) << "</td><td>" << significant(f.after, 4) << "</td></tr>\n";
  }
  h << "</table>\n";
  return h.str();
}

}  // namespace

std::string balance_report_html(const BalancingCampaign& c, const CampaignAnalyses& all, const fs::path& dir) {
  const CampaignAnalysis& a = all.speeds.front();
  std::ostringstream h;
  h << engine::report_page_head("Balancing campaign") << "<h1>Balancing campaign: " << html_escape(c.name) << "</h1>\n"
    << engine::answer_html(a.answer, nlohmann::json::array()) << "<p>Campaign file: " << html_escape(c.file)
    << (a.speed_rpm ? "; at " + significant(*a.speed_rpm, 5) + " rpm" : std::string()) << ".</p>\n"
    << correction_html(c, a) << "<h2 id='readings'>Readings and the fitted model</h2>\n"
    << readings_figure(c, a, dir) << before_after_html(c, a, dir) << coefficients_html(c, a) << unbalance_html(c, a)
    << iso_html(c, a) << model_tests_html(c, a);
  if (all.speeds.size() > 1) {
    h << "<h2 id='speeds'>Other speeds</h2>\n<ul>\n";
    for (std::size_t k = 1; k < all.speeds.size(); ++k) h << "<li>" << html_escape(all.speeds[k].answer) << "</li>\n";
    h << "</ul>\n";
  }
  if (!all.design.empty()) {
    h << "<h2 id='design'>The machine beside its design study</h2>\n<ul>\n";
    for (const auto& d : all.design) h << "<li>" << html_escape(d.sentence) << ".</li>\n";
    h << "</ul>\n";
  }
  if (all.calibration) h << calibration_html(*all.calibration);
  for (const auto& n : all.notes) h << "<p>Note: " << html_escape(n) << "</p>\n";
  h << "</body></html>\n";
  return engine::with_contents(h.str());
}

void write_balance_folder(const fs::path& dir, const BalancingCampaign& c, const CampaignAnalyses& a) {
  if (fs::exists(dir / "balance.json")) {
    throw UsageError(dir.string() + " already holds a campaign's analysis (balance.json): give another --out folder");
  }
  fs::create_directories(dir);
  engine::write_file_atomic((dir / "balance.json").string(), analysis_json(c, a).dump(2) + "\n");
  engine::write_file_atomic((dir / "report.html").string(), balance_report_html(c, a, dir));
}

}  // namespace poise::balancing
