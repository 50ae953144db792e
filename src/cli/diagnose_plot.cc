// The figure of `poise diagnose --out DIR`: plot.dat, plot.gp and plot.svg (gnuplot). The
// report page that shows it: engine/report/diagnosis_page.cc.
#include <algorithm>
#include <numeric>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "cli/diagnose_output.h"
#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"

namespace poise::cli::diagnose_detail {
namespace fs = std::filesystem;
namespace est = poise::estimators;
using nlohmann::json;

// plot.dat, plot.gp and (if gnuplot runs) plot.svg; returns the note for the report.
std::string write_plot(const fs::path& dir, const est::TorqueTable& t, const est::DiagnosisResult& r) {
  std::vector<std::size_t> idx(t.size());
  std::iota(idx.begin(), idx.end(), std::size_t{0});
  std::stable_sort(idx.begin(), idx.end(), [&](auto a, auto b) { return t.theta_deg[a] < t.theta_deg[b]; });
  std::ostringstream dat;
  dat << "# theta_deg measured fitted_before fitted_after residual_before residual_after (" << t.unit << ")\n";
  dat.precision(10);
  for (std::size_t i : idx) {
    dat << t.theta_deg[i] << ' ' << t.torque[i] << ' ' << r.fitted_before[i] << ' ' << r.fitted_after[i] << ' '
        << r.residual_before[i] << ' ' << r.residual_after[i] << '\n';
  }
  engine::write_file_atomic((dir / "plot.dat").string(), dat.str());
  // The residuals in measurement order (time_s, or the file's row order without it), where a
  // drift, a step or a period in time shows.
  const bool timed = t.time_s.size() == t.size();
  std::vector<std::size_t> in_time(t.size());
  std::iota(in_time.begin(), in_time.end(), std::size_t{0});
  if (timed) {
    std::stable_sort(in_time.begin(), in_time.end(), [&](auto a, auto c) { return t.time_s[a] < t.time_s[c]; });
  }
  std::ostringstream dat_time;
  dat_time << "# " << (timed ? "time_s" : "row") << " residual_before residual_after (" << t.unit << ")\n";
  dat_time.precision(10);
  for (std::size_t k = 0; k < in_time.size(); ++k) {
    const std::size_t i = in_time[k];
    dat_time << (timed ? t.time_s[i] : static_cast<double>(k + 1)) << ' ' << r.residual_before[i] << ' '
             << r.residual_after[i] << '\n';
  }
  engine::write_file_atomic((dir / "plot_time.dat").string(), dat_time.str());
  const auto& b = r.estimate_before;
  std::ostringstream gp;
  gp.precision(12);
  gp << "set terminal svg size 900,1080 noenhanced font 'Helvetica,12' background rgb 'white'\n"
     << "set output 'plot.svg'\nset samples 721\nset grid\nset autoscale xfix\nset key below "
        "horizontal\n"
     << "set multiplot layout 3,1 title 'Residual diagnosis of " << fs::path(t.file).filename().string() << "'\n"
     << "set xlabel 'turntable angle theta [deg]'\nset ylabel 'torque [" << t.unit << "]'\n"
     << "A = " << b.amplitude << "; B = " << b.phase << "; K = " << b.offset << "\n"
     << "plot 'plot.dat' u 1:2 w p pt 7 ps 0.7 lc rgb '#000000' t 'measured', \\\n"
     << "  A*sin(x*pi/180 + B) + K w l lw 2 lc rgb '#1f77b4' t 'base fit (Eq. 22)', \\\n"
     << "  'plot.dat' u 1:4 w p pt 6 ps 1.0 lc rgb '#d62728' t 'final model'\n"
     << "set ylabel 'residual [" << t.unit << "]'\n"
     << "plot 'plot.dat' u 1:5 w lp pt 7 ps 0.6 lc rgb '#1f77b4' t 'base fit residual', \\\n"
     << "  'plot.dat' u 1:6 w lp pt 6 ps 0.8 lc rgb '#d62728' t 'final model residual', \\\n"
     << "  0 w l lc rgb '#808080' notitle\n"
     << "set xlabel '" << (timed ? "time of the measurement [s]" : "measurement order [row]") << "'\n"
     << "plot 'plot_time.dat' u 1:2 w lp pt 7 ps 0.6 lc rgb '#1f77b4' t 'base fit residual', \\\n"
     << "  'plot_time.dat' u 1:3 w lp pt 6 ps 0.8 lc rgb '#d62728' t 'final model residual', \\\n"
     << "  0 w l lc rgb '#808080' notitle\nunset multiplot\n";
  engine::write_file_atomic((dir / "plot.gp").string(), gp.str());
  std::string why;
  if (engine::run_gnuplot((dir / "plot.gp").string(), &why) && fs::exists(dir / "plot.svg")) {
    return "";
  }
  if (why.empty()) why = "gnuplot wrote no plot.svg";
  return why + " (run gnuplot plot.gp in this folder to retry).";
}

}  // namespace poise::cli::diagnose_detail
