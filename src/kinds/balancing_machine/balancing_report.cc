#include "kinds/balancing_machine/balancing_study.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/format.h"
#include "core/units.h"
#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"
#include "engine/run/procedure_runner.h"
#include "kinds/balancing_machine/balancing_sections.h"

namespace poise::kinds::balancing_machine {
using namespace poise::engine;
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

std::size_t index_of(const std::vector<std::string>& names, const std::string& name) {
  return static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
}

// Median and 5th / 95th percentiles of one output over the ok samples.
struct Band {
  double p05 = NAN, p50 = NAN, p95 = NAN;
};
Band band_of(std::vector<double> v) {
  Band b;
  if (v.empty()) return b;
  std::sort(v.begin(), v.end());
  auto q = [&](double p) { return v[static_cast<std::size_t>(std::lround(p * static_cast<double>(v.size() - 1)))]; };
  b.p05 = q(0.05);
  b.p50 = q(0.5);
  b.p95 = q(0.95);
  return b;
}

// The nominal machine (details(): nominal_machine, torsional_plate, hard_bearing) and the
// input warnings.
void machine_table(const json& d, const std::vector<std::string>& warnings, std::ostringstream& h) {
  const json& nm = d["nominal_machine"];
  const json& hb = d["hard_bearing"];
  h << "<h2>The machine (nominal)</h2>\n<table>"
    << "<tr><th class='l'>horizontal plates k5 (each)</th><td>" << significant(nm["k5_N_per_m"].get<double>())
    << " N/m</td></tr>"
    << "<tr><th class='l'>torsional plate k6, lever l, k6 l&sup2;</th><td>"
    << significant(nm["k6_N_per_m"].get<double>()) << " N/m, " << significant(nm["lever_m"].get<double>() * 1e3)
    << " mm, " << significant(nm["k6_l2_N_m_per_rad"].get<double>()) << " N m/rad</td></tr>"
    << "<tr><th class='l'>M, m, H, J (rotor R on)</th><td>" << significant(nm["total_mass_kg"].get<double>()) << " kg, "
    << significant(nm["rotating_mass_kg"].get<double>()) << " kg, "
    << significant(nm["mass_centre_height_m"].get<double>() * 1e3) << " mm, "
    << significant(nm["inertia_about_centre_kg_m2"].get<double>()) << " kg m&sup2;</td></tr>"
    << "<tr><th class='l'>natural frequencies (coupled)</th><td>" << significant(nm["omega_1_Hz"].get<double>())
    << " Hz, " << significant(nm["omega_2_Hz"].get<double>()) << " Hz (uncoupled "
    << significant(nm["omega_x_uncoupled_Hz"].get<double>()) << ", "
    << significant(nm["omega_theta_uncoupled_Hz"].get<double>()) << " Hz)</td></tr>"
    << "<tr><th class='l'>speed</th><td>" << significant(nm["speed_rpm"].get<double>())
    << " r/min = " << significant(nm["speed_Hz"].get<double>()) << " Hz</td></tr>"
    << "<tr><th class='l'>torsional plate end condition</th><td>"
    << d["torsional_plate"]["end_condition"].get<std::string>()
    << ": K<sub>rot</sub> = " << significant(d["torsional_plate"]["rotation_factor"].get<double>())
    << " k6 l&sup2;, sensor 2 reads " << significant(d["torsional_plate"]["sensor_2_force_factor"].get<double>())
    << " k6 l &theta;, clamp moment " << significant(100 * d["torsional_plate"]["clamp_moment_share"].get<double>(), 3)
    << "% of F l (L/l = " << significant(d["torsional_plate"]["length_over_lever"].get<double>(), 3) << ")</td></tr>"
    << "<tr><th class='l'>hard-bearing check</th><td>" << (hb["ok"].get<bool>() ? "passes" : "FAILS") << ": "
    << html_escape(hb["message"].get<std::string>()) << "</td></tr></table>\n";
  for (const auto& w : warnings) h << "<p><b>Warning</b>: " << html_escape(w) << "</p>\n";
}

// What every experiment's section reads and writes: the run's values, where its figures go,
// and the page.
struct SectionPage {
  const McResult& mc;
  const std::vector<std::string>& names;
  fs::path dir;
  bool plots;
  std::vector<std::string>& figures;
  std::ostringstream& h;
  /// The ok samples' values of output `n`.
  const std::vector<double>& values(const std::string& n) const { return mc.values[index_of(names, n)]; }
};

// Share of the machines passing: the mean of a 0 / 1 output (summed as v / n in sample order).
double pass_share(const std::vector<double>& v) {
  double pass = 0.0;
  for (double x : v) pass += x / static_cast<double>(v.size());
  return pass;
}

// Per position k, "x(k) p50 p05 p95" of NAME_p1_k<k><suffix>, then of plane 2 (gnuplot data).
template <class XOf>
std::string position_bands(const SectionPage& page, const BalancingExperiment& e, const std::string& suffix, XOf x_of) {
  std::ostringstream dat;
  for (int k = 0; k < e.positions; ++k) {
    dat << x_of(k);
    for (int p = 1; p <= 2; ++p) {
      const Band b = band_of(page.values(e.name + "_p" + std::to_string(p) + "_k" + std::to_string(k) + suffix));
      dat << ' ' << b.p50 << ' ' << b.p05 << ' ' << b.p95;
    }
    dat << '\n';
  }
  return dat.str();
}

// Separation of static and couple unbalance: each testing surface's effect on the two sensors.
void separation_section(const SectionPage& page, const BalancingExperiment& x, const BalancingModel& model) {
  std::ostringstream& h = page.h;
  h << "<h2>Separation of static and couple unbalance (" << html_escape(x.name) << ")</h2>\n"
    << "<p>" << significant(x.mass * 1e3) << " g at r = " << significant(x.radius * 1e3)
    << " mm on each testing surface in " << x.positions << " holes, " << significant(model.run.speed_rpm)
    << " r/min; effect on each sensor "
    << "(|A - A<sub>bare</sub>|, mean over the holes), median and 5-95% over the machines as built. "
    << "Sensor 1 should stay flat, sensor 2 grow in proportion to the height (the separation of the "
    << "model's Eq. 17, spring_plate_machine.h).</p>\n<table><tr><th>surface</th><th>height (mm)</th><th>sensor 1 "
       "(mN)</th><th>sensor 2 (mN)</th></tr>\n";
  std::ostringstream dat;
  for (int s = 1; s <= model.rotor.surfaces; ++s) {
    const std::string base = x.name + "_s" + std::to_string(s);
    const Band b1 = band_of(page.values(base + "_sensor1_mN")), b2 = band_of(page.values(base + "_sensor2_mN"));
    const double z = model.rotor.surface_height(s) * 1e3;
    h << "<tr><td>" << s << "</td><td>" << significant(z) << "</td><td>" << significant(b1.p50) << " <small>["
      << significant(b1.p05) << ", " << significant(b1.p95) << "]</small></td><td>" << significant(b2.p50)
      << " <small>[" << significant(b2.p05) << ", " << significant(b2.p95) << "]</small></td></tr>\n";
    dat << z << ' ' << b1.p50 << ' ' << b1.p05 << ' ' << b1.p95 << ' ' << b2.p50 << ' ' << b2.p05 << ' ' << b2.p95
        << '\n';
  }
  h << "</table>\n";
  if (page.plots) {
    write_file_atomic((page.dir / (x.name + "_sensors.dat")).string(), dat.str());
    svg_plot(page.dir, x.name + "_sensors",
             "set title 'Sensor signals against the height of the test mass'\nset xlabel 'height of the testing "
             "surface above the torsion shaft (mm)'\n"
             "set ylabel 'sensor amplitude (mN)'\nset key top left\nset xrange [0:*]\nset yrange [0:*]\n"
             "plot '" +
                 x.name +
                 "_sensors.dat' u 1:2:3:4 w yerrorlines lw 2 pt 7 title 'sensor 1 (horizontal)', '' u 1:5:6:7 w "
                 "yerrorlines lw 2 pt 5 title 'sensor 2 (torsional)'\n",
             page.figures, h);
  }
}

// U_mar: the readings against the test mass position in each correction plane.
void umar_section(const SectionPage& page, const BalancingExperiment& x, const BalancingSections& sections) {
  std::ostringstream& h = page.h;
  h << "<h2>Minimum achievable residual unbalance U<sub>mar</sub> (" << html_escape(x.name) << ")</h2>\n<p>"
    << significant(x.mass * 1e3) << " g at r = " << significant(x.radius * 1e3) << " mm in " << x.positions
    << " angular positions of each correction plane (surfaces " << sections.plane_1_surface << " and "
    << sections.plane_2_surface
    << "); U<sub>mar,p</sub> = (X<sub>max</sub> - X<sub>min</sub>) r / 2, U<sub>mar</sub> = "
       "U<sub>mar1</sub> + U<sub>mar2</sub> (Eq. 18: e = U<sub>mar1</sub>/M<sub>1</sub> = "
       "U<sub>mar2</sub>/M<sub>2</sub>, "
       "M<sub>1</sub> + M<sub>2</sub> = M<sub>R</sub>). The spread X<sub>max</sub> - X<sub>min</sub> is twice the "
       "rotor's own "
       "residual in that plane plus what the machine adds: compare U<sub>mar,p</sub> with the true residual.</p>\n";
  if (page.plots) {
    write_file_atomic((page.dir / (x.name + "_readings.dat")).string(),
                      position_bands(page, x, "_g", [&](int k) { return 360.0 * k / x.positions; }));
    svg_plot(page.dir, x.name + "_readings",
             "set title 'U_mar test: readings against the test mass position'\nset xlabel 'angular position of the "
             "test mass (deg)'\n"
             "set ylabel 'reading (g at the test radius)'\nset xtics 45\nset key outside bottom center horizontal\n"
             "plot '" +
                 x.name +
                 "_readings.dat' u 1:2:3:4 w yerrorlines lw 2 pt 7 title 'correction plane 1', '' u 1:5:6:7 w "
                 "yerrorlines lw 2 pt 5 title 'correction plane 2'\n",
             page.figures, h);
  }
}

// Stability of the readings: each plane's readings over their mean.
void stability_section(const SectionPage& page, const BalancingExperiment& x, const BalancingSections& sections) {
  std::ostringstream& h = page.h;
  const Band b1 = band_of(page.values(x.name + "_plane1_max_dev_pct")),
             b2 = band_of(page.values(x.name + "_plane2_max_dev_pct"));
  const double pass = pass_share(page.values(x.name + "_pass_ratio"));
  h << "<h2>Stability of the readings (" << html_escape(x.name) << "): "
    << (x.variant == "wang2014" ? "the test as Wang 2014 Sec. 5.2.2 prints it" : "Poise's variant, not in the paper")
    << "</h2>\n<p>" << significant(x.mass * 1e3) << " g at r = " << significant(x.radius * 1e3) << " mm on surface "
    << x.surface << " in " << x.positions << " holes"
    << (x.balance_first ? ", the rotor first balanced with the machine" : "")
    << "; each plane's readings divided by their mean must lie within &plusmn;" << significant(x.band * 100) << "%. "
    << "Largest deviation: plane 1 " << significant(b1.p50) << "% (p95 " << significant(b1.p95) << "%), plane 2 "
    << significant(b2.p50) << "% (p95 " << significant(b2.p95) << "%); " << significant(pass * 100, 3)
    << "% of the machines pass.</p>\n";
  if (x.surface == sections.plane_1_surface || x.surface == sections.plane_2_surface) {
    h << "<p><small>The test mass sits in a correction plane, so the other plane's readings are its "
         "residual unbalance and the machine's error alone: their ratio to their own mean measures noise, "
         "not stability. Put the test mass between or beyond the planes to test both.</small></p>\n";
  }
  if (page.plots) {
    write_file_atomic((page.dir / (x.name + "_ratios.dat")).string(),
                      position_bands(page, x, "_ratio", [](int k) { return k + 1.0; }));
    svg_plot(page.dir, x.name + "_ratios",
             "set title 'Stability test: reading / mean of the plane'\nset xlabel 'hole'\nset ylabel 'reading / mean'\n"
             "set xrange [0.5:" +
                 std::to_string(x.positions) +
                 ".5]\nset key outside bottom center horizontal\n"
                 "lo = " +
                 significant(1 - x.band) + "\nhi = " + significant(1 + x.band) +
                 "\n"
                 "plot lo w l dt 2 lc rgb 'red' title 'band', hi w l dt 2 lc rgb 'red' notitle, '" +
                 x.name +
                 "_ratios.dat' u 1:2:3:4 w yerrorlines lw 2 pt 7 title 'plane 1', '' u 1:5:6:7 w yerrorlines lw 2 pt 5 "
                 "title 'plane 2'\n",
             page.figures, h);
  }
}

// Unbalance reduction ratio, Poise's figure and ISO 21940-21's.
void urr_section(const SectionPage& page, const BalancingExperiment& x) {
  std::ostringstream& h = page.h;
  const Band b = band_of(page.values(x.name + "_min_pct"));
  const double pass = pass_share(page.values(x.name + "_pass_ratio"));
  h << "<h2>Unbalance reduction ratio (" << html_escape(x.name) << ")</h2>\n<p>" << significant(x.mass * 1e3)
    << " g at r = " << significant(x.radius * 1e3) << " mm in each correction plane (0 and 90 deg), one measuring run, "
    << "one correction with the placement tolerances. URR = 1 - |U after| / |U before| (true unbalances), the "
    << "smaller of the two planes: median " << significant(b.p50) << "%, 5% quantile " << significant(b.p05) << "%; "
    << significant(pass * 100, 3) << "% of the machines reach the required " << significant(x.requirement * 100) << "% "
    << "(<b>Poise's figure</b>: it charges the correction masses' placement errors to the machine).</p>\n";
  const Band bi = band_of(page.values(x.name + "_iso_min_pct"));
  const double pass_iso = pass_share(page.values(x.name + "_iso_pass_ratio"));
  h << "<p><b>ISO 21940-21's figure</b>: the indicated test unbalances (reading with the test masses minus the bare "
       "reading) against the known test masses, no correction: URR<sub>iso</sub> = 1 - |D - T| / |T|, the smaller "
       "plane: "
       "median "
    << significant(bi.p50) << "%, 5% quantile " << significant(bi.p05) << "%; " << significant(pass_iso * 100, 3)
    << "% of the machines reach " << significant(x.requirement * 100) << "%.</p>\n";
}

// Two-plane U_mar test, ISO 21940-21 style.
void umar_iso_section(const SectionPage& page, const BalancingExperiment& x) {
  std::ostringstream& h = page.h;
  const double pass = pass_share(page.values(x.name + "_pass_ratio"));
  const Band u1 = band_of(page.values(x.name + "_plane1_kgm")), u2 = band_of(page.values(x.name + "_plane2_kgm"));
  h << "<h2>Two-plane U<sub>mar</sub> test, ISO 21940-21 style (" << html_escape(x.name) << ")</h2>\n<p>"
    << significant(x.mass * 1e3) << " g at r = " << significant(x.radius * 1e3)
    << " mm in both correction planes at once (plane 2's " << significant(x.plane_2_offset / units::kRadPerDeg)
    << " deg from plane 1's), moved together through " << x.positions
    << " positions. U<sub>mar,p</sub> = (X<sub>max</sub> - X<sub>min</sub>) r / 2: plane 1 median "
    << significant(u1.p50 * 1e6) << " g mm, plane 2 " << significant(u2.p50 * 1e6)
    << " g mm; every reading within the mean &plusmn; the claimed " << significant(x.claim * 1e6)
    << " g mm: " << significant(pass * 100, 3) << "% of the machines.</p>\n";
}

// The machine's own influence coefficients (its calibration on rotor R): a table of their spread.
void calibration_section(const SectionPage& page, const BalancingExperiment& x) {
  std::ostringstream& h = page.h;
  h << "<h2>The machine's influence coefficients (" << html_escape(x.name) << ")</h2>\n<p>Each simulated machine "
    << "calibrated on rotor R as production machines are (a bare run, then the calibration mass in each plane): "
       "C = (A - A<sub>0</sub>) / (m r), the sensor force per unbalance at the nominal speed. A real machine's "
       "coefficients from its readings belong within these bands (<code>poise balance</code> with "
       "<code>[design]</code> places them).</p>\n<table><tr><th class='l'>coefficient</th><th>5%</th><th>median</th>"
       "<th>95%</th><th>phase, median</th></tr>\n";
  for (int s = 1; s <= 2; ++s) {
    for (int p = 1; p <= 2; ++p) {
      const std::string n = x.name + "_s" + std::to_string(s) + "_p" + std::to_string(p);
      const Band m = band_of(page.values(n + "_N_per_kgm")), a = band_of(page.values(n + "_deg"));
      h << "<tr><th class='l'>plane " << p << " at sensor " << s << "</th><td>" << significant(m.p05) << "</td><td>"
        << significant(m.p50) << "</td><td>" << significant(m.p95) << " N/(kg m)</td><td>" << significant(a.p50)
        << " deg</td></tr>\n";
    }
  }
  h << "</table>\n";
}

// Estimation error and couple interference: a histogram per error output.
void accuracy_section(const SectionPage& page, const BalancingExperiment& x, const std::vector<OutputSpec>& outputs) {
  std::ostringstream& h = page.h;
  h << "<h2>Estimation error and couple interference (" << html_escape(x.name) << ")</h2>\n<p>A test piece with "
    << significant(x.piece_unbalance * 1e6) << " g mm in each plane (random angles) and its mass centre "
    << "moved by the piece_centre_height tolerance, on the machine calibrated with rotor R. ic: influence "
       "coefficients (calibrated on the machine as built); cf: the corrected closed form with the design "
       "lever and speed (each sensor reads its own plate as built: the difference of the two horizontal "
       "plates reaches it, their common stiffness does not). Interference I<sub>s,c</sub>: static "
       "unbalance indicated per couple "
       "unbalance (1/mm), from a pure couple of "
    << significant(x.mass * 1e3) << " g at " << significant(x.radius * 1e3) << " mm in the two planes.</p>\n";
  if (page.plots) {
    for (const std::string o :
         {"_u_error_ic_gmm", "_u_error_cf_gmm", "_v_error_ic_gmm", "_v_error_cf_gmm", "_plane_error_ic_pct",
          "_plane_error_cf_pct", "_interference_ic_per_mm", "_interference_cf_per_mm"}) {
      const std::string n = x.name + o;
      {
        std::ostringstream dd;
        for (double v : page.values(n)) dd << v << '\n';
        write_file_atomic((page.dir / (n + ".dat")).string(), dd.str());
      }
      const std::string unit = output_unit_of(outputs, n);
      svg_plot(page.dir, n,
               "set title '" + n + "'\nset xlabel '" + unit + "'\nset ylabel 'machines'\nstats '" + n +
                   ".dat' u 1 nooutput\nnb = ceil(sqrt(STATS_records)); nb = (nb < 5 ? 5 : (nb > 25 ? 25 : nb))\n"
                   "bw = (STATS_max - STATS_min) / nb\nif (bw <= 0) bw = 1e-9\n"
                   "bin(x) = bw * floor(x / bw) + bw / 2\nset boxwidth bw absolute\nset yrange [0:*]\n"
                   "if (STATS_records <= 10) set ytics 1\n"  // whole machines, not 0.5
                   "set style fill solid 0.6\nplot '" +
                   n + ".dat' u (bin($1)):(1.0) smooth freq with boxes lc rgb '#4477aa' notitle\n",
               page.figures, h);
    }
  }
}

}  // namespace

