#include "optimize/optimization_plots.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"
#include "optimize/fresh_check.h"

namespace poise::optimize {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

/// The objective in words with its unit ("p95 of g_rmse_torque_mNm [mN*m]", "sum of the
/// variables [mm]").
std::string objective_label(const OptimizationSpec& spec) {
  const std::string unit = spec.objective_output.empty() ? (spec.variables.empty() ? "" : spec.variables[0].unit)
                                                         : output_unit(spec, spec.objective_output);
  const std::string what = spec.objective_output.empty() ? std::string("sum of the variables")
                                                         : spec.objective_statistic + " of " + spec.objective_output;
  return what + (unit.empty() ? "" : " [" + unit + "]");
}

/// plots/convergence.{dat,gp,svg}: every evaluation of every search and its best so far.
bool convergence_plot(const OptimizationSpec& spec, const OptimizationOutcome& out, const fs::path& pdir) {
  std::ostringstream d;
  for (const auto& run : out.runs) {
    double best = INFINITY;
    for (const auto& e : run.result.history) {
      if (e.feasible) best = std::min(best, e.result.objective);
      d << e.evaluation << ' ' << (e.result.ok ? e.result.objective : NAN) << ' ' << (e.feasible ? 1 : 0) << ' '
        << (std::isfinite(best) ? best : NAN) << '\n';
    }
    d << "\n\n";
  }
  engine::write_file_atomic((pdir / "convergence.dat").string(), d.str());
  std::ostringstream titles;
  for (std::size_t r = 0; r < out.runs.size(); ++r) {
    titles << (r ? " " : "") << '"' << choice_label(out.runs[r].choice) << '"';
  }
  std::ostringstream cgp;
  cgp << "set terminal svg size 720,420 dynamic noenhanced font 'Helvetica,12'\nset output 'convergence.svg'\n"
         "set grid\nset title 'Convergence'\nset xlabel 'evaluation'\nset ylabel '"
      << objective_label(spec) << "'\nset key outside bottom center horizontal\nlabels = '" << titles.str()
      << "'\n"
         "plot for [i=0:"
      << out.runs.size() - 1
      << "] 'convergence.dat' index i u 1:($3 > 0 ? $2 : 1/0) w p pt 7 title sprintf('feasible (%s)', word(labels, "
         "i+1)), "
         "for [i=0:"
      << out.runs.size() - 1
      << "] 'convergence.dat' index i u 1:($3 > 0 ? 1/0 : $2) w p pt 6 lc rgb 'gray' notitle, "
         "for [i=0:"
      << out.runs.size() - 1 << "] 'convergence.dat' index i u 1:4 w steps lw 2 notitle\n";
  engine::write_file_atomic((pdir / "convergence.gp").string(), cgp.str());
  std::string why;
  return engine::run_gnuplot((pdir / "convergence.gp").string(), &why);
}

/// plots/pareto.{dat,gp,svg}: the feasible evaluations, the front and its fresh-sample check.
bool pareto_plot(const OptimizationSpec& spec, const OptimizationOutcome& out, const fs::path& pdir) {
  std::ostringstream d2;
  for (const auto& q : out.pool) {
    if (q.feasible) d2 << q.second << ' ' << q.objective << ' ' << q.choice << '\n';
  }
  d2 << "\n\n";
  for (const auto& f : out.front_verification) {
    const json& o = f["objective"];
    const double v = o["value"].get<double>();
    d2 << f["second_optimization"].get<double>() << ' ' << v << ' ' << o.value("lo", v) << ' ' << o.value("hi", v)
       << ' ' << f["objective_optimization"].get<double>() << '\n';
  }
  engine::write_file_atomic((pdir / "pareto.dat").string(), d2.str());
  const std::string xl =
      spec.pareto->statistic + " of " + spec.pareto->output + " [" + output_unit(spec, spec.pareto->output) + "]";
  const std::string yl =
      spec.objective_statistic + " of " + spec.objective_output + " [" + output_unit(spec, spec.objective_output) + "]";
  std::ostringstream pgp;
  pgp << "set terminal svg size 760,480 dynamic noenhanced font 'Helvetica,12'\nset output 'pareto.svg'\n"
         "set grid\nset title 'Pareto front'\nset xlabel '"
      << xl << "'\nset ylabel '" << yl
      << "'\nset key outside bottom center horizontal\n"
         "plot 'pareto.dat' index 0 u 1:2:3 w p pt 7 ps 0.6 lc variable title 'feasible evaluations (colour: choice)', "
         "'pareto.dat' index 1 u 1:5 w lp pt 6 ps 1.2 lc rgb 'black' title 'front (optimization samples)', "
         "'pareto.dat' index 1 u 1:2:3:4 w yerrorbars pt 7 lc rgb 'red' title 'front on fresh samples, 95% CI'\n";
  engine::write_file_atomic((pdir / "pareto.gp").string(), pgp.str());
  std::string why;
  return engine::run_gnuplot((pdir / "pareto.gp").string(), &why);
}

}  // namespace

std::string objective_name(const OptimizationSpec& spec) {
  if (spec.objective_output.empty())
    return "objective_sum" + (spec.variables.empty() ? "" : "_" + spec.variables[0].unit);
  std::string stat = spec.objective_statistic;
  std::replace(stat.begin(), stat.end(), '.', '_');
  return "objective." + spec.objective_output + "." + stat;
}

std::vector<std::string> optimization_plots(const OptimizationSpec& spec, const OptimizationOutcome& out,
                                            const fs::path& pdir) {
  std::vector<std::string> figures;
  if (convergence_plot(spec, out, pdir)) figures.emplace_back("convergence.svg");
  if (spec.pareto && out.feasible && pareto_plot(spec, out, pdir)) figures.emplace_back("pareto.svg");
  return figures;
}

}  // namespace poise::optimize