json BalancingStudy::details(const McResult&) const {
  const BalancingAsBuilt b = nominal_as_built(model_);
  const models::SpringPlateMachineParams p = machine_params(model_, b, model_.rotor);
  const double omega = models::rpm_to_rad_per_s(model_.run.speed_rpm);
  const models::NaturalFrequencies nf = models::natural_frequencies(p);
  const models::HardBearingCheck hb = models::check_hard_bearing(p, omega, model_.hard_bearing_factor);
  const double weight = model_.rotor.mass * 9.80665;
  return {{"nominal_machine",
           {{"k5_N_per_m", p.horizontal_plate_stiffness},
            {"k6_N_per_m", p.torsional_plate_stiffness},
            {"k6_l2_N_m_per_rad", p.torsional_plate_stiffness * p.lever * p.lever},
            {"lever_m", p.lever},
            {"total_mass_kg", p.total_mass},
            {"rotating_mass_kg", p.rotating_mass},
            {"mass_centre_height_m", p.mass_centre_height},
            {"inertia_about_centre_kg_m2", p.inertia},
            {"damping_x_N_s_per_m", p.damping_x},
            {"damping_theta_N_m_s_per_rad", p.damping_theta},
            {"omega_1_Hz", nf.omega_1 / (2 * units::kPi)},
            {"omega_2_Hz", nf.omega_2 / (2 * units::kPi)},
            {"omega_x_uncoupled_Hz", nf.omega_x / (2 * units::kPi)},
            {"omega_theta_uncoupled_Hz", nf.omega_theta / (2 * units::kPi)},
            {"speed_rpm", model_.run.speed_rpm},
            {"speed_Hz", omega / (2 * units::kPi)},
            {"horizontal_plate_stress_per_N_Pa", models::guided_plate_max_stress(b.horizontal_1, 1.0)},
            {"rotor_weight_N", weight}}},
          {"hard_bearing",
           {{"ok", hb.ok},
            {"factor", model_.hard_bearing_factor},
            {"omega_1_over_omega", hb.ratio},
            {"deviation_from_limit", hb.deviation},
            {"message", hb.message}}},
          {"estimator_displayed", balancing_sections(config_).estimator},
          {"warnings", warnings_},
          {"torsional_plate",
           {{"end_condition", models::torsion_plate_end_name(model_.torsional_end)},
            {"rotation_factor", p.torsion_split.rotation_factor},
            {"sensor_2_force_factor", p.torsion_split.force_factor},
            {"clamp_moment_share", p.torsion_split.moment_share},
            {"length_over_lever", b.torsional.length / b.lever}}},
          {"correction_planes",
           {{"plane_1_surface", balancing_sections(config_).plane_1_surface},
            {"plane_1_height_m", model_.rotor.surface_height(balancing_sections(config_).plane_1_surface)},
            {"plane_2_surface", balancing_sections(config_).plane_2_surface},
            {"plane_2_height_m", model_.rotor.surface_height(balancing_sections(config_).plane_2_surface)}}}};
}

void BalancingStudy::report_sections(const McResult& mc, const std::string& plots_dir, bool plots,
                                     std::vector<std::string>& figures, std::ostringstream& h) const {
  machine_table(details(mc), warnings_, h);
  const SectionPage page{mc, output_names(), fs::path(plots_dir), plots, figures, h};
  const BalancingSections& sections = balancing_sections(config_);
  for (const auto& x : sections.experiments) {
    if (mc.outputs.empty()) break;
    if (x.type == "separation") {
      separation_section(page, x, model_);
    } else if (x.type == "umar") {
      umar_section(page, x, sections);
    } else if (x.type == "stability") {
      stability_section(page, x, sections);
    } else if (x.type == "urr") {
      urr_section(page, x);
    } else if (x.type == "umar_iso") {
      umar_iso_section(page, x);
    } else if (x.type == "accuracy") {
      accuracy_section(page, x, outputs());
    } else if (x.type == "calibration") {
      calibration_section(page, x);
    }
  }
}

}  // namespace poise::kinds::balancing_machine
